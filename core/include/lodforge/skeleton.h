// The skeleton a skinned Mesh is bound to, and the animations that move it: the part of a glTF scene a
// writer needs to re-emit a skinned mesh (docs/skinning.md). Shared, immutable, by every level built
// from one import (Mesh::skeleton is a shared_ptr), because levels change vertices, never joints.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

struct Mesh;

// One node of the scene hierarchy the joints live in, with its local transform as the source stored
// it: either `matrix` (16 numbers, column-major) or any of translation (3), rotation (4, quaternion
// x y z w), scale (3); empty vectors are absent (identity).
struct SkeletonNode {
    std::string name;
    std::vector<int> children;  // indices into Skeleton::nodes
    std::vector<double> translation, rotation, scale, matrix;
};

// One glTF animation sampler: key times (seconds, increasing) and the values at each key, `components`
// per key (3 translation/scale, 4 rotation), three times as many for CUBICSPLINE (in-tangent, value,
// out-tangent per key).
struct AnimationSampler {
    std::vector<float> input;
    std::vector<float> output;
    int components = 3;
    std::string interpolation = "LINEAR";  // LINEAR, STEP or CUBICSPLINE
};

struct AnimationChannel {
    int sampler = 0;   // index into Animation::samplers
    int node = 0;      // index into Skeleton::nodes
    std::string path;  // "translation", "rotation" or "scale"
};

struct Animation {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    float duration() const;  // last key time over all samplers (0 when none)
};

// One skin over the node hierarchy: vertex joint index j means node joints[j], whose inverse bind
// matrix is inverse_bind_matrices[j] (column-major; one per joint). Several glTF skins of one import
// are concatenated into this one (each vertex's indices offset accordingly).
struct Skeleton {
    std::vector<SkeletonNode> nodes;
    std::vector<int> roots;                                  // scene root nodes
    std::vector<int> joints;                                 // node of each joint index
    std::vector<std::array<float, 16>> inverse_bind_matrices;  // per joint
    int skeleton_root = -1;                                  // glTF skin.skeleton, -1 when unset
    std::string skin_name;
    std::vector<Animation> animations;
};

// Weights of each vertex as one list of influences: every JOINTS_n/WEIGHTS_n set merged, the
// `max_influences` heaviest kept (0: all, rounded up to a multiple of 4), renormalised to sum 1, and
// stored back as ceil(count / 4) sets; unused slots have joint 0 and weight 0. A vertex without any
// positive weight is bound to joint 0 with weight 1 (so every vertex sums to 1, as glTF requires).
// Does nothing on a mesh without joints.
void limit_influences(Mesh& mesh, std::size_t max_influences);

// Gives `to` (vertex i = vertex from_vertex[i] of `from`, e.g. a level whose builder keeps input
// vertices) the influences and skeleton of `from`. Does nothing when `from` is not skinned.
void carry_influences(const Mesh& from, const std::vector<std::uint32_t>& from_vertex, Mesh& to);

// Largest number of positive weights any vertex has (over all sets).
std::size_t max_influence_count(const Mesh& mesh);

}  // namespace lodforge
