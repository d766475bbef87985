#include "lodforge/pack/preset.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"
#include "lodforge/io/input_file.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace lodforge {

using nlohmann::ordered_json;

bool operator==(const SimplifyWeights& a, const SimplifyWeights& b) {
    return a.normal == b.normal && a.color == b.color && a.texcoord == b.texcoord &&
           a.texcoord_sets == b.texcoord_sets;
}

std::vector<LodTarget> lod_targets_from_ratios(const std::vector<double>& ratios) {
    std::vector<LodTarget> out;
    out.reserve(ratios.size());
    for (double r : ratios) out.push_back(LodTarget{.kind = LodTarget::Kind::ratio, .value = r});
    return out;
}

namespace {

constexpr std::array<std::pair<LodMethod, std::string_view>, 5> method_names{{
    {LodMethod::collapse, "collapse"},
    {LodMethod::cluster, "cluster"},
    {LodMethod::octree, "octree"},
    {LodMethod::lodstrips, "lodstrips"},
    {LodMethod::mcoctree, "mcoctree"},
}};

constexpr std::array<std::pair<Placement, std::string_view>, 2> placement_names{{
    {Placement::optimal, "optimal"},
    {Placement::half_edge, "half-edge"},
}};

// The value of `name` in `names`, or Error(argument) naming `what` and the accepted names.
template <typename T, std::size_t N>
T from_name(const std::array<std::pair<T, std::string_view>, N>& names, std::string_view name, const char* what) {
    std::string accepted;
    for (auto [value, n] : names) {
        if (n == name) return value;
        accepted += accepted.empty() ? std::string(n) : ", " + std::string(n);
    }
    throw_error(Error::Kind::argument, "", std::string("unknown ") + what + " '" + std::string(name) +
                                               "' (accepted: " + accepted + ")");
}

constexpr std::array<std::pair<LodTarget::Kind, std::string_view>, 3> target_names{{
    {LodTarget::Kind::ratio, "ratio"},
    {LodTarget::Kind::triangles, "triangles"},
    {LodTarget::Kind::error, "error"},
}};

// Reads a JSON object key by key, so that every key it does not know is reported as an error.
class ObjectReader {
public:
    ObjectReader(const ordered_json& object, std::string path, const std::string& source)
        : object_(object), path_(std::move(path)), source_(source) {
        if (!object_.is_object()) fail(path_, "must be a JSON object");
    }

    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw_error(Error::Kind::argument, source_, "preset key '" + key + "' " + what);
    }

    std::string key_path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

    const ordered_json* find(const std::string& key) {
        seen_.insert(key);
        auto it = object_.find(key);
        return it == object_.end() ? nullptr : &*it;
    }

    double number(const std::string& key, double value, double min, double max) {
        if (const auto* j = find(key)) {
            if (!j->is_number()) fail(key_path(key), "must be a number");
            value = j->get<double>();
            if (!std::isfinite(value) || value < min || value > max) {
                std::ostringstream range;
                range << "must be between " << min << " and " << max << " (got " << j->dump() << ")";
                fail(key_path(key), range.str());
            }
        }
        return value;
    }

    std::uint32_t count(const std::string& key, std::uint32_t value, std::uint32_t min, std::uint32_t max) {
        if (const auto* j = find(key)) {
            if (!j->is_number_integer() || j->get<long long>() < min || j->get<long long>() > max)
                fail(key_path(key), "must be an integer between " + std::to_string(min) + " and " +
                                        std::to_string(max) + " (got " + j->dump() + ")");
            value = static_cast<std::uint32_t>(j->get<long long>());
        }
        return value;
    }

    bool flag(const std::string& key, bool value) {
        if (const auto* j = find(key)) {
            if (!j->is_boolean()) fail(key_path(key), "must be true or false");
            value = j->get<bool>();
        }
        return value;
    }

    std::string text(const std::string& key, std::string value) {
        if (const auto* j = find(key)) {
            if (!j->is_string()) fail(key_path(key), "must be a string");
            value = j->get<std::string>();
        }
        return value;
    }

    // A string naming one of an enum's values; `from_string` throws Error listing the accepted names.
    template <typename T>
    T name(const std::string& key, T value, T (*from_string)(std::string_view)) {
        if (const auto* j = find(key)) {
            if (!j->is_string()) fail(key_path(key), "must be a string");
            try {
                value = from_string(j->get<std::string>());
            } catch (const Error& e) {
                fail(key_path(key), e.what());
            }
        }
        return value;
    }

    // Call after reading every known key.
    void finish() const {
        for (auto it = object_.begin(); it != object_.end(); ++it)
            if (!seen_.count(it.key())) fail(key_path(it.key()), "is not a known preset option");
    }

    const std::string& source() const { return source_; }

private:
    const ordered_json& object_;
    std::string path_;
    const std::string& source_;
    std::set<std::string> seen_;
};

LodTarget parse_target(const ordered_json& j, std::size_t index, const std::string& source) {
    const std::string where = "levels[" + std::to_string(index) + "]";
    ObjectReader r(j, where, source);
    LodTarget target;
    int kinds = 0;
    for (auto [kind, name] : target_names) {
        const std::string key(name);
        if (!j.contains(key)) continue;
        ++kinds;
        target.kind = kind;
        switch (kind) {
        case LodTarget::Kind::ratio: target.value = r.number(key, 1.0, 1e-9, 0.9999); break;  // 1 would copy level 0
        case LodTarget::Kind::triangles: target.value = r.count(key, 1, 1, 0xffffffffu); break;
        case LodTarget::Kind::error: target.value = r.number(key, 1e-3, 1e-12, 1.0); break;
        }
    }
    if (kinds != 1) r.fail(where, "must have exactly one of \"ratio\", \"triangles\" or \"error\"");
    r.finish();
    return target;
}

}  // namespace

std::string_view to_string(LodMethod method) {
    for (auto [m, name] : method_names)
        if (m == method) return name;
    return "collapse";
}

LodMethod lod_method_from_string(std::string_view name) { return from_name(method_names, name, "LOD method"); }

std::string_view to_string(Placement placement) {
    for (auto [p, name] : placement_names)
        if (p == placement) return name;
    return "optimal";
}

Placement placement_from_string(std::string_view name) { return from_name(placement_names, name, "placement"); }

Preset parse_preset(std::string_view json_text, const std::string& source) {
    ordered_json root;
    try {
        root = ordered_json::parse(json_text.begin(), json_text.end());
    } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a 400-digit number
        throw_error(Error::Kind::format, source, std::string("not valid JSON: ") + e.what());
    }
    Preset p;
    ObjectReader r(root, "", source);
    const auto version = r.count("version", preset_format_version, 1, 0xffffffffu);
    if (version > static_cast<std::uint32_t>(preset_format_version))
        r.fail("version", "is " + std::to_string(version) + "; this LodForge reads presets up to version " +
                              std::to_string(preset_format_version));
    p.name = r.text("name", p.name);
    p.method = r.name("method", p.method, lod_method_from_string);
    if (const auto* levels = r.find("levels"); levels && levels->is_string()) {
        if (levels->get<std::string>() != "auto") r.fail("levels", "must be a non-empty array or \"auto\"");
        p.auto_levels = true;
    } else if (levels) {
        if (!levels->is_array() || levels->empty()) r.fail("levels", "must be a non-empty array or \"auto\"");
        // Each level is a full simplification of the input: a thousand of them ran for minutes.
        if (levels->size() > kMaxPresetLevels)
            r.fail("levels", "has " + std::to_string(levels->size()) + " levels; at most " +
                                 std::to_string(kMaxPresetLevels) + " are allowed");
        p.levels.clear();
        for (std::size_t i = 0; i < levels->size(); ++i) p.levels.push_back(parse_target((*levels)[i], i, source));
    }
    if (const auto* w = r.find("weights")) {
        ObjectReader wr(*w, "weights", source);
        p.weights.normal = static_cast<float>(wr.number("normal", p.weights.normal, 0, 1e6));
        p.weights.color = static_cast<float>(wr.number("color", p.weights.color, 0, 1e6));
        p.weights.texcoord = static_cast<float>(wr.number("uv", p.weights.texcoord, 0, 1e6));
        if (const auto* sets = wr.find("uv_sets")) {
            if (!sets->is_array()) wr.fail("weights.uv_sets", "must be an array of numbers");
            p.weights.texcoord_sets.clear();
            for (const auto& v : *sets) {
                if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0)
                    wr.fail("weights.uv_sets", "must hold finite numbers >= 0");
                p.weights.texcoord_sets.push_back(v.get<float>());
            }
        }
        wr.finish();
    }
    p.min_screen_pixels = r.number("min_screen_pixels", p.min_screen_pixels, 1, 1e5);
    if (const auto* o = r.find("switch")) {
        ObjectReader sr(*o, "switch", source);
        SwitchParams& sw = p.switching;
        sw.pixels = sr.number("pixels", sw.pixels, 0.01, 1e4);
        if (const auto* screen = sr.find("screen")) {
            if (!screen->is_array() || screen->size() != 2 || !(*screen)[0].is_number_integer() ||
                !(*screen)[1].is_number_integer() || (*screen)[0].get<long long>() < 1 ||
                (*screen)[1].get<long long>() < 1 || (*screen)[0].get<long long>() > 65536 ||
                (*screen)[1].get<long long>() > 65536)
                sr.fail("switch.screen", "must be [width, height] in whole pixels from 1 to 65536 (got " +
                                             screen->dump() + ")");
            sw.width = (*screen)[0].get<std::uint32_t>();
            sw.height = (*screen)[1].get<std::uint32_t>();
        }
        sw.fov_deg = sr.number("fov_deg", sw.fov_deg, 1, 179);
        sw.hysteresis = sr.number("hysteresis", sw.hysteresis, 0, 0.99);
        sr.finish();
    }
    p.lock_border = r.flag("lock_border", p.lock_border);
    p.importance = r.text("importance", p.importance);
    p.lock = r.text("lock", p.lock);
    p.seams = r.text("seams", p.seams);
    p.placement = r.name("placement", p.placement, placement_from_string);
    if (const auto* o = r.find("octree")) {
        ObjectReader orr(*o, "octree", source);
        p.octree.max_triangles_per_node =
            orr.count("max_triangles_per_node", p.octree.max_triangles_per_node, 16, 100'000'000);
        p.octree.max_depth = orr.count("max_depth", p.octree.max_depth, 1, 21);
        p.octree.memory_mb = orr.count("memory_mb", p.octree.memory_mb, 16, 1'048'576);
        orr.finish();
    }
    if (const auto* o = r.find("mcoctree")) {
        ObjectReader mr(*o, "mcoctree", source);
        p.mcoctree.resolution = mr.count("resolution", p.mcoctree.resolution, 4, 4096);
        mr.finish();
    }
    if (const auto* o = r.find("strips")) {
        ObjectReader sr(*o, "strips", source);
        p.strips.primitive_restart = sr.flag("primitive_restart", p.strips.primitive_restart);
        sr.finish();
    }
    if (const auto* o = r.find("skin")) {
        ObjectReader kr(*o, "skin", source);
        if (const auto* m = kr.find("max_influences")) {
            if (!m->is_array() || m->empty()) kr.fail("skin.max_influences", "must be a non-empty array of counts");
            p.skin.max_influences.clear();
            for (const auto& v : *m) {
                if (!v.is_number_integer() || v.get<std::int64_t>() < 1 || v.get<std::int64_t>() > 8)
                    kr.fail("skin.max_influences", "must hold whole numbers from 1 to 8");
                p.skin.max_influences.push_back(v.get<std::uint32_t>());
            }
        }
        p.skin.pose_samples = kr.count("pose_samples", p.skin.pose_samples, 0, 64);
        p.skin.weight = kr.number("weight", p.skin.weight, 0, 100);
        kr.finish();
    }
    if (const auto* o = r.find("export")) {
        ObjectReader er(*o, "export", source);
        p.exports.glb = er.flag("glb", p.exports.glb);
        p.exports.ply = er.flag("ply", p.exports.ply);
        p.exports.obj = er.flag("obj", p.exports.obj);
        p.exports.lodstrips = er.flag("lodstrips", p.exports.lodstrips);
        p.exports.image_error = er.flag("image_error", p.exports.image_error);
        er.finish();
    }
    r.finish();
    if (p.exports.lodstrips && p.method != LodMethod::lodstrips)
        r.fail("export.lodstrips", "needs \"method\": \"lodstrips\"");
    return p;
}

std::string preset_to_json(const Preset& p) {
    ordered_json j;
    j["version"] = preset_format_version;
    j["name"] = p.name;
    j["method"] = std::string(to_string(p.method));
    j["levels"] = ordered_json::array();
    for (const auto& t : p.auto_levels ? std::vector<LodTarget>{} : p.levels) {
        ordered_json level;
        for (auto [kind, name] : target_names)
            if (kind == t.kind) {
                if (kind == LodTarget::Kind::triangles)
                    level[std::string(name)] = static_cast<std::uint64_t>(t.value);
                else
                    level[std::string(name)] = t.value;
            }
        j["levels"].push_back(level);
    }
    if (p.auto_levels) j["levels"] = "auto";
    j["min_screen_pixels"] = p.min_screen_pixels;
    j["switch"] = {{"pixels", p.switching.pixels},
                   {"screen", {p.switching.width, p.switching.height}},
                   {"fov_deg", p.switching.fov_deg},
                   {"hysteresis", p.switching.hysteresis}};
    j["weights"] = {{"normal", p.weights.normal}, {"color", p.weights.color}, {"uv", p.weights.texcoord}};
    if (!p.weights.texcoord_sets.empty()) j["weights"]["uv_sets"] = p.weights.texcoord_sets;
    j["lock_border"] = p.lock_border;
    // Paint is written only when set: presets without it stay as they were.
    if (!p.importance.empty()) j["importance"] = p.importance;
    if (!p.lock.empty()) j["lock"] = p.lock;
    if (!p.seams.empty()) j["seams"] = p.seams;
    j["placement"] = std::string(to_string(p.placement));
    j["octree"] = {{"max_triangles_per_node", p.octree.max_triangles_per_node},
                   {"max_depth", p.octree.max_depth},
                   {"memory_mb", p.octree.memory_mb}};
    j["mcoctree"] = {{"resolution", p.mcoctree.resolution}};
    j["strips"] = {{"primitive_restart", p.strips.primitive_restart}};
    j["skin"] = {{"max_influences", p.skin.max_influences},
                 {"pose_samples", p.skin.pose_samples},
                 {"weight", p.skin.weight}};
    j["export"] = {{"glb", p.exports.glb}, {"ply", p.exports.ply}, {"obj", p.exports.obj},
                   {"lodstrips", p.exports.lodstrips}, {"image_error", p.exports.image_error}};
    return j.dump(2) + "\n";
}

Preset load_preset(const std::string& path) {
    return parse_preset(read_input_text(path, "a preset file"), path);
}

void save_preset(const std::string& path, const Preset& preset) {
    AtomicFile file(path, false);
    file.stream() << preset_to_json(preset);
    file.commit();
}

}  // namespace lodforge
