// A skinned mesh in a pose of its animation: the skeleton's node transforms at a time t (glTF samplers,
// LINEAR / STEP / CUBICSPLINE, rotations by quaternion slerp) and the vertices moved by linear blend
// skinning, as an engine draws them (docs/skinning.md, "Poses").
#pragma once

#include "lodforge/mesh.h"

#include <cstddef>
#include <vector>

namespace lodforge {

struct PoseParams {
    std::size_t animation = 0;  // index into Skeleton::animations (ignored when there are none)
    double time = 0;            // seconds; each channel holds its first / last key outside its keys
    bool rest = false;          // true: the nodes keep their stored transforms (the animation ignored)
};

struct PoseResult {
    std::vector<Vec3f> positions;  // per vertex, in scene space (the skinned node's transform ignored, as glTF says)
    std::vector<Vec3f> normals;    // per vertex, unit length; empty when the mesh has no normals
};

// Throws Error(invalid) when the mesh has no skin (no joints or no skeleton) or a vertex names a joint
// the skin lacks, Error(argument) when `animation` is out of range of a skeleton that has animations.
// With no animation the nodes keep their stored transforms (the rest pose).
PoseResult pose_mesh(const Mesh& mesh, const PoseParams& params);

// The mesh with positions and normals replaced by pose_mesh()'s (everything else unchanged).
Mesh posed_copy(const Mesh& mesh, const PoseParams& params);

// `count` times spread evenly over the animation, at the middle of equal slices of [0, duration]
// (a looping animation's first and last frames are one pose, so neither end is favoured). Empty when
// count is 0; all 0 when the skeleton has no animation.
std::vector<double> pose_sample_times(const Skeleton& skeleton, std::size_t animation, std::size_t count);

}  // namespace lodforge
