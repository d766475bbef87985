// The options model shared by the studio and the CLI (F3D-style): everything an artist tunes to turn one
// mesh into a LOD pack. A preset is a JSON file; `lodforge pack --preset P.json` and the studio's export
// button read the same file through these functions, so the same preset gives the same pack.
//
//   Preset p = load_preset("game.json");      // throws lodforge::Error naming the file and the key
//   p.levels = lod_targets_from_ratios({0.5, 0.25, 0.1});
//   save_preset("game.json", p);              // atomic write
//
// The JSON keys are documented in docs/presets.md. Unknown keys are an error (a typo must not be
// silently ignored); missing keys take the defaults below, so a preset may name only what it changes.
#pragma once

#include "lodforge/pack/switch_points.h"
#include "lodforge/simplify/simplify.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lodforge {

// Presets compare equal when every option does (the studio's undo and "modified" marker rely on it).
bool operator==(const SimplifyWeights& a, const SimplifyWeights& b);

// How the levels of a pack are made.
enum class LodMethod {
    collapse,   // in-core generalized-quadric edge collapse, each level from the previous one
    cluster,    // in-core vertex clustering with generalized quadrics
    octree,     // out-of-core octree (max triangles per node, max depth, memory budget)
    lodstrips,  // collapse sequence replayed on triangle strips (.lodstrips)
    mcoctree,   // prioritized marching-cube octree (surface rebuilt from points)
};

// One level's target; exactly one kind per level.
struct LodTarget {
    enum class Kind { ratio, triangles, error };
    Kind kind = Kind::ratio;
    double value = 1.0;   // ratio in (0, 1]; triangle count >= 1; error relative to the bbox diagonal > 0
    bool operator==(const LodTarget&) const = default;
};

std::vector<LodTarget> lod_targets_from_ratios(const std::vector<double>& ratios);

struct OctreeOptions {
    std::uint32_t max_triangles_per_node = 20000;
    std::uint32_t max_depth = 8;
    std::uint32_t memory_mb = 256;
    bool operator==(const OctreeOptions&) const = default;
};

struct McOctreeOptions {
    std::uint32_t resolution = 128;   // cubes along the longest bounding-box axis
    bool operator==(const McOctreeOptions&) const = default;
};

struct StripOptions {
    bool primitive_restart = true;    // false: degenerate triangles join the strips
    bool operator==(const StripOptions&) const = default;
};

// Skinned inputs (docs/skinning.md): the most joints a vertex of each level may follow, one value per
// preset level (the last repeats for further levels), 1..8; the heaviest are kept and renormalised.
// Level 0 (the input) keeps all its influences, renormalised.
// pose_samples (0..64): collapse levels weigh their cost in that many poses sampled from the animation
// besides the bind pose (0: the bind pose alone), `weight` (0..100; 2 measured best, docs/skinning.md)
// times as much (SkinCostParams).
struct SkinOptions {
    std::vector<std::uint32_t> max_influences{4};
    std::uint32_t pose_samples = 0;
    double weight = 2.0;
    bool operator==(const SkinOptions&) const = default;
};

// What the pack contains besides pack.json.
struct ExportOptions {
    bool glb = true;          // one .glb with every level (MSFT_lod + MSFT_screencoverage)
    bool ply = false;         // one PLY per level
    bool obj = false;         // one OBJ (+ MTL) per level
    bool lodstrips = false;   // the .lodstrips file (method lodstrips only)
    // Each level's image-space error in pack.json (docs/image-compare.md): needs a front end with the
    // renderer (PackParams::image_error); off by default, as rendering 14 views per level takes seconds.
    bool image_error = false;
    bool operator==(const ExportOptions&) const = default;
};

struct Preset {
    std::string name = "default";
    LodMethod method = LodMethod::collapse;
    std::vector<LodTarget> levels = lod_targets_from_ratios({0.5, 0.25, 0.1, 0.03});
    // "levels": "auto": the levels are chosen from `switching` and `min_screen_pixels` (auto_levels.h);
    // `levels` is then ignored (and kept, so switching auto off restores the list).
    bool auto_levels = false;
    // The smallest on-screen size that matters, in pixels (the bounding sphere's projected diameter):
    // automatic chains stop at the level that takes over at this size.
    double min_screen_pixels = 16;
    // The screen the switch points are computed for (pack.json, the GLB's MSFT_screencoverage).
    SwitchParams switching;
    SimplifyWeights weights;
    bool lock_border = false;
    // Artist paint (docs/artist-control.md), method collapse only: a paint file or "color:r|g|b|a" for
    // the importance, a paint file for the lock; paths relative to the working directory; "" = none.
    std::string importance;
    std::string lock;
    // Seam class weights for the collapse method, as the CLI's --seams ("weight=crease:4,border:2";
    // parse_seam_weights()); "" = none.
    std::string seams;
    // Where the collapse method's kept vertices go (docs/presets.md, "placement"): optimal gives every
    // level its own vertex data (lower error, larger GLB); half-edge keeps input vertices, so the levels
    // share one vertex buffer. lodstrips always uses half-edge (its strips replay one collapse prefix).
    Placement placement = Placement::optimal;
    OctreeOptions octree;
    McOctreeOptions mcoctree;
    StripOptions strips;
    SkinOptions skin;
    ExportOptions exports;
    bool operator==(const Preset&) const = default;
};

// The preset format version written into every file ("version": 1).
inline constexpr int preset_format_version = 1;
// Most levels a preset may list (each one is a simplification of the whole input).
inline constexpr std::size_t kMaxPresetLevels = 32;

// Parses preset JSON text; `source` names the file (or "<text>") in error messages. Throws
// lodforge::Error(format) for malformed JSON and (argument) for bad values or unknown keys.
Preset parse_preset(std::string_view json_text, const std::string& source = "<preset>");
// Pretty-printed JSON with every key, in a fixed order (so saving is deterministic and diffable).
std::string preset_to_json(const Preset& preset);

Preset load_preset(const std::string& path);
void save_preset(const std::string& path, const Preset& preset);  // atomic write

std::string_view to_string(LodMethod method);
// Throws lodforge::Error(argument) listing the accepted names.
LodMethod lod_method_from_string(std::string_view name);

std::string_view to_string(Placement placement);   // "optimal" or "half-edge"
// Throws lodforge::Error(argument) listing the accepted names.
Placement placement_from_string(std::string_view name);

}  // namespace lodforge
