#include "simplify_options.h"

#include "lodforge/error.h"
#include "lodforge/pack/preset_library.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace lodforge::cli {
namespace {

std::vector<std::string> split(const std::string& text, char sep) {
    std::vector<std::string> parts;
    std::stringstream in(text);
    std::string part;
    while (std::getline(in, part, sep)) parts.push_back(part);
    if (!text.empty() && text.back() == sep) parts.emplace_back();
    return parts;
}

double parse_number(const std::string& text, const std::string& what) {
    const char* begin = text.c_str();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (text.empty() || end != begin + text.size() || !std::isfinite(v))
        throw Error(Error::Kind::argument, what + ": '" + text + "' is not a number");
    return v;
}

}  // namespace

// `uvN` (or `texcoordN`) sets texcoord set N's weight; sets before N without their own entry keep the
// plain `uv` weight, whichever order the items come in.
void parse_weights(const std::string& text, SimplifyWeights& weights) {
    const char* names = " (names: normal, color, uv, uv0, uv1, ...)";
    std::vector<std::pair<std::size_t, float>> per_set;
    for (const std::string& item : split(text, ',')) {
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos)
            throw Error(Error::Kind::argument, "--weights: expected name=value, got '" + item + "'" + names);
        const std::string name = item.substr(0, eq);
        const double v = parse_number(item.substr(eq + 1), "--weights " + name);
        if (v < 0) throw Error(Error::Kind::argument, "--weights " + name + ": must be >= 0");
        std::string digits;
        if (name.size() > 2 && name.compare(0, 2, "uv") == 0) digits = name.substr(2);
        else if (name.size() > 8 && name.compare(0, 8, "texcoord") == 0) digits = name.substr(8);
        if (name == "normal") weights.normal = static_cast<float>(v);
        else if (name == "color" || name == "colour") weights.color = static_cast<float>(v);
        else if (name == "uv" || name == "texcoord") weights.texcoord = static_cast<float>(v);
        else if (!digits.empty() && digits.size() <= 2 && digits.find_first_not_of("0123456789") == std::string::npos)
            per_set.emplace_back(std::stoul(digits), static_cast<float>(v));
        else
            throw Error(Error::Kind::argument, "--weights: unknown attribute '" + name + "'" + names);
    }
    std::size_t sets = weights.texcoord_sets.size();
    for (const auto& [set, w] : per_set) sets = std::max(sets, set + 1);
    weights.texcoord_sets.resize(sets, weights.texcoord);
    for (const auto& [set, w] : per_set) weights.texcoord_sets[set] = w;
}

std::vector<double> parse_number_list(const std::string& text, const std::string& option) {
    std::vector<double> values;
    for (const std::string& item : split(text, ',')) values.push_back(parse_number(item, option));
    if (values.empty()) throw Error(Error::Kind::argument, option + ": give at least one value");
    return values;
}

CLI::Option* add_preset_option(CLI::App* cmd, std::string& value) {
    return cmd->add_option("--preset", value,
                           "Preset: a shipped name (mobile, console, web, scan-archive) or a JSON file "
                           "(docs/presets.md); flags given here override its keys");
}

CLI::Option* add_placement_option(CLI::App* cmd, std::string& value) {
    return cmd
        ->add_option("--placement", value,
                     "Collapse levels: optimal (the default; each level has its own vertices, moved to the "
                     "quadric optimum) or half-edge (input vertices, one vertex buffer shared by all levels)")
        ->check(CLI::IsMember({"optimal", "half-edge"}));
}

std::optional<Preset> preset_from_option(const std::string& value) {
    if (value.empty()) return std::nullopt;
    try {
        return resolve_preset(value);
    } catch (const Error& e) {
        // An unknown shipped name is a usage error (2); a bad value inside a preset file is that file's
        // problem (1), like any other input file's.
        const bool file = value.find('/') != std::string::npos ||
                          (value.size() >= 5 && value.compare(value.size() - 5, 5, ".json") == 0);
        if (e.kind() != Error::Kind::argument || !file) throw;
        throw Error(Error::Kind::format, e.what());
    }
}

std::vector<LodTarget> parse_level_targets(const std::string& ratios, const std::string& triangles,
                                           const std::string& errors, const std::string& command) {
    const int given = static_cast<int>(!ratios.empty()) + static_cast<int>(!triangles.empty()) +
                      static_cast<int>(!errors.empty());
    if (given > 1)
        throw Error(Error::Kind::argument,
                    command + ": give at most one of --levels, --level-triangles and --level-errors");
    std::vector<LodTarget> levels;
    if (!ratios.empty()) {
        for (double r : parse_number_list(ratios, "--levels")) {
            if (!(r > 0 && r < 1))
                throw Error(Error::Kind::argument, "--levels: ratio " + std::to_string(r) +
                                                       " is outside (0, 1) (level 0 is the input itself)");
            levels.push_back({LodTarget::Kind::ratio, r});
        }
    } else if (!triangles.empty()) {
        for (double t : parse_number_list(triangles, "--level-triangles")) {
            if (!(t >= 1) || t != std::floor(t))
                throw Error(Error::Kind::argument, "--level-triangles: " + std::to_string(t) + " is not a positive integer");
            levels.push_back({LodTarget::Kind::triangles, t});
        }
    } else if (!errors.empty()) {
        for (double e : parse_number_list(errors, "--level-errors")) {
            if (!(e > 0)) throw Error(Error::Kind::argument, "--level-errors: errors must be > 0");
            levels.push_back({LodTarget::Kind::error, e});
        }
    }
    return levels;
}

bool apply_level_options(Preset& preset, const std::string& ratios, const std::string& triangles,
                         const std::string& errors, const std::string& command) {
    if (ratios == "auto") {
        if (!triangles.empty() || !errors.empty())
            throw Error(Error::Kind::argument,
                        command + ": --levels auto chooses the levels; drop --level-triangles and --level-errors");
        preset.auto_levels = true;
        return true;
    }
    std::vector<LodTarget> levels = parse_level_targets(ratios, triangles, errors, command);
    if (levels.empty()) return false;
    preset.levels = std::move(levels);
    preset.auto_levels = false;
    return true;
}

void add_level_options(CLI::App* cmd, std::string& ratios, std::string& triangles, std::string& errors) {
    cmd->add_option("--levels", ratios,
                    "Triangle ratios of the input, decreasing, e.g. 0.5,0.25,0.1,0.03; or 'auto' (levels chosen "
                    "from the pixel tolerance and the smallest on-screen size, collapse method)");
    cmd->add_option("--level-triangles", triangles, "Triangle counts, decreasing, e.g. 20000,5000,1000");
    cmd->add_option("--level-errors", errors,
                    "Error bounds per step (fraction of the diagonal), increasing, e.g. 0.001,0.004");
}

void add_paint_options(CLI::App* cmd, std::string& importance, std::string& lock, std::string& seams) {
    cmd->add_option("--importance", importance,
                    "Per-vertex importance in [0, 1]: a paint file, or color:r|g|b|a (a vertex-colour channel) "
                    "(collapse method)");
    cmd->add_option("--lock", lock, "Paint file whose locked vertices never move or disappear (collapse method)");
    cmd->add_option("--seams", seams,
                    "Cost factors per seam class, e.g. weight=crease:4,border:2 (classes: uv, uv_mirror, crease, "
                    "material, color, border, non_manifold; collapse method)");
}

}  // namespace lodforge::cli
