// Surface distance between two skinned meshes (a level and its original) in the bind pose and in
// poses sampled from the animation: a level that looks right standing can still collapse when the
// character walks (docs/skinning.md, "Pose-space error").
#pragma once

#include "lodforge/metrics/metrics.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <string>
#include <vector>

namespace lodforge {

struct PoseErrorParams {
    std::size_t poses = 8;      // animation frames measured, at pose_sample_times()
    std::size_t animation = 0;  // which animation of the reference's skeleton
    // Sampling of every measurement; vertex_errors is not filled, region_errors only for the bind pose.
    DistanceParams distance;
};

struct PoseFrameError {
    double time = 0;  // seconds into the animation
    DistanceResult distance;
};

struct PoseErrorResult {
    DistanceResult bind;                // the meshes as stored (bind pose)
    std::vector<PoseFrameError> frames; // one per sampled time, each mesh posed by its own skeleton
    // Over the frames: the largest Hausdorff distance, the largest and the average mean distance
    // (model units, and divided by the bind pose's reference diagonal).
    double worst_hausdorff = 0, worst_mean = 0, mean_mean = 0;
    double worst_hausdorff_relative = 0, worst_mean_relative = 0, mean_mean_relative = 0;
};

// Throws Error(invalid) naming `reference_name` / `test_name` when either mesh has no skin or its
// skeleton no animation, Error(argument) when poses is 0 or the animation does not exist in both,
// Error(cancelled) when progress asks to stop.
PoseErrorResult compare_poses(const Mesh& reference, const Mesh& test, const PoseErrorParams& params,
                              const std::string& reference_name = "reference", const std::string& test_name = "test",
                              Progress* progress = nullptr);

}  // namespace lodforge
