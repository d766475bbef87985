// Skinning-aware collapse cost (docs/skinning.md, "Skinning-aware simplification"): the skinned mesh
// posed at evenly spaced times of its animation, as further frames of the multi-frame cost
// (SimplifyParams::extra_frames), so that a collapse that looks free in the bind pose but tears a knee
// or an elbow when it bends costs what it costs in its worst pose.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/simplify/simplify.h"

#include <cstddef>
#include <vector>

namespace lodforge {

struct SkinCostParams {
    std::size_t pose_samples = 0;  // poses sampled from the animation; 0 = the bind pose alone
    std::size_t animation = 0;     // which animation of the skeleton
    float weight = 2.f;            // weight of the poses' cost against the bind pose's (SimplifyParams::frame_weight)
};

struct SkinPoseFrames {
    // One array of positions per pose, as long as the mesh's positions, in the bind pose's scale (each
    // pose scaled by the ratio of the bind pose's bounding-box diagonal to the rest pose's, so that a
    // skeleton carrying a unit scale does not shrink the poses' cost to nothing).
    std::vector<std::vector<Vec3f>> frames;
    float weight = 1.f;
    // Points `params.extra_frames` at the frames (which must outlive the simplification) and sets the
    // frame cost to the worst pose, weighted; does nothing without frames.
    void attach(SimplifyParams& params) const;
};

// No frames when pose_samples is 0, the mesh has no skin or its skeleton no animation (nothing to pose);
// throws Error(argument) when `animation` does not exist or weight is negative or not finite.
SkinPoseFrames skin_pose_frames(const Mesh& mesh, const SkinCostParams& params);

}  // namespace lodforge
