// Where each level of a pack takes over, in the forms engines take (docs/pack.md, "Switch points").
//
//   SwitchParams p;  p.pixels = 2;  p.fov_deg = 45;
//   SwitchPoints s = switch_points({0, 0.004, 0.02}, diagonal, largest_side, p);
//   s.levels[1].godot.range_begin   // camera distance at which level 1 replaces level 0
//
// Level k+1 replaces level k once level k+1's measured error projects to at most `pixels` pixels on a
// `width` x `height` screen with a vertical field of view of `fov_deg`; the object is measured by its
// bounding sphere (radius = half the bounding-box diagonal). Every form below is that one switch point.
#pragma once

#include "lodforge/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

struct SwitchParams {
    double pixels = 1;               // largest error an artist accepts on screen, in pixels (> 0)
    std::uint32_t width = 1920;      // reference screen, pixels
    std::uint32_t height = 1080;
    double fov_deg = 60;             // vertical field of view, degrees (0, 180): distances only
    double hysteresis = 0.1;         // Godot's margins, as a fraction of each switch distance [0, 1)
    bool operator==(const SwitchParams&) const = default;
};

// Godot's GeometryInstance3D visibility range of one level (distances in model units, from the camera to
// the bounding sphere's centre); an end of 0 is Godot's "no end" (the coarsest level is never culled).
struct GodotRange {
    double range_begin = 0, range_begin_margin = 0;
    double range_end = 0, range_end_margin = 0;
};

struct LevelSwitch {
    // glTF MSFT_screencoverage (and Babylon.js's useLODScreenCoverage): the screen-area fraction the
    // sphere covers where this level gives way to the next; 0 for the coarsest level.
    double coverage = 0;
    // The same point as the sphere's projected diameter over the screen height.
    double screen_size = 0;
    // Unity LODGroup screenRelativeTransitionHeight of this level (where it ends; 0 for the coarsest),
    // for the LODGroup size Unity computes itself (the bounding box's largest side).
    double unity_transition_height = 0;
    // Unreal Engine LOD screen size of this level (where it begins; level 0 gets at least 1).
    double unreal_screen_size = 0;
    GodotRange godot;
};

struct SwitchPoints {
    std::vector<LevelSwitch> levels;   // one per level, level 0 (the input) first
};

// Screen-area fraction at which an error of `error_relative` (of the bounding-box diagonal) projects to
// `pixels` pixels on a width x height screen; 1 for errors too small to ever show (0 included).
double coverage_for_error(double error_relative, const SwitchParams& params);

// `error_relative[k]` is level k's measured distance to the input over the diagonal (level 0: 0);
// `diagonal` and `largest_side` are the input bounding box's. Switch points never move out of order:
// a finer level that measured worse than a coarser one does not make the coarser one switch in later.
// Throws Error(argument) for parameters out of the ranges above or a non-positive diagonal.
SwitchPoints switch_points(const std::vector<double>& error_relative, double diagonal, double largest_side,
                           const SwitchParams& params);
// The same for the input's bounding box (an empty or flat-to-a-point box gives no levels).
SwitchPoints switch_points(const std::vector<double>& error_relative, const Bounds& box, const SwitchParams& params);

// One level's switch points as pack.json writes them (docs/formats/pack-json.md), keys in a fixed order:
// coverage, screen_size, unity_transition_height, unreal_screen_size, godot {visibility_range_begin,
// visibility_range_begin_margin, visibility_range_end, visibility_range_end_margin}.
std::string level_switch_json(const LevelSwitch& s);

}  // namespace lodforge
