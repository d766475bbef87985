// glTF 2.0 import (.gltf with external or data-URI buffers, and binary .glb) through tinygltf.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"

#include <string>

namespace lodforge {

// Every triangle primitive of every mesh reachable from the default scene (or all scenes' roots when
// none is default) is appended once, placed by the world transform of its first instance in
// depth-first order (further instances add nothing: counts match the data as stored).
// POSITION, NORMAL, COLOR_0, TEXCOORD_0/1 are kept; each primitive's material becomes a Material
// (face_materials per triangle). Textures keep their URI or embedded bytes. Vertices are never welded:
// position_ids identify the accessor's stored vertices.
struct GltfReadOptions {
    // false: each mesh once, as stored (counts match the file; LODs are built per mesh and shared by
    // its instances), with an import note naming meshes that other nodes instance again.
    // true: every node instance placed as its own copy (what a viewer shows).
    bool place_every_instance = false;
};

Mesh read_gltf(const std::string& path, Progress* progress = nullptr, const GltfReadOptions& options = {});

}  // namespace lodforge
