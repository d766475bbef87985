// Levels of detail from the methods that are not a plain simplification chain: LODStrips, the
// prioritized marching-cube octree and the out-of-core octree. The pack (`lodforge pack`) and the studio
// both call these, so one preset gives the same levels everywhere (docs/pack.md, "Methods").
//
//   MethodLevels m = build_method_levels(mesh, preset, "scan.ply");   // m.levels: one per preset level
//
// Each preset level becomes the method's nearest level at or below the level's triangle target (ratio of
// the input's triangles, or a count); error targets are refused for these methods, whose levels are
// chosen by triangle count. `collapse` and `cluster` are built by build_lod_chain / simplify_cluster.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/pack/preset.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <cstdint>
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

struct MethodLevels {
    std::vector<Mesh> levels;                   // one per preset level, fine to coarse
    std::vector<std::size_t> target_triangles;  // what each level asked for
    std::vector<std::string> notes;             // for the user: targets a method could not meet, ...
    std::vector<std::uint8_t> lodstrips_file;   // the encoded .lodstrips (lodstrips method only)
    // The structure's cells: every node of the out-of-core octree; the cut of the finest level of the
    // MC octree; none for LODStrips.
    std::vector<StructureCell> cells;
    OctreeStats octree_stats;                   // octree method only (nodes == 0 otherwise)
};

// Triangle target of a preset level for a mesh of `input_triangles`; Error(argument) for error targets
// (naming `method` and the level) and for targets that round to zero.
std::size_t method_target_triangles(const LodTarget& target, std::size_t input_triangles, std::size_t level,
                                    const char* method);

// The dispatch for the three methods above; Error(argument) for collapse and cluster (not built here).
// `source_path` names the file in messages; the octree method reads it directly when it is a PLY file
// (out of core) and otherwise writes the mesh to a temporary PLY first.
MethodLevels build_method_levels(const Mesh& mesh, const Preset& preset, const std::string& source_path,
                                 Progress* progress = nullptr);

MethodLevels build_lodstrips_levels(const Mesh& mesh, const Preset& preset, const std::string& source_path,
                                    Progress* progress = nullptr);
MethodLevels build_mcoctree_levels(const Mesh& mesh, const Preset& preset, const std::string& source_path,
                                   Progress* progress = nullptr);
MethodLevels build_octree_levels(const Mesh& mesh, const Preset& preset, const std::string& source_path,
                                 Progress* progress = nullptr);

}  // namespace lodforge
