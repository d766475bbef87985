// glTF export of a morphing mesh with LOD: each level a mesh with the same morph targets, and a weights
// animation over the frames (docs/morph.md, "glTF export").
//
//   MorphStripsBuild strips = build_morph_lodstrips(morph, lod);
//   MorphGltfOptions o;  o.timing = morph_gltf_timing(morph);       // the source's own key times
//   write_morph_glb(morph, lod, strips, o, "horse.glb");
//
// One vertex buffer in the strips' canonical order (level k draws a prefix of it, as in the LOD pack's
// shared buffers), targets j = frame j+1 − frame 0 for positions and normals, so every level has
// K − 1 targets. The animation's key i sets target i−1 to 1 and the rest to 0; with LINEAR
// interpolation glTF then plays exactly V(t) between keyframes.
#pragma once

#include "lodforge/io/gltf_writer.h"
#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_lod.h"
#include "lodforge/morph/morph_lodstrips.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <string>
#include <vector>

namespace lodforge {

struct MorphGltfTiming {
    bool animated = true;           // false: no animation (a glTF source without one)
    double start_seconds = 0;       // time of keyframe 0
    double seconds_per_frame = 1.0 / 30.0;
};

// The timing a source implies: a sequence directory plays at 30 keyframes per second from 0; a glTF
// with a weights animation keeps its first and last key times (keyframes evenly spaced between them, as
// load_morph sampled them); a glTF without one gets no animation. Reads the glTF again for its keys.
MorphGltfTiming morph_gltf_timing(const MorphMesh& morph);

struct MorphGltfOptions {
    std::string name = "morph";
    MorphGltfTiming timing;
    std::vector<double> screen_coverage;  // per written level (full detail first), or empty
    // KHR_mesh_quantization targets (normalized SHORT positions, BYTE normals; GlbMorphTargets::quantize),
    // the default; false writes float32 targets and no extension.
    bool quantize = true;
};

struct MorphGltfResult {
    GlbResult glb;
    std::size_t targets = 0;
    std::vector<std::size_t> level_triangles;  // full detail first
    std::vector<std::size_t> level_vertices;   // the prefix each level draws
};

// The shared buffer: vertex arrays (frame 0, canonical order) and per level (full detail, then each
// stored level of the LOD) the strips' triangles at that level with their materials.
SharedLodBuffers morph_gltf_buffers(const MorphMesh& morph, const MorphLod& lod, const MorphStripsBuild& strips);
// quantize: KHR_mesh_quantization targets (GlbMorphTargets::quantize), and each normal displacement that
// does not fit normalized BYTE ([-1, 1]) replaced by λ·n_j − n_0 with the largest λ in (0, 1] that fits,
// so n_0 + d still points along frame j's normal (renderers normalise), or by a clamped one where that
// points closer after rounding (docs/morph.md, "glTF export").
GlbMorphTargets morph_gltf_targets(const MorphMesh& morph, const MorphStripsBuild& strips, const MorphGltfTiming& timing,
                                   bool quantize = false);

MorphGltfResult write_morph_glb(const MorphMesh& morph, const MorphLod& lod, const MorphStripsBuild& strips,
                                const MorphGltfOptions& options, const std::string& path, Progress* progress = nullptr);

}  // namespace lodforge
