// Vertex-clustering simplification on a uniform grid with generalized quadrics (see
// docs/simplification.md, "Vertex clustering").
//
//   ClusterParams p;  p.target_ratio = 0.1f;
//   ClusterResult r = simplify_cluster(mesh, p);   // r.mesh, r.triangles, r.reason, r.cell_size
//
// One pass over the triangles per tried resolution, no adjacency: much faster than edge collapse and
// topology-agnostic (it closes holes and merges nearby sheets), at a higher error for the same count.
// The triangle count is a step function of the cell size, so a target is approached by searching the
// cell size, and the achieved count and the reason are reported.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"
#include "lodforge/simplify/simplify.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lodforge {

struct ClusterParams {
    std::size_t target_triangles = 0;  // aim for this many triangles (0 = unused)
    float target_ratio = 0.f;          // or this fraction of the input's, in (0, 1]
    // Cells along the longest side of the bounding box; when > 0 it is used as given (no search) and the
    // targets must be unset.
    std::size_t grid_resolution = 0;
    // The search stops once the count is within this fraction of the target (and otherwise after
    // `max_passes` counting passes with the closest count found).
    float tolerance = 0.01f;
    int max_passes = 16;
    SimplifyWeights weights;  // a difference of 1 costs like a deviation of w diagonals (SimplifyWeights)
    // Keep separate wedges per cell for vertices that are not connected inside the cell (UV charts,
    // hard-normal creases, material borders), each with its own attributes; false merges them.
    bool preserve_seams = true;
};

struct ClusterResult {
    enum class StopReason {
        target_reached,   // within `tolerance` of the target
        closest,          // no cell size within tolerance: the closest count found (steps are coarse)
        grid_limit,       // the finest grid allowed (2^20 cells a side) still has fewer triangles
        resolution_given, // ClusterParams::grid_resolution was used as given
    };
    Mesh mesh;
    std::size_t triangles = 0;
    std::size_t target_triangles = 0;  // 0 when the resolution was given
    StopReason reason = StopReason::target_reached;
    float error = 0;           // largest per-cell quadric error (RMS plane distance + weighted attributes)
    float error_relative = 0;  // the same relative to the input's bounding-box diagonal
    // The grid: cell (i, j, k) is the box origin + cell_size * [i, i+1) × [j, j+1) × [k, k+1).
    Vec3f grid_origin;
    float cell_size = 0;
    std::uint32_t grid_dims[3] = {0, 0, 0};
    int passes = 0;  // counting passes of the search
    // Input vertex → output vertex it was clustered into (~0u for vertices no face uses, and for those
    // whose cluster lost all its triangles).
    std::vector<std::uint32_t> vertex_cluster;
};

// Throws Error(argument) on bad parameters, Error(invalid) when the mesh has no triangles or when every
// grid the target leads to (or the grid given) collapses it to nothing (rather than return an empty mesh),
// Error(cancelled) when progress asks to stop. Output: one vertex per occupied cell (and per wedge class
// with preserve_seams) at the quadric-optimal position clamped into its cell, attributes at their
// quadric optimum (normals renormalised, colours clamped to [0, 1]); triangles with two corners in one
// cell and repeated triangles (either winding) are dropped.
ClusterResult simplify_cluster(const Mesh& mesh, const ClusterParams& params, Progress* progress = nullptr);

}  // namespace lodforge
