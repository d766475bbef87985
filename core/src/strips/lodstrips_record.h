// Internal: the offline steps shared by the LODStrips builder (lodstrips_builder.cpp) and the morph strip
// recorder (morph_lodstrips.cpp): canonical vertex order, strips laid into regions, and the per-collapse
// recording loop (lodstrips_record.cpp), so both write records the runtime replays identically
// (docs/lodstrips.md: even-count removals of types 1 and 2, the freed tail repeats the last slot).
#pragma once

#include "lodforge/strips/lodstrips.h"
#include "lodforge/error.h"
#include "lodforge/mesh.h"
#include "lodforge/progress.h"
#include "lodforge/simplify/simplify.h"
#include "lodforge/strips/stripify.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lodforge::strip_replay {

using ::lodstrips::Removal;

inline bool degenerate(std::uint32_t a, std::uint32_t b, std::uint32_t c) { return a == b || b == c || a == c; }

inline std::size_t region_triangles(const std::uint32_t* p, std::uint32_t drawn) {
    std::size_t n = 0;
    for (std::uint32_t i = 0; i + 2 < drawn; ++i) n += !degenerate(p[i], p[i + 1], p[i + 2]);
    return n;
}

// Removes r.count indices at r.pos exactly as the runtime does (the live tail moves left, the freed slots
// repeat the region's last slot).
inline void remove_run(std::uint32_t* region, std::uint32_t cap, std::uint32_t& live, const Removal& r) {
    const std::uint32_t fill = region[cap - 1];
    std::move(region + r.pos + r.count, region + live, region + r.pos);
    std::fill(region + live - r.count, region + live, fill);
    live -= r.count;
}

// Finds the first removable degenerate run in the drawn part [0, drawn) of a strip, scanning from the
// start: type 1, a run of L >= 4 equal indices, keeps 2 (L even) or 3 (L odd); type 2, an alternation
// abab.. of p >= 2 pairs, keeps one pair. Only even counts are removed, so the rest of the strip keeps
// its parity (and every triangle its winding). Returns false when there is none.
inline bool find_degenerate_run(const std::uint32_t* p, std::uint32_t drawn, Removal& out) {
    std::uint32_t i = 0;
    while (i + 3 < drawn) {
        if (p[i] == p[i + 1]) {
            std::uint32_t j = i + 1;
            while (j < drawn && p[j] == p[i]) ++j;
            const std::uint32_t run = j - i;
            if (run >= 4) {
                const std::uint32_t keep = run % 2 == 0 ? 2 : 3;
                out.pos = static_cast<std::uint16_t>(i + keep);
                out.count = static_cast<std::uint16_t>(run - keep);
                out.type = 1;
                return true;
            }
            i = j - 1;
            continue;
        }
        std::uint32_t j = i + 2;
        while (j < drawn && p[j] == p[j - 2]) ++j;
        const std::uint32_t pairs = (j - i) / 2;
        if (pairs >= 2) {
            out.pos = static_cast<std::uint16_t>(i + 2);
            out.count = static_cast<std::uint16_t>(2 * (pairs - 1));
            out.type = 2;
            return true;
        }
        ++i;
    }
    return false;
}

// The file's material record of a mesh material (texture paths, factors, the base colour's UV set
// clamped to the sets the mesh has).
inline ::lodstrips::Material strip_material(const lodforge::Material& m, std::size_t texcoord_sets) {
    ::lodstrips::Material o;
    o.name = m.name;
    o.base_color[0] = m.base_color.x, o.base_color[1] = m.base_color.y, o.base_color[2] = m.base_color.z,
    o.base_color[3] = m.base_color.w;
    o.metallic = m.metallic, o.roughness = m.roughness;
    o.emissive[0] = m.emissive.x, o.emissive[1] = m.emissive.y, o.emissive[2] = m.emissive.z;
    o.double_sided = m.double_sided;
    o.base_color_texture = m.base_color_texture.path;
    o.normal_texture = m.normal_texture.path;
    o.metallic_roughness_texture = m.metallic_roughness_texture.path;
    o.occlusion_texture = m.occlusion_texture.path;
    o.emissive_texture = m.emissive_texture.path;
    o.base_color_texcoord_set =
        texcoord_sets == 0
            ? 0
            : static_cast<std::uint32_t>(std::clamp<int>(m.base_color_texture.texcoord_set, 0, static_cast<int>(texcoord_sets) - 1));
    return o;
}

// The material group of each face of `faces` (the faces a replay at level 0 keeps: a subsequence of
// mesh's faces, in order), matched back to the input faces. Throws Error(invalid), `what` first, when a
// face names a material the mesh does not have.
inline std::vector<std::uint32_t> face_groups(const Mesh& mesh, const std::vector<std::uint32_t>& faces, const char* what) {
    const std::size_t nf = faces.size() / 3;
    std::vector<std::uint32_t> group(nf, 0);
    if (mesh.face_materials.empty()) return group;
    std::size_t f = 0;
    for (std::size_t i = 0; i < nf; ++i, ++f) {
        while (f < mesh.triangle_count() &&
               !std::equal(faces.begin() + std::ptrdiff_t(3 * i), faces.begin() + std::ptrdiff_t(3 * i + 3),
                           mesh.indices.begin() + std::ptrdiff_t(3 * f)))
            ++f;
        group[i] = f < mesh.triangle_count() ? mesh.face_materials[f] : 0;
    }
    const std::size_t group_count = std::max<std::size_t>(1, mesh.materials.size());
    for (std::uint32_t g : group)
        if (g >= group_count)
            throw Error(Error::Kind::invalid, std::string(what) + ": a face names material " + std::to_string(g) +
                                                  " of " + std::to_string(mesh.materials.size()));
    return group;
}

inline constexpr std::uint32_t no_vertex = 0xFFFFFFFFu;

// Vertices a strip set over `faces` (replay at level 0) and `moves` needs: every face corner and both ends
// of every move. OR-ed into `used` (size = the mesh's vertex count), so several sequences can share it.
void mark_used(const std::vector<std::uint32_t>& faces, const std::vector<VertexMove>& moves, std::vector<std::uint8_t>& used);

// Canonical order (docs/lodstrips.md): used vertices no move removes first (input order), then the
// vertices of the last collapse, ..., the vertices of the first collapse last, so level k uses a prefix.
// Error(invalid), `what` first, when a vertex is removed twice.
struct CanonicalOrder {
    std::vector<std::uint32_t> canonical;     // input vertex → canonical vertex, no_vertex if unused
    std::vector<std::uint32_t> input_vertex;  // canonical vertex → input vertex
};
CanonicalOrder canonical_order(const std::vector<std::uint8_t>& used, const std::vector<VertexMove>& moves, const char* what);

// Colours (8-bit when every channel is exactly k/255), texcoords and materials of the canonical vertices.
void copy_attributes(const Mesh& mesh, const std::vector<std::uint32_t>& input_vertex, ::lodstrips::Data& d);

// Strips once at full detail, per material group, cut into pieces of at most max_strip_length indices at
// even positions (a piece repeats the two indices before its cut, so no triangle is lost and winding
// holds), laid into regions: restart mode, piece + restart index; degenerate mode, piece + the join to
// the next piece, padded so every region is even and every piece starts even. Needs d.vertex_count;
// fills d.restart, strip_offsets, strip_materials, initial_indices.
struct StripLayoutParams {
    StripJoin join = StripJoin::restart;
    std::size_t max_strip_length = 256;
    std::size_t cache_size = 16;
    StripOrder strip_order = StripOrder::run_off;
};
void lay_out_strips(const std::vector<std::uint32_t>& faces, const std::vector<std::uint32_t>& face_group, std::size_t groups,
                    const std::vector<std::uint32_t>& canonical, const StripLayoutParams& params, ::lodstrips::Data& d);

// The offline replay: the first `count` collapses of (collapses, moves) applied to d.initial_indices; per
// collapse every position of each removed vertex (rewritten to its target), then every degenerate run of
// the strips it touched, each removed before the next is looked for. Needs the layout fields of d; fills
// collapse_begin, targets, rewrite_begin, rewrite_positions, removal_begin, removals, triangles. Progress
// goes from `from` to `to` under `stage`.
struct RecordStats {
    std::size_t removals_type1 = 0, removals_type2 = 0;
};
RecordStats record_collapses(const std::vector<Collapse>& collapses, const std::vector<VertexMove>& moves, std::size_t count,
                             const std::vector<std::uint32_t>& canonical, ::lodstrips::Data& d, Progress* progress,
                             double from, double to, const char* stage);

}  // namespace lodforge::strip_replay
