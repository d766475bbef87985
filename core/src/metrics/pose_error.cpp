// Pose-space error: compare() (Metro, Cignoni, Rocchini, Scopigno, "Metro: measuring error on simplified
// surfaces", Computer Graphics Forum 1998) repeated on both meshes posed by linear blend skinning at
// evenly spaced times of the animation. Each mesh is posed by its own skeleton, so a level written to its
// own file is measured exactly as an engine would draw it.
#include "lodforge/metrics/pose_error.h"

#include "lodforge/error.h"
#include "lodforge/progress_range.h"
#include "lodforge/skeleton.h"
#include "lodforge/skeleton_pose.h"

#include <algorithm>

namespace lodforge {

namespace {

void check_animated(const Mesh& mesh, const std::string& name, std::size_t animation) {
    if (!mesh.has_skin())
        throw Error(Error::Kind::invalid, name + ": the mesh has no skin (no JOINTS_0/WEIGHTS_0 and skeleton); "
                                                 "pose-space error needs a skinned, animated mesh");
    if (mesh.skeleton->animations.empty())
        throw Error(Error::Kind::invalid, name + ": the skin has no animation to sample poses from");
    if (animation >= mesh.skeleton->animations.size())
        throw Error(Error::Kind::argument, name + ": animation " + std::to_string(animation) + " does not exist (it has " +
                                               std::to_string(mesh.skeleton->animations.size()) + ")");
}

}  // namespace

PoseErrorResult compare_poses(const Mesh& reference, const Mesh& test, const PoseErrorParams& params,
                              const std::string& reference_name, const std::string& test_name, Progress* progress) {
    if (params.poses == 0) throw Error(Error::Kind::argument, "pose-space error: the number of poses must be at least 1");
    check_animated(reference, reference_name, params.animation);
    check_animated(test, test_name, params.animation);
    DistanceParams distance = params.distance;
    distance.vertex_errors = false;
    const double steps = double(params.poses + 1);
    PoseErrorResult out;
    {
        ProgressRange range(progress, 0.0, 1.0 / steps);
        out.bind = compare(reference, test, distance, &range);
    }
    distance.region_errors = false;
    const std::vector<double> times = pose_sample_times(*reference.skeleton, params.animation, params.poses);
    for (std::size_t i = 0; i < times.size(); ++i) {
        PoseParams pose;
        pose.animation = params.animation;
        pose.time = times[i];
        const Mesh ref = posed_copy(reference, pose);
        const Mesh tst = posed_copy(test, pose);
        ProgressRange range(progress, double(i + 1) / steps, double(i + 2) / steps);
        PoseFrameError& f = out.frames.emplace_back();
        f.time = times[i];
        f.distance = compare(ref, tst, distance, &range);
        out.worst_hausdorff = std::max(out.worst_hausdorff, f.distance.hausdorff);
        out.worst_mean = std::max(out.worst_mean, f.distance.mean);
        out.mean_mean += f.distance.mean / double(times.size());
    }
    const double diagonal = out.bind.diagonal;
    if (diagonal > 0) {
        out.worst_hausdorff_relative = out.worst_hausdorff / diagonal;
        out.worst_mean_relative = out.worst_mean / diagonal;
        out.mean_mean_relative = out.mean_mean / diagonal;
    }
    return out;
}

}  // namespace lodforge
