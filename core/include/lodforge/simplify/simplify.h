// In-core edge-collapse simplification with generalized quadrics (see docs/simplification.md).
//
//   SimplifyParams p;  p.target_ratio = 0.1f;
//   SimplifyResult r = simplify(mesh, p);   // r.mesh, r.reason, r.error, r.collapses
//
// Collapses are half-edge collapses on *points* (Mesh::position_ids): all wedges of the removed point move
// onto wedges of the kept point, so UV seams and hard-normal creases move together and stay welded. With
// half-edge placement (the default of SimplifyParams) the kept vertices are a subset of the input vertices
// with their attributes unchanged, which makes the collapse sequence replayable (progressive meshes,
// LODStrips), and no collapse folds a surviving face's UV triangle (in a texcoord set with a weight) over
// or flat; optimal placement moves them and re-solves their attributes (lower error, see Placement).
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace lodforge {

// Attribute weights: attributes are compared in their natural units (normals: unit vectors, colours:
// [0, 1] RGBA, texcoords: UV units), geometry in units of the bounding-box diagonal. 0 ignores the
// attribute. Edge collapse (simplify()): the attribute error is measured against the size of the region
// a collapse disturbs, so a weight w makes an attribute difference of 1 across a region of size d cost as
// much as a geometric deviation of 10 w d (the default colour weight is meshoptimizer's 1.0 on that scale,
// the normal weight 0.2 instead of its 0.5: measured, docs/simplification.md "Attribute fidelity");
// clustering and the octree: as much as a deviation of w diagonals.
struct SimplifyWeights {
    float normal = 0.02f;
    float color = 0.1f;
    float texcoord = 0.1f;                // every texcoord set without an entry in `texcoord_sets`
    std::vector<float> texcoord_sets;     // per-set override, index = set
};

enum class Placement {
    half_edge,  // the removed point moves onto the kept one (vertex subset; replayable sequence)
    optimal,    // the kept point moves to the quadric-optimal position and every wedge of it gets the
                // attributes minimising its attribute quadric there (Hoppe 1999; normals renormalised,
                // colours clamped to [0, 1], a wedge with an empty quadric keeps its value); the cost is
                // taken at those attributes. Lower error; positions and attributes change, so levels
                // cannot share one vertex buffer (the collapse sequence still reproduces the connectivity)
};

struct SimplifyParams {
    std::size_t target_triangles = 0;  // stop at or below this many triangles (0 = unused)
    float target_ratio = 0.f;          // or at this fraction of the input triangles (0 = unused)
    // Stop before a collapse whose error estimate (Q/weight, square-rooted) exceeds this, relative to the
    // bounding-box diagonal of the input. Infinity = no limit. With neither target set the error alone
    // decides. When both targets are set, the larger triangle count wins.
    float max_error = std::numeric_limits<float>::infinity();
    SimplifyWeights weights;
    bool lock_border = false;     // border points are never removed (else they slide along the border)
    bool preserve_seams = true;   // a seam point only moves along its seam; false lets seams close
    bool weld = true;             // also treat vertices at bit-identical positions as one point (glTF)
    Placement placement = Placement::half_edge;
    // Order of the collapses. passes (default): rounds of independent cheapest-first collapses, each
    // point touched at most once per round (fast; meshoptimizer's scheme). greedy: one global priority
    // queue, always the cheapest valid collapse next (slower; kept for comparison). Both give replayable
    // sequences with the prefix property (a run to a lower target starts with a higher target's run).
    enum class Schedule { passes, greedy };
    Schedule schedule = Schedule::passes;
    // A collapse is refused when it turns a face's normal by more than acos(min_normal_dot).
    float min_normal_dot = 0.2f;
    // Weight of each face's plane in the quadrics (and of its attribute quadric): its area (Garland &
    // Heckbert) or the square root of its area (meshoptimizer's choice). The cost stays a weighted mean of
    // squared distances either way; sqrt_area gives small faces more say. With height_weight 0.3 it lowers
    // the maximum error on most cells measured, at ~28 % more instructions (docs/simplification.md,
    // "Hausdorff against meshopt"); the defaults keep the previous behaviour.
    enum class AreaWeight { area, sqrt_area };
    AreaWeight area_weight = AreaWeight::area;
    // Pass schedule, half-edge (extra frames: frame 0's geometry): each point carries a bound on how far the region it stands
    // for may be from its faces (grown by the height of every point collapsed onto it), and the order of
    // collapses adds height_weight × (bound + height of the removed point over its fan)², in squared
    // diagonals, to the quadric cost. Only the order changes: `error`, `error_relative` and max_error stay
    // the quadric's. 0 (the default) = the quadric order alone; 0.3 is the measured setting.
    float height_weight = 0.f;
    // Morphing meshes (docs/morph.md): further positions of the same vertices, one array per frame (the
    // mesh's own positions are frame 0). Each frame gets its own plane quadrics; a collapse's geometric
    // cost is combined over all frames (attributes count once, from the mesh) and the flip and needle
    // checks hold in every frame, so one collapse order serves every frame. Needs Placement::half_edge;
    // the arrays must outlive the call. Empty (the default) leaves the simplifier exactly as it was.
    std::vector<const std::vector<Vec3f>*> extra_frames;
    enum class FrameCost {
        max,  // the worst frame's cost
        sum,  // the sum over frames, divided by the frame count (so max_error keeps its meaning)
    };
    FrameCost frame_cost = FrameCost::max;
    // Factor on the extra frames' excess cost over frame 0 (finite, >= 0): 0 lets only their flip checks
    // act, 1 counts them as much as frame 0 (skinned poses, SkinCostParams::weight).
    float frame_weight = 1.f;
    // Artist control (docs/artist-control.md), one entry per input vertex; empty = none. Vertices at one
    // point (wedges, welded positions) are resolved per point: the largest importance, locked if any is.
    // importance in [0, 1]: the cost of removing a point is multiplied by 1 + importance_scale x its
    // importance (the kept point inherits the larger importance); optimal placement also counts the kept
    // point's. The cost is a squared distance, so the default 99 holds a fully painted region to about a
    // tenth of the error of the rest at the same cost; the error estimates (max_error, SimplifyResult::error)
    // are of the scaled cost. The fast geometry-only paths are skipped when importance is given.
    std::vector<float> importance;
    float importance_scale = 99.f;
    // Nonzero: the vertex's point is never removed and never moves (optimal placement puts an edge with a
    // locked end at that end); its vertices keep their input position and attributes bit for bit.
    std::vector<std::uint8_t> lock;
    // Cost factor per seam class (index: SeamClass, lodforge/simplify/seams.h; empty or 1 = none): removing
    // a point on a seam of a class costs that many times more (the largest factor of its classes), as
    // importance does; parse_seam_weights() reads them from the CLI's --seams.
    std::vector<float> seam_weights;
};

// One point collapse: every vertex (wedge) of point `from_point` moves onto a vertex of `to_point`.
// Indices are into the input mesh (vertices, and points as welded: SimplifyResult::input_points).
struct Collapse {
    std::uint32_t from_point = 0;
    std::uint32_t to_point = 0;
    std::uint32_t moves_begin = 0;  // range [moves_begin, moves_end) of SimplifyResult::moves
    std::uint32_t moves_end = 0;
};

struct VertexMove {
    std::uint32_t from = 0;  // input vertex removed
    std::uint32_t to = 0;    // input vertex that replaces it in every face
};

struct SimplifyResult {
    enum class StopReason {
        target_reached,  // the triangle target was reached
        error_limit,     // the next collapse would exceed max_error
        topology_limit,  // no valid collapse left (locked borders, seams, flips, closed small shells)
    };
    Mesh mesh;
    std::size_t triangles = 0;
    float error = 0;           // largest collapse error estimate, model units
    float error_relative = 0;  // the same relative to the input's bounding-box diagonal
    StopReason reason = StopReason::target_reached;
    std::size_t target_triangles = 0;  // the triangle target used (at least 1 for a ratio; 0 with max_error alone)
    // Input faces dropped before simplifying (degenerate on points, or repeating an earlier face's points):
    // why a mesh can end below its target, "target reached", without any collapse.
    std::size_t dropped_faces = 0;
    std::vector<Collapse> collapses;        // in order: replaying the first k gives level k
    std::vector<VertexMove> moves;
    std::vector<std::uint32_t> vertex_map;  // output vertex → input vertex
    std::vector<std::uint32_t> input_points;  // input vertex → point id used (position_ids + welding)
};

// Throws Error(argument) on bad parameters, Error(cancelled) when progress asks to stop. Input faces that
// are degenerate on points (two corners on one point) or repeat an earlier face's three points
// (either winding) are dropped. Output vertices keep the input order
// (one vertex per point first, extra wedges after, as Mesh requires) and faces the input order.
SimplifyResult simplify(const Mesh& mesh, const SimplifyParams& params, Progress* progress = nullptr);

// Index buffer (input vertex indices) after replaying the first `k` collapses of `result` on `input`:
// faces keep the input order; faces simplify() drops up front are absent, and a face disappears once two
// of its corners are on one point. For
// Placement::half_edge, replaying all collapses gives exactly result.mesh's faces (through vertex_map).
std::vector<std::uint32_t> replay_collapses(const Mesh& input, const SimplifyResult& result, std::size_t k);

// Derives position_ids so that vertices at the same position are one point: existing ids are kept
// (merged further), and vertices closer than `tolerance` (0 = bit-identical positions) are joined and
// snapped to the first one's position. Returns the mesh re-laid out as Mesh requires (one vertex per
// point first); faces and attributes are unchanged.
Mesh weld_seams(const Mesh& mesh, float tolerance = 0.f);

}  // namespace lodforge
