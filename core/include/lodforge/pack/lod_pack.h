// A LOD pack: what an engine loads for one mesh. Built from a preset (lodforge/preset.h) by both the
// studio's export button and `lodforge pack`, through this one function, so the same mesh and preset
// give byte-identical packs (see docs/pack.md for the files and the pack.json format).
//
//   PackParams p;  p.preset = load_preset("game.json");
//   p.source_path = "spot.obj";  p.output_dir = "packs/spot";
//   PackResult r = write_lod_pack(read_mesh(p.source_path), p, &progress);
//
// The levels come from the preset's method and targets; each is measured against the input with
// compare() (Metro), and the measured error gives its MSFT_screencoverage hint. The pack is written
// into a temporary directory beside output_dir and moved into place at the end: a failed or cancelled
// pack leaves nothing behind (and an existing output_dir untouched).
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/metrics/image_error.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/pack/preset.h"
#include "lodforge/pack/switch_points.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lodforge {

struct PackParams {
    Preset preset;             // method, levels, weights, exports, ...
    std::string source_path;   // the file the mesh came from: hashed into pack.json, stem names the outputs
    std::string output_dir;    // created if missing
    // Sampling of the error measurements (vertex_errors is not used). Part of what makes a pack: two
    // packs are identical only with equal parameters; the CLI and the studio use the defaults.
    DistanceParams distance;
    // The image-space error of a level against the input, for presets with export.image_error: written
    // into pack.json as each level's (after the first) "image_error". Rendering needs VTK, which the core
    // does not link: the front ends set this (lodforge/render/image_compare.h; the CLI's `pack`, the
    // studio's export). Must be set when the preset asks (else Error(argument)); may throw, and the pack
    // then fails like any other step.
    std::function<ImageError(const Mesh& input, const Mesh& level)> image_error;
};

struct PackLevel {
    std::size_t triangles = 0, vertices = 0;   // vertices = surface points (as `lodforge info` counts)
    std::size_t wedges = 0;                    // vertices as stored in the GLB (one per attribute set)
    double error = 0, error_relative = 0;   // measured Metro Hausdorff vs the input (model units, / bbox diagonal)
    double mean_error = 0, mean_error_relative = 0;
    // MSFT_screencoverage hint derived from the errors (docs/pack.md): the level is shown while the
    // object covers at least this fraction of the screen area; 0 for the coarsest level.
    double screen_coverage = 0;
    // The same switch point as an engine "screen size": projected bounding-sphere diameter / screen height.
    double screen_size = 0;
    // Every engine's form of the level's switch points, for the preset's `switch` block (switch_points.h).
    LevelSwitch switching;
    std::vector<std::string> files;         // per-level files written (PLY/OBJ), relative to output_dir
    std::optional<ImageError> image_error;  // PackParams::image_error's result (levels after the first)
};

struct PackResult {
    std::vector<PackLevel> levels;          // levels[0] = the input
    std::vector<std::string> files;         // every file written, relative to output_dir (pack.json included)
    std::string glb;                        // the .glb's name in `files`, empty when not exported
    std::string source_sha256;              // as in pack.json
    std::string manifest;                   // the text of pack.json
    std::vector<std::string> notes;         // targets a method could not meet, ... (also in pack.json)
    // Preset levels (1-based, as the preset lists them) left out because they were identical to the
    // level before them (same vertices, attributes, triangles and materials): an engine would switch
    // between equal meshes. Each one also has a note; pack.json lists them as "dropped_levels".
    std::vector<std::size_t> dropped_levels;
};

// Throws Error(argument) for a bad preset or parameters (empty source_path or output_dir, export.image_error
// without PackParams::image_error, an error
// target with the cluster, lodstrips, octree or mcoctree method, a .lodstrips export without the lodstrips
// method),
// Error(io) naming the file for an unreadable source or texture or an unwritable output, and
// Error(cancelled); in every case nothing is left in or beside output_dir.
PackResult write_lod_pack(const Mesh& mesh, const PackParams& params, Progress* progress = nullptr);

// True when an engine would draw `a` and `b` alike: the same indices, positions, colours, texcoords,
// face materials, joints and weights, and normals within 1e-5 (a chain that stopped re-normalises them,
// which moves them by an ulp). The pack leaves such a level out; the studio flags it.
bool same_surface(const Mesh& a, const Mesh& b);

// The pack.json format version written by this build.
inline constexpr int pack_format_version = 1;

}  // namespace lodforge
