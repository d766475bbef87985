// Levels of detail of a morphing mesh: half-edge collapse sequences over the shared connectivity.
//
//   MorphLodParams p;  p.order = MorphOrder::single;           // one order good in every frame
//   MorphLod lod = build_morph_lod(morph, p);
//   Mesh m = extract_morph(morph, lod, 0.4, 0.25);             // pose at t = 0.4, a quarter of the detail
//
// Half-edge collapses keep a subset of the input vertices, so every prefix of every sequence is a valid
// connectivity for every frame's positions: a level is a number of collapses, applied to any pose.
// Three strategies (docs/morph.md has the measurements that chose the default):
//  - single: one sequence whose collapse costs combine every sampled frame (max or mean of the per-frame
//    quadric errors; SimplifyParams::extra_frames), valid in every frame;
//  - per_frame: one sequence per keyframe, built on that frame's shape (the thesis); time t uses the
//    sequence of the nearest keyframe;
//  - naive: the sequence of keyframe 0, reused for every frame.
#pragma once

#include "lodforge/metrics/metrics.h"
#include "lodforge/morph/morph.h"
#include "lodforge/progress.h"
#include "lodforge/simplify/simplify.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lodforge {

enum class MorphOrder { single, per_frame, naive };
const char* morph_order_name(MorphOrder order);

struct MorphLodParams {
    MorphOrder order = MorphOrder::single;
    // Stored levels as fractions of the input triangles, strictly decreasing, in (0, 1). The last one is
    // the coarsest level (LOD factor 0); the sequences stop there.
    std::vector<float> levels = {0.5f, 0.25f, 0.1f, 0.03f};
    // Weights, seams, normal limit. Targets are set per level, placement is half-edge, weld is off
    // (morph_points() decides which wedges are one point), extra_frames are set for the single order.
    // The schedule defaults to greedy here: on animated meshes (small, built offline) it gave a 2-14 %
    // lower mean error than the round schedule at every level of the horse for 1.6x the build time
    // (docs/morph.md).
    SimplifyParams simplify = [] {
        SimplifyParams p;
        p.schedule = SimplifyParams::Schedule::greedy;
        return p;
    }();
    SimplifyParams::FrameCost frame_cost = SimplifyParams::FrameCost::sum;  // measured better (docs/morph.md)
    // Keyframes whose positions enter the single order's cost, spread evenly (first and last kept);
    // 0 = all of them. 16 measured best overall (docs/morph.md): more frames add flip constraints that
    // strongly deforming sequences pay for, fewer lose poses.
    std::size_t cost_frames = 16;
};

// One collapse sequence (indices into the morph mesh's vertices and points) and where its levels end.
struct MorphSequence {
    std::size_t frame = 0;  // keyframe it was built on (single: 0, its costs span the sampled frames)
    SimplifyResult sequence;  // collapses, moves and input_points; its mesh is left empty
    std::vector<std::size_t> level_collapses;  // per level: collapses to replay (non-decreasing)
    std::vector<std::size_t> level_triangles;  // per level: triangles after them
};

struct MorphLod {
    MorphOrder order = MorphOrder::single;
    std::vector<float> levels;
    std::size_t triangles = 0;  // triangles of the full level (faces degenerate on points dropped)
    std::vector<MorphSequence> sequences;  // single, naive: one; per_frame: one per keyframe
};

// Throws Error(argument) for bad levels, Error(cancelled) when asked to stop.
MorphLod build_morph_lod(const MorphMesh& morph, const MorphLodParams& params, Progress* progress = nullptr);

// The sequence serving time t (per_frame: the nearest keyframe's; otherwise the only one).
std::size_t morph_sequence_at(const MorphLod& lod, std::size_t frame_count, double t);
// Collapses for LOD factor f in [0, 1]: 1 = none (full detail), 0 = the coarsest level, linear between
// (continuous LOD, as LODStrips' GoToLod). Throws Error(argument) outside [0, 1].
std::size_t morph_collapses_for(const MorphSequence& sequence, double lod_factor);
// Faces (input vertex indices) after the first k collapses of a sequence.
std::vector<std::uint32_t> morph_level_indices(const MorphMesh& morph, const MorphSequence& sequence, std::size_t k);

// The pose at t with the faces of LOD factor f, as a compact mesh (only the vertices the level uses,
// points first; attributes from the base; normals blended and renormalised).
Mesh extract_morph(const MorphMesh& morph, const MorphLod& lod, double t, double lod_factor);

// Metro distance of every level at the given keyframes against the full mesh of the same frame.
struct MorphLevelError {
    std::size_t level = 0, frame = 0, triangles = 0;
    DistanceResult distance;
};
struct MorphMeasureParams {
    std::vector<std::size_t> frames;  // keyframes to measure; empty = all
    std::vector<std::size_t> levels;  // level indices; empty = all
    DistanceParams distance;          // vertex_errors is turned off
};
std::vector<MorphLevelError> measure_morph_lod(const MorphMesh& morph, const MorphLod& lod,
                                               const MorphMeasureParams& params, Progress* progress = nullptr);

}  // namespace lodforge
