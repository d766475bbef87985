#include "io/gltf_json_check.h"

#include "lodforge/error.h"

#include <nlohmann/json.hpp>

#include <string_view>
#include <vector>

namespace lodforge {
namespace {

// The unsigned integer members of the glTF 2.0 schema that tinygltf would read as 0 when negative.
bool is_unsigned_member(std::string_view key) {
    return key == "byteOffset" || key == "byteLength" || key == "byteStride" || key == "count";
}

// SAX handler: nlohmann's sax_parse is iterative, so depth is bounded here before any recursion.
// Members are checked only under the top-level "accessors" and "bufferViews", outside "extras" and
// "extensions" (whose content is the author's, not the schema's).
class Checker : public nlohmann::json::json_sax_t {
public:
    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t v) override {
        return v < 0 ? bad("is negative (" + std::to_string(v) + ")") : value();
    }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t& text) override { return bad("is not an integer (" + text + ")"); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override { return open(); }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override { return open(); }
    bool end_array() override { return close(); }
    bool key(string_t& k) override {
        key_ = k;
        return true;
    }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::json::exception& e) override {
        error_ = "not valid JSON at byte " + std::to_string(position) + " (" + e.what() + ")";
        return false;
    }
    const std::string& error() const { return error_; }

private:
    bool value() {
        key_.clear();
        return true;
    }
    bool bad(const std::string& what) {
        if (checked_.empty() || !checked_.back() || !is_unsigned_member(key_)) return value();
        error_ = "'" + key_ + "' " + what + "; it must be a non-negative integer";
        return false;
    }
    bool open() {
        if (checked_.size() >= static_cast<std::size_t>(kGltfMaxJsonDepth)) {
            error_ = "JSON nested deeper than " + std::to_string(kGltfMaxJsonDepth) + " levels";
            return false;
        }
        bool child = false;
        if (checked_.size() == 1) child = key_ == "accessors" || key_ == "bufferViews";
        else if (checked_.size() > 1) child = checked_.back() && key_ != "extras" && key_ != "extensions";
        checked_.push_back(child);
        key_.clear();
        return true;
    }
    bool close() {
        checked_.pop_back();
        key_.clear();
        return true;
    }
    std::vector<bool> checked_;  // per open container: are its unsigned members checked
    std::string key_;
    std::string error_;
};

}  // namespace

void check_gltf_json(const std::string& path, const char* json, std::size_t size) {
    Checker checker;
    const bool ok = nlohmann::json::sax_parse(json, json + size, &checker, nlohmann::json::input_format_t::json,
                                              /*strict=*/false);
    if (!ok) throw_error(Error::Kind::format, path, "cannot parse glTF: " + checker.error());
}

}  // namespace lodforge
