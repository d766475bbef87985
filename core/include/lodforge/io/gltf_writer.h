// glTF 2.0 binary (.glb) export of a chain of levels of detail (see docs/pack.md, "The GLB").
//
//   GlbOptions o;  o.name = "spot";  o.screen_coverage = {0.38, 0.09, 0.01, 0};
//   write_glb(chain.shared, o, "spot.glb");          // levels over one vertex buffer (LOD chains)
//   write_glb({lod0, lod1, lod2}, o, "spot.glb");     // independent levels (clustering)
//
// One node per level: node 0 (level 0, the only node in the scene) carries `MSFT_lod` with the coarser
// levels' nodes in `ids` and, when given, `MSFT_screencoverage` in its `extras`. A reader without
// MSFT_lod shows level 0. Each level is one glTF mesh whose primitives are the level's triangles split
// by face material. Positions (with min/max), normals (unit length), COLOR_0, every TEXCOORD_n (v
// flipped back to glTF's top-left origin), materials (pbrMetallicRoughness, normal, occlusion,
// emissive, double-sided) and their images (embedded in the binary chunk) are written. Skinned levels
// (Mesh::has_skin, one shared Mesh::skeleton) get JOINTS_n/WEIGHTS_n, `"skin": 0` on every level node,
// the skeleton's nodes after the level nodes and its animations once (docs/skinning.md).
//
// Extending with morph targets: the writer emits each *vertex source* (one Mesh's vertex arrays, or
// SharedLodBuffers::vertices) once, and each level's primitives take accessors over a prefix of a
// source. Morph targets belong to a vertex source as well (one displacement array per target and
// attribute, the same length as the positions), so they become more bufferViews of that source and a
// `targets` list on every primitive drawing from it, without touching levels, materials or images.
#pragma once

#include "lodforge/simplify/lod_chain.h"
#include "lodforge/mesh.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

struct GlbOptions {
    std::string name = "mesh";        // node names are <name>_LOD<k>, mesh names the same
    // MSFT_screencoverage: one value per level, non-increasing (level k is shown while the object
    // covers at least screen_coverage[k] of the screen). Empty: no hint is written. Any other length
    // is an Error(argument).
    std::vector<double> screen_coverage;
    std::string generator = "LodForge";
    // A texture file that cannot be read: false throws Error(io) naming it; true drops the binding
    // (the material keeps its factors) and records a warning in GlbResult::warnings.
    bool skip_missing_textures = false;
};

struct GlbResult {
    std::size_t bytes = 0;        // size of the .glb
    std::size_t levels = 0;
    std::size_t primitives = 0;   // over all levels
    std::size_t materials = 0;
    std::size_t images = 0;       // embedded images (each distinct image once)
    std::vector<std::string> warnings;
};

// The .glb bytes. `levels` are fine to coarse (level 0 first, at least one, each with triangles).
// Materials equal across levels are written once; images equal in content are embedded once. Throws
// Error(invalid) for inconsistent meshes (attribute sizes, indices or face materials out of range),
// Error(io) for an unreadable texture (see GlbOptions::skip_missing_textures), Error(unsupported)
// for a texture that is neither PNG nor JPEG (all core glTF allows), Error(cancelled).
std::vector<std::uint8_t> encode_glb(const std::vector<Mesh>& levels, const GlbOptions& options,
                                     GlbResult* result = nullptr, Progress* progress = nullptr);
// The levels of a LOD chain over its one shared vertex buffer: every level's accessors view a prefix
// of the same bufferViews, so vertices are stored once.
std::vector<std::uint8_t> encode_glb(const SharedLodBuffers& shared, const GlbOptions& options,
                                     GlbResult* result = nullptr, Progress* progress = nullptr);

// encode_glb, then an atomic write to `path` (AtomicFile). Errors name `path` or the texture.
GlbResult write_glb(const std::vector<Mesh>& levels, const GlbOptions& options, const std::string& path,
                    Progress* progress = nullptr);
GlbResult write_glb(const SharedLodBuffers& shared, const GlbOptions& options, const std::string& path,
                    Progress* progress = nullptr);

// Morph targets and a weights animation for the levels of a shared buffer (docs/morph.md, "glTF
// export"). Every level's primitives get the same targets (accessors over the level's vertex prefix),
// every level's mesh the same default weights, and the animation drives the weights of every level's
// node, so whichever level MSFT_lod shows plays the same motion. Without this argument the output is
// byte-for-byte what it was before morph targets existed.
struct GlbMorphTargets {
    std::vector<std::string> names;                   // per target (mesh extras.targetNames); may be empty
    std::vector<std::vector<Vec3f>> position_deltas;  // [target][shared vertex], at least one target
    std::vector<std::vector<Vec3f>> normal_deltas;    // [target][shared vertex], or empty
    std::vector<float> default_weights;               // per target; empty = zeros
    // Weights animation, written when key_times is not empty: increasing times in seconds and the
    // weights at each key ([key][target]); interpolation "LINEAR" or "STEP".
    std::vector<float> key_times;
    std::vector<std::vector<float>> key_weights;
    std::string interpolation = "LINEAR";
    std::string animation_name = "morph";
    // KHR_mesh_quantization (docs/morph.md, "glTF export"): POSITION deltas as normalized SHORT with one
    // uniform scale s (the largest displacement component) and translation c on every level node, so
    // the base positions are written as (p - c) / s (float); NORMAL deltas as normalized BYTE, except a
    // target with a component outside [-1, 1], which stays FLOAT. The extension is listed in
    // extensionsUsed and extensionsRequired. Position error <= s / 65534 per component; normal delta
    // error <= 1 / 254 per component.
    bool quantize = false;
};

// As encode_glb(shared, ...) with morph targets. Error(invalid) for targets or keys whose sizes do not
// match the vertex buffer, the target count or each other, or non-finite values.
std::vector<std::uint8_t> encode_glb(const SharedLodBuffers& shared, const GlbOptions& options,
                                     const GlbMorphTargets& morph, GlbResult* result = nullptr,
                                     Progress* progress = nullptr);
GlbResult write_glb(const SharedLodBuffers& shared, const GlbOptions& options, const GlbMorphTargets& morph,
                    const std::string& path, Progress* progress = nullptr);

}  // namespace lodforge
