// A summary of a mesh for humans and tools: what `lodforge info` prints and the studio's statistics
// panel shows. One place so both always agree.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/io/mesh_validate.h"

#include <string>
#include <vector>

namespace lodforge {

struct MeshInfo {
    std::string path;
    std::string format;
    std::size_t vertices = 0;   // surface points as stored in the file (Mesh::point_count())
    std::size_t wedges = 0;     // render vertices after splitting attribute seams (Mesh::vertex_count())
    std::size_t triangles = 0;
    std::vector<std::string> attributes;  // "position", "normal", "color", "texcoord0", "joints0", "weights0", ...
    std::size_t materials = 0;
    std::vector<std::string> textures;    // paths (or "<embedded image/png>") of every texture used
    std::vector<std::string> missing_textures;  // textures whose file does not exist
    std::vector<std::string> warnings;          // importer notes (Mesh::warnings)
    // The skin (all zero when the mesh is not skinned): joint count, the most influences any vertex
    // has, and each animation as "name (duration s, channels)".
    std::size_t joints = 0;
    std::size_t max_influences = 0;
    std::vector<std::string> animations;
    Bounds bounds;
    ValidationReport validation;
};

MeshInfo mesh_info(const Mesh& mesh, const std::string& path = {}, const std::string& format = {});
std::string to_json(const MeshInfo& info, int indent = 2);
std::string to_text(const MeshInfo& info);

}  // namespace lodforge
