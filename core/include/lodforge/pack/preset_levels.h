// The levels of detail a preset describes, for any method: the one function the pack
// (`lodforge pack`, the studio's export), the `lod` command and the studio's level view all call, so
// one preset gives the same levels everywhere (docs/pack.md, "Methods").
//
//   PresetLevels r = build_preset_levels(mesh, load_preset("game.json"), {.source_path = "scan.ply"});
//   r.levels[k - 1] is level k (the input is level 0), r.distance[k - 1] its measured error
//
// collapse builds a LOD chain (each level from the previous one); cluster clusters the input once per
// level; lodstrips, mcoctree and octree build their multiresolution structure once and cut it at each
// level's triangle target (the nearest level at or below it), so error targets are refused for them,
// as for cluster.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/pack/preset.h"
#include "lodforge/progress.h"
#include "lodforge/simplify/lod_chain.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lodforge {

// A cube of the method's structure, for overlays (the studio's octree cells).
struct StructureCell {
    float min[3] = {0, 0, 0};
    float size = 0;
    int depth = 0;                // root 0
    bool leaf = false;
    std::uint64_t triangles = 0;  // input triangles under the cell (octree); 0 where not known (MC octree)
};

// Why a level has the triangles it has.
enum class LevelStop {
    target_reached,
    error_limit,     // collapse: the next collapse would exceed the level's error target
    topology_limit,  // collapse: no valid collapse left
    closest,         // the structure's (or the clustering grid's) nearest level to the target
};

struct PresetLevelsParams {
    // Names the input in messages; the octree method streams it from disk when it is a PLY file (and
    // otherwise writes the mesh to a temporary PLY first). May be empty.
    std::string source_path;
    bool measure = true;       // measure every level against the input with compare()
    DistanceParams distance;   // sampling of those measurements (vertex_errors is never filled)
};

struct PresetLevels {
    std::vector<Mesh> levels;                   // levels 1..N, fine to coarse (level 0 is the input)
    std::vector<LodTarget> targets;             // per level: the preset's, or those "levels": "auto" chose
    std::vector<std::size_t> target_triangles;  // per level; 0 for error targets
    std::vector<LevelStop> stops;               // per level
    std::vector<DistanceResult> distance;       // per level, against the input (empty without measure)
    std::vector<std::string> notes;             // for the user: targets a method could not meet, ...
    // Every vertex of every level is a vertex of the input at its place (half-edge collapses: collapse
    // with Preset::placement half-edge, and lodstrips); the others move vertices or make new surfaces.
    bool vertices_on_input = false;
    // collapse: the chain's step errors, collapse sequence and, with half-edge placement, all levels
    // over one vertex buffer (for the GLB; empty with optimal placement); its level meshes are moved
    // into `levels` (chain->levels[k].mesh is empty for k >= 1).
    std::optional<LodChainResult> chain;
    std::vector<std::uint8_t> lodstrips_file;   // the encoded .lodstrips (lodstrips only)
    // The structure's cells: every node of the out-of-core octree; the cut of the finest level of the
    // MC octree; none for the other methods.
    std::vector<StructureCell> cells;
    OctreeStats octree_stats;                   // octree only (nodes == 0 otherwise)
};

// Optional profile of a build (not part of the levels).
struct PresetLevelsStats {
    std::vector<double> level_seconds;  // per level: its build and measurement (structures: shared evenly)
};

// A preset with "levels": "auto" (collapse only) gets its targets from choose_auto_levels
// (lodforge/pack/auto_levels.h), measured whatever `measure` says; a last level that measures too
// coarse for the preset's min_screen_pixels is left out.
// Throws Error(argument) for a preset without levels or with targets the method cannot take (naming
// source_path and the level), Error(invalid) for an input without triangles or a level the method
// cannot make, Error(cancelled) when `progress` asks to stop.
PresetLevels build_preset_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params = {},
                                 Progress* progress = nullptr, PresetLevelsStats* stats = nullptr);

}  // namespace lodforge
