// LODStrips builder: half-edge collapse sequence replayed on triangle strips.
//
// Follows Ramos, "LodStrips: continuous level of detail using triangle strips" (UJI thesis, 2008):
// canonical vertex order and W[] (§3.3), per-LOD change records and degenerate-run removal of types
// 1 and 2 (§4.2.2), records grouped per strip in one element buffer (ch. 5, the GPU variant). Collapses
// come from simplify() (Garland–Heckbert 1998 generalized quadrics, Hoppe 1999 wedges) with half-edge
// placement; strips from stripify(). Decisions (wedges, parity, strip pieces, what a LOD is) are in
// docs/lodstrips.md.
#include "lodforge/strips/lodstrips.h"

#include "lodforge/error.h"
#include "strips/lodstrips_record.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace lodforge {
namespace {

using strip_replay::find_degenerate_run;
using strip_replay::region_triangles;
using strip_replay::remove_run;

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

// Removes every degenerate run of one strip region (as the recorder does, lodstrips_record.cpp).
void reduce_region_plain(std::uint32_t* region, std::uint32_t cap, std::uint32_t& live, bool restart) {
    lodstrips::Removal r;
    while (find_degenerate_run(region, live - (restart ? 1u : 0u), r)) remove_run(region, cap, live, r);
}

}  // namespace

LodStripsBuild build_lodstrips(const Mesh& mesh, const LodStripsParams& params, Progress* progress) {
    if (mesh.triangle_count() == 0) throw Error(Error::Kind::argument, "build_lodstrips: the mesh has no triangles");
    if (params.max_strip_length < 16 || params.max_strip_length > 65000)
        throw Error(Error::Kind::argument, "build_lodstrips: max_strip_length must be in [16, 65000]");
    if (!(params.coarsest_ratio >= 0.f && params.coarsest_ratio <= 1.f))
        throw Error(Error::Kind::argument, "build_lodstrips: coarsest_ratio must be in [0, 1]");
    if (mesh.vertex_count() >= lodstrips::restart_index)
        throw Error(Error::Kind::argument, "build_lodstrips: too many vertices for 32-bit indices");

    LodStripsBuild out;
    SimplifyParams sp;
    sp.target_ratio = params.coarsest_ratio;
    sp.target_triangles = params.coarsest_triangles;
    sp.max_error = params.max_error;
    sp.weights = params.weights;
    sp.lock_border = params.lock_border;
    sp.placement = Placement::half_edge;
    check_progress(progress, 0.0, "simplifying");
    out.simplification = simplify(mesh, sp, progress);
    const SimplifyResult& s = out.simplification;
    out.reason = s.reason;
    check_progress(progress, 0.6, "stripifying");

    // Faces the simplifier starts from (it drops degenerate and repeated ones up front), matched back to
    // input faces for their materials: they are a subsequence of the input faces, in order.
    const std::vector<std::uint32_t> base = replay_collapses(mesh, s, 0);
    const std::vector<std::uint32_t> face_group = strip_replay::face_groups(mesh, base, "build_lodstrips");
    const std::size_t group_count = std::max<std::size_t>(1, mesh.materials.size());

    // Canonical order: vertices no collapse removes first (input order), then the vertices of the last
    // collapse, ..., the vertices of the first collapse last: level k uses the prefix.
    std::vector<std::uint8_t> used(mesh.vertex_count(), 0);
    strip_replay::mark_used(base, s.moves, used);
    strip_replay::CanonicalOrder order = strip_replay::canonical_order(used, s.moves, "build_lodstrips");
    out.canonical = std::move(order.canonical);
    out.input_vertex = std::move(order.input_vertex);
    const auto N = static_cast<std::uint32_t>(out.input_vertex.size());

    lodstrips::Data& d = out.data;
    d.vertex_count = N;
    d.positions.resize(3u * N);
    for (std::uint32_t c = 0; c < N; ++c) {
        const Vec3f p = mesh.positions[out.input_vertex[c]];
        d.positions[3 * c] = p.x, d.positions[3 * c + 1] = p.y, d.positions[3 * c + 2] = p.z;
    }
    if (mesh.has_normals()) {
        d.normals.resize(3u * N);
        for (std::uint32_t c = 0; c < N; ++c) {
            const Vec3f n = mesh.normals[out.input_vertex[c]];
            d.normals[3 * c] = n.x, d.normals[3 * c + 1] = n.y, d.normals[3 * c + 2] = n.z;
        }
    }
    strip_replay::copy_attributes(mesh, out.input_vertex, d);

    strip_replay::lay_out_strips(base, face_group, group_count, out.canonical,
                                 {params.join, params.max_strip_length, params.cache_size, params.strip_order}, d);
    check_progress(progress, 0.7, "recording strip changes");
    const strip_replay::RecordStats rs = strip_replay::record_collapses(s.collapses, s.moves, s.collapses.size(), out.canonical,
                                                                        d, progress, 0.7, 1.0, "recording strip changes");
    out.degenerate_runs_type1 = rs.removals_type1;
    out.degenerate_runs_type2 = rs.removals_type2;
    return out;
}

Mesh lodstrips_mesh(const lodstrips::LodStrips& rt) {
    const lodstrips::Data& d = rt.data();
    Mesh m;
    const std::size_t n = rt.vertex_count();
    m.positions.resize(n);
    for (std::size_t v = 0; v < n; ++v) m.positions[v] = {d.positions[3 * v], d.positions[3 * v + 1], d.positions[3 * v + 2]};
    if (!d.normals.empty()) {
        m.normals.resize(n);
        for (std::size_t v = 0; v < n; ++v) m.normals[v] = {d.normals[3 * v], d.normals[3 * v + 1], d.normals[3 * v + 2]};
    }
    if (!d.colors.empty()) {
        m.colors.resize(n);
        for (std::size_t v = 0; v < n; ++v)
            m.colors[v] = {d.colors[4 * v], d.colors[4 * v + 1], d.colors[4 * v + 2], d.colors[4 * v + 3]};
    }
    for (const auto& set : d.texcoords) {
        std::vector<Vec2f>& uv = m.texcoords.emplace_back(n);
        for (std::size_t v = 0; v < n; ++v) uv[v] = {set[2 * v], set[2 * v + 1]};
    }
    for (const lodstrips::Material& src : d.materials) {
        Material& mat = m.materials.emplace_back();
        mat.name = src.name;
        mat.base_color = {src.base_color[0], src.base_color[1], src.base_color[2], src.base_color[3]};
        mat.metallic = src.metallic;
        mat.roughness = src.roughness;
        mat.emissive = {src.emissive[0], src.emissive[1], src.emissive[2]};
        mat.double_sided = src.double_sided;
        mat.base_color_texture.path = src.base_color_texture;
        mat.base_color_texture.texcoord_set = static_cast<int>(src.base_color_texcoord_set);
        mat.normal_texture.path = src.normal_texture;
        mat.metallic_roughness_texture.path = src.metallic_roughness_texture;
        mat.occlusion_texture.path = src.occlusion_texture;
        mat.emissive_texture.path = src.emissive_texture;
    }
    for (std::size_t s = 0; s < rt.strip_count(); ++s) {
        const std::size_t before = m.indices.size();
        rt.append_strip_triangles(s, m.indices);
        if (!d.materials.empty()) m.face_materials.insert(m.face_materials.end(), (m.indices.size() - before) / 3, rt.strip_material(s));
    }
    return m;
}

LodStripsDependencies lodstrips_dependencies(const lodstrips::Data& d) {
    // Faces are the full-resolution strips' triangles; replay the sequence on them (indexed, canonical
    // numbers) and remember for each face the last collapse that changed it.
    lodstrips::LodStrips rt;
    std::vector<std::uint32_t> faces;
    {
        std::string why;
        if (!rt.assign(d, &why)) throw Error(Error::Kind::invalid, "lodstrips_dependencies: " + why);
        rt.triangles(faces);
    }
    const std::size_t nf = faces.size() / 3;
    std::vector<std::vector<std::uint32_t>> faces_of(d.vertex_count);
    for (std::uint32_t f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) faces_of[faces[3 * f + k]].push_back(f);
    std::vector<std::uint32_t> last(nf, kNone);
    LodStripsDependencies deps;
    deps.begin.assign(1, 0);
    const std::size_t K = d.collapse_count();
    for (std::size_t k = 0; k < K; ++k) {
        const std::size_t first = deps.parents.size();
        for (std::uint32_t o = d.collapse_begin[k]; o < d.collapse_begin[k + 1]; ++o) {
            const std::uint32_t v = d.vertex_of_ordinal(o), t = d.targets[o];
            for (std::uint32_t f : faces_of[v]) {
                // Faces that already vanished count too: applying a later collapse to a corner of a face
                // whose vanishing collapse is not applied would give the face a state it never had.
                std::uint32_t* tri = &faces[3 * f];
                if (last[f] != kNone && last[f] != k) deps.parents.push_back(last[f]);
                last[f] = static_cast<std::uint32_t>(k);
                for (int i = 0; i < 3; ++i)
                    if (tri[i] == v) tri[i] = t;
                faces_of[t].push_back(f);
            }
            faces_of[v].clear();
            faces_of[v].shrink_to_fit();
        }
        std::sort(deps.parents.begin() + static_cast<std::ptrdiff_t>(first), deps.parents.end());
        deps.parents.erase(std::unique(deps.parents.begin() + static_cast<std::ptrdiff_t>(first), deps.parents.end()),
                           deps.parents.end());
        deps.begin.push_back(static_cast<std::uint32_t>(deps.parents.size()));
    }
    return deps;
}

VariableResolution extract_variable_resolution(const lodstrips::Data& d, const LodStripsDependencies& deps,
                                               const std::function<bool(std::uint32_t)>& coarsen) {
    const std::size_t K = d.collapse_count();
    if (deps.begin.size() != K + 1) throw Error(Error::Kind::argument, "extract_variable_resolution: dependencies of another model");
    VariableResolution out;
    out.applied.assign(K, 0);
    for (std::size_t k = 0; k < K; ++k) {
        bool ok = coarsen(d.vertex_of_ordinal(d.collapse_begin[k]));
        for (std::uint32_t i = deps.begin[k]; ok && i < deps.begin[k + 1]; ++i) ok = out.applied[deps.parents[i]] != 0;
        out.applied[k] = ok;
        out.collapses_applied += ok;
    }
    // Where each vertex ends up: targets are lower numbers, so one increasing pass resolves chains.
    std::vector<std::uint32_t> final_vertex(d.vertex_count);
    std::vector<std::uint32_t> collapse_of(d.collapse_begin.back());
    for (std::size_t k = 0; k < K; ++k)
        for (std::uint32_t o = d.collapse_begin[k]; o < d.collapse_begin[k + 1]; ++o) collapse_of[o] = static_cast<std::uint32_t>(k);
    const std::uint32_t removed = d.collapse_begin.back();
    for (std::uint32_t v = 0; v < d.vertex_count; ++v) {
        const std::uint32_t o = d.vertex_count - 1 - v;
        final_vertex[v] = (o < removed && out.applied[collapse_of[o]]) ? final_vertex[d.targets[o]] : v;
    }
    out.indices = d.initial_indices;
    const std::size_t S = d.strip_count();
    out.draw_counts.resize(S);
    for (std::size_t r = 0; r < S; ++r) {
        std::uint32_t* region = out.indices.data() + d.strip_offsets[r];
        const std::uint32_t cap = d.strip_offsets[r + 1] - d.strip_offsets[r];
        for (std::uint32_t i = 0; i < cap; ++i)
            if (region[i] != lodstrips::restart_index) region[i] = final_vertex[region[i]];
        std::uint32_t live = cap;
        reduce_region_plain(region, cap, live, d.restart);
        out.draw_counts[r] = static_cast<std::int32_t>(live - (d.restart ? 1u : 0u));
        out.triangles += region_triangles(region, live - (d.restart ? 1u : 0u));
    }
    return out;
}

VariableResolution extract_variable_resolution(const lodstrips::Data& d, const LodStripsDependencies& deps,
                                               const Vec3f& center, float radius) {
    const float r2 = radius * radius;
    return extract_variable_resolution(d, deps, [&](std::uint32_t v) {
        const float dx = d.positions[3 * v] - center.x, dy = d.positions[3 * v + 1] - center.y,
                    dz = d.positions[3 * v + 2] - center.z;
        return dx * dx + dy * dy + dz * dz > r2;
    });
}

}  // namespace lodforge
