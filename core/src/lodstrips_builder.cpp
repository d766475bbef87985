// LODStrips builder: half-edge collapse sequence replayed on triangle strips.
//
// Follows Ramos, "LodStrips: continuous level of detail using triangle strips" (UJI thesis, 2008):
// canonical vertex order and W[] (§3.3), per-LOD change records and degenerate-run removal of types
// 1 and 2 (§4.2.2), records grouped per strip in one element buffer (ch. 5, the GPU variant). Collapses
// come from simplify() (Garland–Heckbert 1998 generalized quadrics, Hoppe 1999 wedges) with half-edge
// placement; strips from stripify(). Decisions (wedges, parity, strip pieces, what a LOD is) are in
// docs/lodstrips.md.
#include "lodforge/lodstrips.h"

#include "lodforge/error.h"
#include "lodstrips_record.h"

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

// Removes every degenerate run of one strip region; `record` sees each removal in order.
template <class F>
void reduce_region(std::uint32_t* region, std::uint32_t cap, std::uint32_t& live, bool restart, F&& record) {
    lodstrips::Removal r;
    while (find_degenerate_run(region, live - (restart ? 1u : 0u), r)) {
        record(r);
        remove_run(region, cap, live, r);
    }
}

void reduce_region_plain(std::uint32_t* region, std::uint32_t cap, std::uint32_t& live, bool restart) {
    reduce_region(region, cap, live, restart, [](const lodstrips::Removal&) {});
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
    const std::size_t nf = base.size() / 3;
    const std::vector<std::uint32_t> face_group = strip_replay::face_groups(mesh, base, "build_lodstrips");
    const std::size_t group_count = std::max<std::size_t>(1, mesh.materials.size());

    // Canonical order: vertices no collapse removes first (input order), then the vertices of the last
    // collapse, ..., the vertices of the first collapse last: level k uses the prefix.
    const std::size_t nv = mesh.vertex_count();
    std::vector<std::uint8_t> used(nv, 0);
    for (std::uint32_t v : base) used[v] = 1;
    std::vector<std::uint8_t> removed(nv, 0);
    for (const VertexMove& m : s.moves) {
        if (removed[m.from]) throw Error(Error::Kind::invalid, "build_lodstrips: vertex " + std::to_string(m.from) + " removed twice");
        removed[m.from] = 1;
        used[m.from] = used[m.to] = 1;
    }
    std::size_t kept = 0, total = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        kept += used[v] && !removed[v];
        total += used[v];
    }
    out.canonical.assign(nv, kNone);
    out.input_vertex.assign(total, 0);
    {
        std::uint32_t next = 0;
        for (std::size_t v = 0; v < nv; ++v)
            if (used[v] && !removed[v]) out.canonical[v] = next++;
        std::uint32_t ordinal = 0;
        for (const VertexMove& m : s.moves) out.canonical[m.from] = static_cast<std::uint32_t>(total - 1 - ordinal++);
        for (std::size_t v = 0; v < nv; ++v)
            if (out.canonical[v] != kNone) out.input_vertex[out.canonical[v]] = static_cast<std::uint32_t>(v);
    }
    const std::uint32_t N = static_cast<std::uint32_t>(total);

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
    if (mesh.has_colors()) {
        d.colors.resize(4u * N);
        d.colors_8bit = true;
        for (std::uint32_t c = 0; c < N; ++c) {
            const Vec4f col = mesh.colors[out.input_vertex[c]];
            const float ch[4] = {col.x, col.y, col.z, col.w};
            for (int k = 0; k < 4; ++k) {
                d.colors[4 * c + k] = ch[k];
                const float q = std::round(ch[k] * 255.f);
                if (!(q >= 0.f && q <= 255.f) || q / 255.f != ch[k]) d.colors_8bit = false;
            }
        }
    }
    d.texcoords.resize(mesh.texcoords.size());
    for (std::size_t t = 0; t < mesh.texcoords.size(); ++t) {
        d.texcoords[t].resize(2u * N);
        for (std::uint32_t c = 0; c < N; ++c) {
            const Vec2f uv = mesh.texcoords[t][out.input_vertex[c]];
            d.texcoords[t][2 * c] = uv.x, d.texcoords[t][2 * c + 1] = uv.y;
        }
    }
    for (const Material& m : mesh.materials) d.materials.push_back(strip_replay::strip_material(m, mesh.texcoords.size()));

    // Stripify once at full resolution, per material; cut strips into pieces at even positions (the
    // piece after a cut repeats the two indices before it, so no triangle is lost and parity holds).
    const std::uint32_t piece = static_cast<std::uint32_t>(params.max_strip_length & ~std::size_t(1));
    std::vector<std::vector<std::uint32_t>> pieces;
    std::vector<std::uint32_t> piece_material;
    for (std::uint32_t g = 0; g < group_count; ++g) {
        std::vector<std::uint32_t> tri;
        for (std::size_t f = 0; f < nf; ++f)
            if (face_group[f] == g)
                for (int k = 0; k < 3; ++k) tri.push_back(out.canonical[base[3 * f + k]]);
        if (tri.empty()) continue;
        StripifyParams stp;
        stp.join = StripJoin::restart;
        stp.cache_size = params.cache_size;
        const StripifyResult r = stripify(tri, N, stp);
        for (const auto& strip : r.strips) {
            std::size_t start = 0;
            while (strip.size() - start > piece) {
                pieces.emplace_back(strip.begin() + start, strip.begin() + start + piece);
                piece_material.push_back(g);
                start += piece - 2;
            }
            pieces.emplace_back(strip.begin() + start, strip.end());
            piece_material.push_back(g);
        }
    }

    // Regions: restart mode, piece + restart index; degenerate mode, piece + join to the next piece (its
    // last and the next first index, one more to keep every region even so each piece starts even).
    d.restart = params.join == StripJoin::restart;
    d.strip_offsets.assign(1, 0);
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        std::vector<std::uint32_t>& buf = d.initial_indices;
        buf.insert(buf.end(), pieces[i].begin(), pieces[i].end());
        if (d.restart) {
            buf.push_back(lodstrips::restart_index);
        } else {
            const std::uint32_t len = static_cast<std::uint32_t>(pieces[i].size());
            if (i + 1 < pieces.size()) {
                buf.push_back(pieces[i].back());
                buf.push_back(pieces[i + 1].front());
                if ((len + 2) % 2) buf.push_back(pieces[i + 1].front());
            } else if (len % 2) {
                buf.push_back(pieces[i].back());
            }
        }
        d.strip_offsets.push_back(static_cast<std::uint32_t>(buf.size()));
        d.strip_materials.push_back(piece_material[i]);
    }
    const std::size_t S = pieces.size();
    pieces.clear();

    // Offline replay of the whole sequence on the strips.
    std::vector<std::uint32_t> buf = d.initial_indices;
    std::vector<std::uint32_t> live(S);
    for (std::size_t r = 0; r < S; ++r) live[r] = d.strip_offsets[r + 1] - d.strip_offsets[r];
    auto cap = [&](std::size_t r) { return d.strip_offsets[r + 1] - d.strip_offsets[r]; };
    auto drawn = [&](std::size_t r) { return live[r] - (d.restart ? 1u : 0u); };
    std::vector<std::vector<std::uint32_t>> strips_of(N);
    for (std::size_t r = 0; r < S; ++r)
        for (std::uint32_t e = d.strip_offsets[r]; e < d.strip_offsets[r + 1]; ++e) {
            const std::uint32_t v = buf[e];
            if (v == lodstrips::restart_index) continue;
            if (strips_of[v].empty() || strips_of[v].back() != r) strips_of[v].push_back(static_cast<std::uint32_t>(r));
        }
    std::size_t tris = 0;
    for (std::size_t r = 0; r < S; ++r) tris += region_triangles(buf.data() + d.strip_offsets[r], drawn(r));

    const std::size_t K = s.collapses.size();
    d.collapse_begin.assign(1, 0);
    d.rewrite_begin.assign(1, 0);
    d.removal_begin.assign(1, 0);
    d.triangles.assign(1, static_cast<std::uint32_t>(tris));
    std::vector<std::uint32_t> touched;
    for (std::size_t k = 0; k < K; ++k) {
        if (k % 4096 == 0) check_progress(progress, 0.7 + 0.3 * double(k) / double(K), "recording strip changes");
        const Collapse& c = s.collapses[k];
        touched.clear();
        for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m)
            for (std::uint32_t r : strips_of[out.canonical[s.moves[m].from]]) touched.push_back(r);
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        std::size_t before = 0;
        for (std::uint32_t r : touched) before += region_triangles(buf.data() + d.strip_offsets[r], drawn(r));
        for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m) {
            const std::uint32_t v = out.canonical[s.moves[m].from], t = out.canonical[s.moves[m].to];
            d.targets.push_back(t);
            std::sort(strips_of[v].begin(), strips_of[v].end());  // records in strip order, as the file has them
            for (std::uint32_t r : strips_of[v]) {
                std::uint32_t* region = buf.data() + d.strip_offsets[r];
                // Degenerate mode rewrites the fill too: it repeats the last index and must keep doing so.
                const std::uint32_t end = d.restart ? drawn(r) : cap(r);
                for (std::uint32_t i = 0; i < end; ++i)
                    if (region[i] == v) {
                        region[i] = t;
                        d.rewrite_positions.push_back(d.strip_offsets[r] + i);
                    }
                if (std::find(strips_of[t].begin(), strips_of[t].end(), r) == strips_of[t].end()) strips_of[t].push_back(r);
            }
            strips_of[v].clear();
            strips_of[v].shrink_to_fit();
            d.rewrite_begin.push_back(static_cast<std::uint32_t>(d.rewrite_positions.size()));
        }
        std::size_t after = 0;
        for (std::uint32_t r : touched) {
            std::uint32_t* region = buf.data() + d.strip_offsets[r];
            reduce_region(region, cap(r), live[r], d.restart, [&](const lodstrips::Removal& rm) {
                lodstrips::Removal x = rm;
                x.strip = r;
                d.removals.push_back(x);
                ++(x.type == 1 ? out.degenerate_runs_type1 : out.degenerate_runs_type2);
            });
            after += region_triangles(region, drawn(r));
        }
        tris = tris - before + after;
        d.collapse_begin.push_back(static_cast<std::uint32_t>(d.targets.size()));
        d.removal_begin.push_back(static_cast<std::uint32_t>(d.removals.size()));
        d.triangles.push_back(static_cast<std::uint32_t>(tris));
    }
    check_progress(progress, 1.0, "recording strip changes");
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
