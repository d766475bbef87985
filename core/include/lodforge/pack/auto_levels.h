// Automatic LOD chains (a preset's "levels": "auto"; docs/pack.md, "Automatic levels"): the number of
// levels and their targets chosen from the screen the pack switches for.
//
//   AutoLevelsResult a = choose_auto_levels(mesh, {.switching = preset.switching, .min_screen_pixels = 16});
//   preset.levels = a.targets;   // triangle targets, fine to coarse
//
// Candidates: one level per halving of the object's on-screen size, from the screen height down to
// min_screen_pixels; each may err by `pixels` at the size where it takes over. Of those whose measured
// error still switches them in at min_screen_pixels or larger, kept: the coarsest (it serves the
// smallest sizes) and, fine to coarse, each that at least halves the triangles of the level kept before
// it. Deterministic (the collapse chain and the Metro sampling are).
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/pack/preset.h"
#include "lodforge/pack/switch_points.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <string>
#include <vector>

namespace lodforge {

struct AutoLevelsParams {
    SwitchParams switching;          // pixel tolerance and screen (the field of view plays no part)
    double min_screen_pixels = 16;   // smallest projected diameter that matters, pixels (>= 1)
    double max_kept_ratio = 0.5;     // a level must have at most this fraction of the previous one's triangles
    SimplifyWeights weights;         // the collapse chain's, as the preset gives them
    bool lock_border = false;
    DistanceParams distance;         // sampling of the measurements
    std::string source_path;         // names the input in messages
};

struct AutoLevelCandidate {
    double screen_pixels = 0;        // projected diameter it was made for
    double error_target = 0;         // step error bound it was built with (of the diagonal)
    std::size_t triangles = 0;
    double error_relative = 0;       // measured Hausdorff distance to the input, of the diagonal
    bool kept = false;
};

struct AutoLevelsResult {
    std::vector<LodTarget> targets;               // the kept candidates as triangle targets
    std::vector<AutoLevelCandidate> candidates;   // every candidate, fine to coarse
};

// The candidates' on-screen diameters: height, height / 2, ... while >= min_screen_pixels (at least
// one: the height itself when it is below the minimum).
std::vector<double> auto_level_sizes(const SwitchParams& switching, double min_screen_pixels);

// Throws Error(invalid) for an input without triangles or one that cannot be simplified by half even
// once (no level would be kept), Error(cancelled) when `progress` asks to stop.
AutoLevelsResult choose_auto_levels(const Mesh& mesh, const AutoLevelsParams& params, Progress* progress = nullptr);

}  // namespace lodforge
