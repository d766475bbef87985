// A chain of levels of detail built by successive edge-collapse simplification (see
// docs/simplification.md, "LOD chains").
//
//   LodChainParams p;  p.levels = lod_levels_from_ratios({0.5f, 0.25f, 0.1f, 0.03f});
//   LodChainResult r = build_lod_chain(mesh, p);   // r.levels[0] is the input, r.levels[k] level k
//
// Level k is simplified from level k-1 (cheaper than from the input, and nested: every vertex of level k
// descends from a vertex of level k-1). With half-edge placement (the default) collapses never create
// vertices, so every level indexes the input's vertex array: `r.shared` holds the vertices once and one
// index range per level, as meshoptimizer's LOD chains do. With optimal placement every level has its
// own positions and attributes (lower error, more bytes) and `r.shared` is empty. Either way
// `r.sequence` is one collapse sequence on the input covering the whole chain
// (replay_collapses(input, r.sequence, r.levels[k].collapses_end) gives level k's connectivity).
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/progress.h"
#include "lodforge/simplify/simplify.h"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace lodforge {

// The target of one level (level 1 onwards; level 0 is the input). Set exactly one of the three.
struct LodLevelTarget {
    float ratio = 0.f;            // fraction of the INPUT's triangles, in (0, 1) (1 would copy level 0)
    std::size_t triangles = 0;    // triangle count
    // Largest simplifier error estimate of this level's step, relative to the input's bounding-box
    // diagonal (see SimplifyParams::max_error). Infinity = unused.
    float max_error = std::numeric_limits<float>::infinity();
};

std::vector<LodLevelTarget> lod_levels_from_ratios(const std::vector<float>& ratios);
std::vector<LodLevelTarget> lod_levels_from_triangles(const std::vector<std::size_t>& triangles);
std::vector<LodLevelTarget> lod_levels_from_errors(const std::vector<float>& max_errors);

struct LodChainParams {
    // Levels from fine to coarse: ratios and triangle counts strictly decreasing, max errors strictly
    // increasing (kinds may be mixed; then each must still be coarser than the previous target).
    std::vector<LodLevelTarget> levels;
    // Weights, border locking, seams, welding, placement and the normal limit of every step. Its targets
    // are ignored (each level sets its own). Placement::optimal leaves LodChainResult::shared empty.
    // Its extra_frames, when given, hold positions of the chain's input vertices; each step gets them
    // for its own vertices (they need Placement::half_edge).
    SimplifyParams simplify;
    bool measure = true;        // measure every level against the input with compare()
    DistanceParams distance;    // sampling of those measurements (vertex_errors is not filled)
};

struct LodLevel {
    Mesh mesh;                       // the level as a standalone mesh (level 0: the input as given)
    std::size_t triangles = 0;
    std::size_t target_triangles = 0;  // 0 for level 0 and error-driven levels
    SimplifyResult::StopReason reason = SimplifyResult::StopReason::target_reached;
    // Simplifier estimate of this step (this level against the previous one), relative to the input's
    // diagonal and in model units; `accumulated_error*` sums the steps since level 0 (the estimate of
    // the distance to the input by the triangle inequality).
    float step_error = 0, step_error_relative = 0;
    float accumulated_error = 0, accumulated_error_relative = 0;
    // Measured against the input (when LodChainParams::measure; zero for level 0).
    bool measured = false;
    DistanceResult distance;
    // This level's step in LodChainResult::sequence.collapses; replaying [0, collapses_end) gives it.
    std::size_t collapses_begin = 0, collapses_end = 0;
    // Level vertex → the input vertex it descends from (the same vertex, at the same place, with
    // half-edge placement; moved, with re-solved attributes, with optimal placement).
    std::vector<std::uint32_t> input_vertex;
};

// Range of one level in SharedLodBuffers.
struct LodIndexRange {
    std::size_t first_index = 0;   // into SharedLodBuffers::indices
    std::size_t index_count = 0;   // 3 per triangle
    std::uint32_t vertex_count = 0;  // the level uses vertices [0, vertex_count) of the shared buffer
};

// All levels over one vertex buffer. Vertices are the input vertices some level uses, ordered
// coarsest-first (those of the last level, then those only the level before uses, ...), so level k
// uses a prefix of the buffer. Attributes and materials are the input's; position_ids are left empty
// (renderers do not need them; the level meshes keep them).
struct SharedLodBuffers {
    Mesh vertices;                            // vertex arrays and materials; no faces
    std::vector<std::uint32_t> indices;       // the triangles of every level, level 0 first
    std::vector<std::uint32_t> face_materials;  // per triangle of `indices` when the input has them
    std::vector<LodIndexRange> levels;
    std::vector<std::uint32_t> input_vertex;  // shared vertex → input vertex
};

struct LodChainResult {
    std::vector<LodLevel> levels;  // levels[0] is the input, then one per LodChainParams::levels entry
    SharedLodBuffers shared;       // half-edge placement only: empty (no levels) with optimal placement
    // The collapses of every step expressed on the input (vertices and points as welded by the first
    // step): replay_collapses(input, sequence, levels[k].collapses_end) gives level k's faces in input
    // vertex indices. `sequence.mesh` is left empty; sequence.input_points is filled.
    SimplifyResult sequence;
};

// Throws Error(argument) for an empty or non-decreasing level list or a target out of range;
// Error(invalid) when the input has no triangles; Error(cancelled) when progress asks to stop
// (progress covers all levels: each step's simplification and measurement).
LodChainResult build_lod_chain(const Mesh& mesh, const LodChainParams& params, Progress* progress = nullptr);

}  // namespace lodforge
