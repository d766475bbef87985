// Switch points of a pack's levels (switch_points.h): one screen-space rule, written in the units each
// engine takes. The rule is the screen-space error bound of view-dependent LOD (Luebke et al., "Level
// of Detail for 3D Graphics", 2003, ch. 4): a level may be drawn once its geometric error projects to
// at most the tolerated number of pixels. The engine forms follow each engine's own LOD measure:
// MSFT_screencoverage as Babylon.js measures it (sphere area over screen area), Unreal's screen size
// (sphere diameter over screen height), Unity's relative height (LODGroup size over the frustum height
// at the object) and Godot's visibility ranges (camera distances).
#include "lodforge/pack/switch_points.h"

#include "lodforge/error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace lodforge {

namespace {

void check(const SwitchParams& p, double diagonal, double largest_side) {
    auto bad = [](const std::string& what) { throw Error(Error::Kind::argument, "switch points: " + what); };
    if (!(p.pixels > 0) || !std::isfinite(p.pixels)) bad("the pixel tolerance must be > 0");
    if (p.width == 0 || p.height == 0) bad("the reference screen must have a width and a height");
    if (!(p.fov_deg > 0 && p.fov_deg < 180)) bad("the field of view must be between 0 and 180 degrees");
    if (!(p.hysteresis >= 0 && p.hysteresis < 1)) bad("the hysteresis must be in [0, 1)");
    if (!(diagonal > 0) || !std::isfinite(diagonal)) bad("the bounding-box diagonal must be > 0");
    if (!(largest_side > 0) || largest_side > diagonal * (1 + 1e-6)) bad("the largest side must be in (0, diagonal]");
}

}  // namespace

double coverage_for_error(double error_relative, const SwitchParams& p) {
    if (!(error_relative > 0)) return 1.0;
    // Sphere of radius r = diagonal / 2 projected to rho pixels: the error spans error_relative * 2 * rho
    // pixels, `pixels` at rho = pixels / (2 e); the sphere then covers pi rho^2 of W H.
    const double rho = p.pixels / (2.0 * error_relative);
    return std::min(1.0, std::numbers::pi * rho * rho / (double(p.width) * double(p.height)));
}

SwitchPoints switch_points(const std::vector<double>& error_relative, double diagonal, double largest_side,
                           const SwitchParams& p) {
    check(p, diagonal, largest_side);
    const std::size_t n = error_relative.size();
    const double W = p.width, H = p.height;
    const double radius = diagonal / 2;
    const double tan_half = std::tan(p.fov_deg * std::numbers::pi / 360.0);
    SwitchPoints out;
    out.levels.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        LevelSwitch& s = out.levels[k];
        s.coverage = k + 1 < n ? coverage_for_error(error_relative[k + 1], p) : 0.0;
        if (k > 0) s.coverage = std::min(s.coverage, out.levels[k - 1].coverage);
        const double rho = std::sqrt(s.coverage * W * H / std::numbers::pi);  // sphere radius, pixels
        s.screen_size = 2 * rho / H;
        // Unity's relative height is the LODGroup size over the frustum height at the object, and the
        // sphere's diameter is the diagonal: the same point for a size of largest_side.
        s.unity_transition_height = s.screen_size * largest_side / diagonal;
        // Unreal draws level k while the screen size is below level k's own value: its begin.
        s.unreal_screen_size = k == 0 ? 1.0 : out.levels[k - 1].screen_size;
        // The camera distance at which the sphere projects to rho pixels: rho = r H / (2 d tan(fov / 2)).
        const double end = rho > 0 ? radius * H / (2 * rho * tan_half) : 0.0;
        s.godot.range_end = end;
        s.godot.range_end_margin = p.hysteresis * end;
        if (k > 0) {
            s.godot.range_begin = out.levels[k - 1].godot.range_end;
            s.godot.range_begin_margin = out.levels[k - 1].godot.range_end_margin;
        }
    }
    if (n > 1) out.levels[0].unreal_screen_size = std::max(1.0, out.levels[1].unreal_screen_size);
    return out;
}

SwitchPoints switch_points(const std::vector<double>& error_relative, const Bounds& box, const SwitchParams& params) {
    const double diagonal = box.diagonal();
    if (!(diagonal > 0)) return {};
    const Vec3f size = box.size();
    // In float the diagonal of a box flat in two axes can round below its one side.
    const double largest = std::min<double>(diagonal, std::max({size.x, size.y, size.z}));
    return switch_points(error_relative, diagonal, largest, params);
}

std::string level_switch_json(const LevelSwitch& s) {
    nlohmann::ordered_json j;
    j["coverage"] = s.coverage;
    j["screen_size"] = s.screen_size;
    j["unity_transition_height"] = s.unity_transition_height;
    j["unreal_screen_size"] = s.unreal_screen_size;
    j["godot"] = {{"visibility_range_begin", s.godot.range_begin},
                  {"visibility_range_begin_margin", s.godot.range_begin_margin},
                  {"visibility_range_end", s.godot.range_end},
                  {"visibility_range_end_margin", s.godot.range_end_margin}};
    return j.dump();
}

}  // namespace lodforge
