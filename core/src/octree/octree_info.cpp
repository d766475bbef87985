#include "lodforge/octree/octree_info.h"

#include <nlohmann/json.hpp>

#include <vector>

namespace lodforge {

std::string octree_info_json(const OctreeStats& s, const OctreeHeader& h, int indent) {
    nlohmann::json j;
    j["nodes"] = s.nodes;
    j["leaves"] = s.leaves;
    j["depth_reached"] = s.depth_reached;
    j["levels"] = s.triangles_per_level.size();
    j["triangles_per_level"] = s.triangles_per_level;
    j["leaves_per_depth"] = s.leaves_per_depth;
    j["triangles_per_depth"] = s.triangles_per_depth;
    j["input_triangles"] = h.input_triangles;
    j["input_vertices"] = h.input_vertices;
    j["max_leaf_triangles"] = s.max_leaf_triangles;
    std::vector<std::string> attrs;
    if (h.layout.normals) attrs.push_back("normals");
    if (h.layout.colors) attrs.push_back("colors");
    if (h.layout.texcoords) attrs.push_back("texcoords");
    j["attributes"] = attrs;
    j["bounds"] = {{"min", {h.bounds.min.x, h.bounds.min.y, h.bounds.min.z}},
                   {"max", {h.bounds.max.x, h.bounds.max.y, h.bounds.max.z}}};
    j["root_cube"] = {{"min", {h.root_min[0], h.root_min[1], h.root_min[2]}}, {"size", h.root_size}};
    j["max_triangles"] = h.max_triangles;
    j["max_depth"] = h.max_depth;
    j["file_bytes"] = s.file_bytes;
    return j.dump(indent);
}

}  // namespace lodforge
