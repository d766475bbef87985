// Morphing meshes: one connectivity, K keyframes of positions (and normals), blended linearly in time
// (LODStrips thesis, chapter 6; see docs/morph.md).
//
//   MorphMesh m = load_morph("seq-horse-gallop");      // 48 OBJ frames with identical connectivity
//   Mesh pose = morph_mesh_at(m, 0.37);                 // positions blended, normals renormalised
//
// t runs over the whole sequence: t = 0 is the first keyframe, t = 1 the last, keyframes evenly spaced.
// Between keyframes k and k+1, with s the fraction between them: V(t) = (1 − s)·V(k) + s·V(k+1);
// normals blend the same way and are renormalised.
//
// Case (a) of the issue loads here: keyframes that already share one connectivity (OBJ/PLY sequence,
// glTF morph targets). Case (b), two meshes of different connectivity, is made into the same MorphMesh
// (connectivity + per-frame positions) by build_supermesh (supermesh.h), so everything downstream applies
// to it.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

struct MorphMesh {
    // Connectivity and attributes of every frame (faces, texcoords, colours, materials, position_ids);
    // its positions and normals are those of keyframe 0.
    Mesh base;
    std::vector<std::vector<Vec3f>> frame_positions;  // [frame][vertex]
    std::vector<std::vector<Vec3f>> frame_normals;    // [frame][vertex], unit length
    bool normals_from_input = false;  // false: computed from the faces of each frame (area weighted)
    std::vector<std::string> frame_names;  // file name or "target N" / "key N" per frame
    std::string source;                    // what it was loaded from

    std::size_t frame_count() const { return frame_positions.size(); }
    std::size_t vertex_count() const { return base.vertex_count(); }
};

// Where t falls: V(t) = (1 − s)·V(frame) + s·V(frame + 1) (s = 0 and frame = K−1 at t = 1).
struct MorphSpan {
    std::size_t frame = 0;
    float s = 0;
};
// Throws Error(argument) when t is not in [0, 1] or frame_count is 0.
MorphSpan morph_span(std::size_t frame_count, double t);

// Indices of `count` of `total` frames spread evenly (first and last kept, no repeats); 0 or count ≥
// total = all of them.
std::vector<std::size_t> spread_frames(std::size_t total, std::size_t count);

// Blended positions / renormalised normals at t (out is resized to the vertex count).
void morph_positions_at(const MorphMesh& morph, double t, std::vector<Vec3f>& out);
void morph_normals_at(const MorphMesh& morph, double t, std::vector<Vec3f>& out);
// base with the positions and normals at t (every attribute and face of the base kept).
Mesh morph_mesh_at(const MorphMesh& morph, double t);
// base with keyframe k's positions and normals.
Mesh morph_keyframe_mesh(const MorphMesh& morph, std::size_t frame);

// Area-weighted vertex normals of `positions` over mesh.indices, shared across the wedges of one point
// (position_ids), unit length ((0,0,1) for a vertex no face with area uses).
std::vector<Vec3f> vertex_normals(const Mesh& mesh, const std::vector<Vec3f>& positions);

// Point ids that hold for every frame: two vertices are one point when they are one point of the base
// (position_ids) or sit at bit-identical positions in *every* frame. Dense, numbered by first vertex.
// The simplifier gets these with weld = false, so each point has one position per frame.
std::vector<std::uint32_t> morph_points(const MorphMesh& morph);

// Checks and completes a MorphMesh made by hand: at least one frame, every frame as long as base,
// finite values, faces in range; fills frame_normals from the faces when empty and sets base's
// positions and normals to frame 0. `source` names it in error messages. Throws Error(invalid).
void finish_morph(MorphMesh& morph, const std::string& source);

struct MorphLoadOptions {
    // Keep this many keyframes, evenly spread over the sequence (first and last kept); 0 = all.
    std::size_t frames = 0;
};

// A directory of .obj/.ply files (sorted by name, at least two) or a .gltf/.glb with morph targets.
// glTF: with a weights animation on the morphing node, the keyframes are the animation sampled at its
// key count of evenly spaced times; without one, base + each target at weight 1 (docs/morph.md).
// Errors: Error(invalid) naming the first file (and face or vertex) whose connectivity differs,
// Error(io)/Error(format) for unreadable files, Error(unsupported) for glTF without morph targets.
MorphMesh load_morph(const std::string& path, const MorphLoadOptions& options = {}, Progress* progress = nullptr);

}  // namespace lodforge
