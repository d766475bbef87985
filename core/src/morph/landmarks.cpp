// Landmark files for the two-mesh supermesh (docs/morph.md, case (b)). The format is JSON so artists can
// write or fix one by hand; indices are checked here, once, for the CLI and the studio alike.
#include "lodforge/morph/landmarks.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"
#include "lodforge/io/input_file.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <unordered_set>

namespace lodforge {

namespace {

constexpr const char* k_format = "lodforge-landmarks";
constexpr int k_version = 1;

std::uint32_t index_of(const nlohmann::json& value, const std::string& path, std::size_t pair, const char* side)
{
    if (!value.is_number_integer() || value.get<long long>() < 0 ||
        value.get<long long>() > static_cast<long long>(UINT32_MAX)) {
        throw_error(Error::Kind::format, path,
                    "landmark pair " + std::to_string(pair) + ": vertex " + side +
                        " is not a non-negative integer index");
    }
    return static_cast<std::uint32_t>(value.get<long long>());
}

}  // namespace

Landmarks read_landmarks(const std::string& path)
{
    check_input_file(path, "a landmark file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_error(Error::Kind::io, path, "cannot open landmark file");
    std::stringstream text;
    text << in.rdbuf();
    nlohmann::json doc = nlohmann::json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
    if (doc.is_discarded()) throw_error(Error::Kind::format, path, "not valid JSON");
    // Every member's type is checked before it is read: nlohmann's value() and get() throw their own
    // type_error on a member of another type (`"format": 1`), which named neither the file nor the entry.
    const auto format = doc.is_object() ? doc.find("format") : doc.end();
    if (format == doc.end() || !format->is_string() || format->get_ref<const std::string&>() != k_format) {
        throw_error(Error::Kind::format, path, std::string("not a landmark file (\"format\" must be \"") +
                                                   k_format + "\")");
    }
    // Compared as a JSON number, not through get<int>(), which would wrap 4294967297 to 1.
    if (!doc.contains("version") || !doc["version"].is_number_integer() || doc["version"] != k_version) {
        throw_error(Error::Kind::format, path, "unsupported landmark file version (this build reads version 1)");
    }
    if (!doc.contains("pairs") || !doc["pairs"].is_array()) {
        throw_error(Error::Kind::format, path, "\"pairs\" must be an array of [a, b] vertex index pairs");
    }
    Landmarks result;
    const auto& pairs = doc["pairs"];
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const auto& p = pairs[i];
        if (!p.is_array() || p.size() != 2) {
            throw_error(Error::Kind::format, path,
                        "landmark pair " + std::to_string(i) + " is not two vertex indices [a, b]");
        }
        result.pairs.push_back({index_of(p[0], path, i, "a"), index_of(p[1], path, i, "b")});
    }
    return result;
}

void write_landmarks(const Landmarks& landmarks, const std::string& path)
{
    nlohmann::ordered_json doc;
    doc["format"] = k_format;
    doc["version"] = k_version;
    nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
    for (const auto& p : landmarks.pairs) pairs.push_back({p.a, p.b});
    doc["pairs"] = std::move(pairs);
    AtomicFile file(path, /*binary=*/false);
    file.stream() << doc.dump(2) << '\n';
    file.commit();
}

void check_landmarks(const Landmarks& landmarks, std::size_t a_vertex_count, std::size_t b_vertex_count,
                     const std::string& source)
{
    std::unordered_set<std::uint32_t> seen_a, seen_b;
    for (std::size_t i = 0; i < landmarks.pairs.size(); ++i) {
        const auto& p = landmarks.pairs[i];
        const std::string which = "landmark pair " + std::to_string(i) + " ";
        if (p.a >= a_vertex_count) {
            throw_error(Error::Kind::invalid, source,
                        which + "names vertex " + std::to_string(p.a) + " of mesh A, which has " +
                            std::to_string(a_vertex_count) + " vertices");
        }
        if (p.b >= b_vertex_count) {
            throw_error(Error::Kind::invalid, source,
                        which + "names vertex " + std::to_string(p.b) + " of mesh B, which has " +
                            std::to_string(b_vertex_count) + " vertices");
        }
        if (!seen_a.insert(p.a).second) {
            throw_error(Error::Kind::invalid, source, which + "repeats vertex " + std::to_string(p.a) + " of mesh A");
        }
        if (!seen_b.insert(p.b).second) {
            throw_error(Error::Kind::invalid, source, which + "repeats vertex " + std::to_string(p.b) + " of mesh B");
        }
    }
}

}  // namespace lodforge
