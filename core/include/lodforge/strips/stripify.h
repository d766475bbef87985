// Triangle strips for a triangle mesh, vertex-cache aware (see docs/stripify.md).
//
//   StripifyParams p;  p.join = StripJoin::restart;
//   StripifyResult r = stripify(mesh, p);   // r.indices (one buffer), r.strips (one list per strip)
//
// Every non-degenerate input triangle is drawn exactly once, with its input winding: the triangle at an
// odd position of a strip is read with its first two indices swapped (the OpenGL / Direct3D rule), and the
// result is a cyclic rotation of the input triangle. Degenerate input triangles (a repeated index) are
// dropped and counted. The algorithm orders triangles for the vertex cache first (optional), then grows
// strips along that order; docs/stripify.md has the details and the measurements.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"
#include "lodforge/strips/vertex_cache.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace lodforge {

enum class StripJoin {
    restart,     // strips separated by restart_index (0xFFFFFFFF); draw with primitive restart enabled
    degenerate,  // one strip: strips joined by repeating the last and first index (two, or three to keep
                 // the next strip on an even position so its winding stays right)
};

// Which triangle order the strips grow along (both skipped with optimize_cache = false).
enum class StripOrder {
    // lodforge's Forsyth variant that lets the order run off in strips: the fewest strips and indices and
    // the lower ACMR for a 16-entry cache (what LODStrips uses).
    run_off,
    // meshoptimizer's meshopt_optimizeVertexCacheStrip order, strips grown in a wider window: a few more
    // indices, the lower ACMR for a 32-entry cache; on the benchmark models it has fewer indices than
    // meshopt_stripify on that order and no worse ACMR at 16 and 32 (docs/stripify.md).
    cache,
};

// StripifyParams::window value meaning "the order's own default" (1 for run_off, 5 for cache).
inline constexpr std::size_t default_window = std::size_t(-1);

struct StripifyParams {
    StripJoin join = StripJoin::restart;
    StripOrder order = StripOrder::run_off;
    // FIFO cache size the triangle order is tuned for (sizes above 64 order as 64) and the reported ACMR is
    // measured with (>= 3).
    std::size_t cache_size = 16;
    // Reorder triangles for the vertex cache before growing strips. Without it, strips follow the input
    // order, which is only good when the input is already cache-ordered.
    bool optimize_cache = true;
    // How far a strip may leave the cache order: it may take a triangle whose rank in the order is below
    // (first unstripped rank) + window + (triangles the strip already holds), a window that slides as the
    // strip consumes the order. 1 follows the order closely (best ACMR with the run_off order, and on scans
    // also the fewest indices: docs/stripify.md); 0 means unlimited (long strips that ignore the order, ACMR
    // near 1); default_window picks 1 for run_off and 5 for cache (measured best, docs/stripify.md).
    std::size_t window = default_window;
};

struct StripifyResult {
    std::vector<std::uint32_t> indices;             // the buffer to draw, in the chosen join mode
    std::vector<std::vector<std::uint32_t>> strips; // each strip alone, starting on an even position
    StripJoin join = StripJoin::restart;
    std::size_t triangles = 0;             // triangles drawn (= input triangles - degenerate_dropped)
    std::size_t degenerate_dropped = 0;    // input triangles with a repeated index, not drawn
    std::size_t swaps = 0;                 // extra indices inserted inside strips to turn (a b a c)
    double indices_per_triangle = 0;       // indices.size() / triangles
    double acmr = 0;                       // FIFO ACMR of `indices` at params.cache_size
};

// The mesh's triangles (Mesh::indices) as strips. Throws Error(Kind::argument) for out-of-range indices,
// an index count that is not a multiple of 3, cache_size < 3, or a vertex count that reaches
// restart_index; Error(Kind::cancelled) when progress asks to stop.
StripifyResult stripify(const Mesh& mesh, const StripifyParams& params = {}, Progress* progress = nullptr);
StripifyResult stripify(std::span<const std::uint32_t> indices, std::size_t vertex_count,
                        const StripifyParams& params = {}, Progress* progress = nullptr);

// Forsyth-style vertex cache order of a triangle list (used by stripify): the triangles of `indices`,
// reordered, windings unchanged (degenerate triangles are kept). Exposed for tests and benchmarks.
std::vector<std::uint32_t> optimize_vertex_cache(std::span<const std::uint32_t> indices, std::size_t vertex_count,
                                                 std::size_t cache_size = 16);

}  // namespace lodforge
