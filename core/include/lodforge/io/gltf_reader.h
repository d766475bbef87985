// glTF 2.0 import (.gltf with external or data-URI buffers, and binary .glb) through tinygltf.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"

#include <string>
#include <vector>

namespace lodforge {

// Morph targets of the imported primitives (filled only when GltfReadOptions::morph_targets is set;
// see docs/morph.md). Every primitive must have the same number of targets. Deltas are per Mesh vertex,
// in the same space as the Mesh (the node's world transform applied, without translation); normal
// deltas are scaled so that normalize(mesh.normals[v] + Σ w·normal_delta) is the morphed normal.
struct GltfMorphTargets {
    std::vector<std::string> names;                   // per target; empty strings when unnamed
    std::vector<std::vector<Vec3f>> position_deltas;  // [target][vertex]
    std::vector<std::vector<Vec3f>> normal_deltas;    // [target][vertex]; empty when no target has NORMAL
    std::vector<float> default_weights;               // mesh.weights (zeros when absent)
    // The first animation channel driving the weights of a node that places a morphing mesh
    // (empty when none): key times in seconds and the weights at each key ([key][target]).
    std::vector<float> key_times;
    std::vector<std::vector<float>> key_weights;
    std::string interpolation;  // "LINEAR", "STEP" or "CUBICSPLINE" (in-tangents dropped on import)
    std::size_t target_count() const { return position_deltas.size(); }
};

// Every triangle primitive of every mesh reachable from the default scene (or all scenes' roots when
// none is default) is appended once, placed by the world transform of its first instance in
// depth-first order (further instances add nothing: counts match the data as stored).
// POSITION, NORMAL, COLOR_0, TEXCOORD_0/1 are kept; each primitive's material becomes a Material
// (face_materials per triangle). When every placed mesh is skinned, every JOINTS_n/WEIGHTS_n pair is
// kept (Mesh::joints/weights, bind pose) with the node hierarchy, the skins (merged into one) and the
// node animations (Mesh::skeleton; docs/skinning.md); a scene mixing skinned and static meshes is
// imported static with a note. Textures keep their URI or embedded bytes. Vertices are never welded:
// position_ids identify the accessor's stored vertices.
struct GltfReadOptions {
    // false: each mesh once, as stored (counts match the file; LODs are built per mesh and shared by
    // its instances), with an import note naming meshes that other nodes instance again.
    // true: every node instance placed as its own copy (what a viewer shows).
    bool place_every_instance = false;
    // When set, receives the morph targets (Error(unsupported) when primitives disagree on the count).
    GltfMorphTargets* morph_targets = nullptr;
};

Mesh read_gltf(const std::string& path, Progress* progress = nullptr, const GltfReadOptions& options = {});

}  // namespace lodforge
