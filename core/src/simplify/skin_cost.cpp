// Skinning-aware collapse cost: quadric error measured in sampled poses of the animation.
//
// Based on:
//  - M. Garland, P. Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997 (plane
//    quadrics, here one set per pose through the multi-frame cost of simplify_frames.cpp);
//  - S. Kircher, M. Garland, "Progressive Multiresolution Meshes for Deforming Surfaces", SCA 2005, and
//    A. Mohr, M. Gleicher, "Deformation Sensitive Decimation", 2003 (simplifying an animated mesh by
//    the quadrics of several of its poses, so that a collapse must be good in every pose).
#include "lodforge/simplify/skin_cost.h"

#include "lodforge/error.h"
#include "lodforge/skeleton.h"
#include "lodforge/skeleton_pose.h"

#include <cmath>

namespace lodforge {

void SkinPoseFrames::attach(SimplifyParams& params) const {
    if (frames.empty()) return;
    params.extra_frames.clear();
    for (const std::vector<Vec3f>& f : frames) params.extra_frames.push_back(&f);
    params.frame_cost = SimplifyParams::FrameCost::max;
    params.frame_weight = weight;
}

SkinPoseFrames skin_pose_frames(const Mesh& mesh, const SkinCostParams& params) {
    if (!(params.weight >= 0.f) || !std::isfinite(params.weight))
        throw Error(Error::Kind::argument, "skin cost: the pose weight must be finite and >= 0");
    SkinPoseFrames out;
    out.weight = params.weight;
    if (params.pose_samples == 0 || !mesh.has_skin() || mesh.skeleton->animations.empty()) return out;
    if (params.animation >= mesh.skeleton->animations.size())
        throw Error(Error::Kind::argument, "skin cost: animation " + std::to_string(params.animation) +
                                               " does not exist (the skeleton has " +
                                               std::to_string(mesh.skeleton->animations.size()) + ")");
    // The rest pose (the nodes' stored transforms) sets the scale between scene and bind-pose units.
    PoseParams rest;
    rest.rest = true;
    Bounds rest_bounds;
    for (Vec3f p : pose_mesh(mesh, rest).positions) rest_bounds.add(p);
    const float rest_diagonal = rest_bounds.diagonal();
    const float scale = rest_diagonal > 0 ? mesh.bounds().diagonal() / rest_diagonal : 1.f;

    for (double t : pose_sample_times(*mesh.skeleton, params.animation, params.pose_samples)) {
        PoseParams pose;
        pose.animation = params.animation;
        pose.time = t;
        std::vector<Vec3f> positions = pose_mesh(mesh, pose).positions;
        for (Vec3f& p : positions) p = p * scale;
        out.frames.push_back(std::move(positions));
    }
    return out;
}

}  // namespace lodforge
