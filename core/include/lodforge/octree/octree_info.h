// The statistics of an octree LOD asset as JSON: the one description of `lodforge octree info --json`
// and the Python binding's octree_info() / build_octree() dicts, so their keys cannot drift.
#pragma once

#include "lodforge/octree/octree_store.h"

#include <string>

namespace lodforge {

// A JSON object with the keys nodes, leaves, depth_reached, levels, triangles_per_level, leaves_per_depth,
// triangles_per_depth, input_triangles, input_vertices, max_leaf_triangles, attributes, bounds, root_cube,
// max_triangles, max_depth, file_bytes; formatted by nlohmann::json::dump(indent).
std::string octree_info_json(const OctreeStats& stats, const OctreeHeader& header, int indent = 2);

}  // namespace lodforge
