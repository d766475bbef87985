// LODStrips: continuous level of detail on triangle strips (see docs/lodstrips.md).
//
//   LodStripsParams p;  p.join = StripJoin::restart;
//   LodStripsBuild b = build_lodstrips(mesh, p);     // b.data: vertices, strips, collapse records
//   write_lodstrips(b.data, "bunny.lodstrips");
//   lodstrips::LodStrips rt;  rt.assign(b.data);       // the runtime of lodstrips_runtime.h
//   rt.go_to_lod(0.5);
//
// The builder simplifies with half-edge collapses (simplify(), Placement::half_edge), numbers the vertices
// so that the coarsest level uses a prefix, stripifies once at full resolution, replays the whole
// collapse sequence on the strips and records, per collapse, every strip position to rewrite and every
// degenerate run to remove. The runtime applies the records forward and in exact reverse.
#pragma once

#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/mesh.h"
#include "lodforge/progress.h"
#include "lodforge/simplify/simplify.h"
#include "lodforge/strips/stripify.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace lodforge {

struct LodStripsParams {
    StripJoin join = StripJoin::restart;
    SimplifyWeights weights;
    // The coarsest stored level: simplify down to this fraction of the input triangles, or this many
    // triangles (the larger count wins; both 0 = as far as the simplifier can go), or until the next
    // collapse's error exceeds max_error (relative to the bounding-box diagonal).
    float coarsest_ratio = 0.01f;
    std::size_t coarsest_triangles = 0;
    float max_error = std::numeric_limits<float>::infinity();
    bool lock_border = false;
    // Strips are cut into pieces of at most this many indices (>= 16, <= 65534), which bounds the tail a
    // removal moves at run time and lets positions fit 16 bits.
    std::size_t max_strip_length = 256;
    std::size_t cache_size = 16;
    // run_off: fewest indices (the file is smaller); cache: meshoptimizer's cache order, a few more
    // indices for a lower ACMR at 32 entries (docs/stripify.md).
    StripOrder strip_order = StripOrder::run_off;
};

struct LodStripsBuild {
    lodstrips::Data data;
    SimplifyResult simplification;             // collapses + moves (input indices), for replay_collapses
    std::vector<std::uint32_t> canonical;      // input vertex -> canonical vertex, UINT32_MAX if unused
    std::vector<std::uint32_t> input_vertex;   // canonical vertex -> input vertex
    SimplifyResult::StopReason reason = SimplifyResult::StopReason::target_reached;
    std::size_t degenerate_runs_type1 = 0;
    std::size_t degenerate_runs_type2 = 0;
};

// Throws Error(argument) for bad parameters or a mesh without triangles, Error(cancelled) on request.
LodStripsBuild build_lodstrips(const Mesh& mesh, const LodStripsParams& params = {}, Progress* progress = nullptr);

// Storage figures of a model as written by write_lodstrips.
struct LodStripsStorage {
    std::size_t file_bytes = 0;
    std::size_t vertex_bytes = 0;      // the VERT section: the vertex records
    std::size_t strip_bytes = 0;       // STRP
    std::size_t change_bytes = 0;      // COLL
    std::size_t indexed_mesh_bytes = 0;  // vertex_bytes + 12 bytes per full-resolution triangle
    double ratio_to_indexed = 0;       // file_bytes / indexed_mesh_bytes
};

// The file image (format in docs/formats/lodstrips.md). Throws Error(invalid) for data the runtime would refuse.
std::vector<std::uint8_t> encode_lodstrips(const lodstrips::Data& data);
LodStripsStorage lodstrips_storage(const lodstrips::Data& data);
// Writes through AtomicFile; Error(io) names the file.
void write_lodstrips(const lodstrips::Data& data, const std::string& path);
// Reads, checks and decodes; Error(io) / Error(format) name the file and the problem.
lodstrips::Data read_lodstrips(const std::string& path);

// The mesh a runtime draws now: the vertices it can reference (a prefix of the canonical order, all
// attributes and materials) and its triangles with their materials.
Mesh lodstrips_mesh(const lodstrips::LodStrips& runtime);

// Variable resolution (docs/lodstrips.md, "Variable resolution"). Records are positional, so only prefixes
// of the sequence can be reached incrementally; a per-vertex selection is extracted instead from the
// full-resolution strips, with the collapses chosen closed under their dependencies: a collapse is
// applied only when the criterion asks for it and every earlier collapse it depends on is applied
// (collapse j depends on i < j when i was the last collapse to change a face that j changes).
struct LodStripsDependencies {
    std::vector<std::uint32_t> begin;    // collapse_count + 1
    std::vector<std::uint32_t> parents;  // earlier collapses each collapse depends on
};
LodStripsDependencies lodstrips_dependencies(const lodstrips::Data& data);

struct VariableResolution {
    std::vector<std::uint8_t> applied;     // per collapse
    std::vector<std::uint32_t> indices;    // element buffer, same layout as the runtime's
    std::vector<std::int32_t> draw_counts; // per strip
    std::size_t triangles = 0;
    std::size_t collapses_applied = 0;
};
// `coarsen(v)` is asked for the vertex each collapse removes (its first removed vertex, canonical).
VariableResolution extract_variable_resolution(const lodstrips::Data& data, const LodStripsDependencies& deps,
                                               const std::function<bool(std::uint32_t vertex)>& coarsen);
// The usual criterion: coarsen what lies farther than `radius` from `center`.
VariableResolution extract_variable_resolution(const lodstrips::Data& data, const LodStripsDependencies& deps,
                                               const Vec3f& center, float radius);

}  // namespace lodforge
