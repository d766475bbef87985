// The offline LODStrips steps shared by the builder and the morph strip recorder: canonical vertex order,
// strips laid into regions, and the per-collapse change records.
//
// Follows Ramos, "LodStrips: continuous level of detail using triangle strips" (UJI thesis, 2008):
// canonical vertex order and W[] (§3.3), per-LOD change records and degenerate-run removal of types 1 and
// 2 (§4.2.2), records grouped per strip in one element buffer (ch. 5). Decisions in docs/lodstrips.md.
#include "strips/lodstrips_record.h"

#include <algorithm>
#include <string>

namespace lodforge::strip_replay {

void mark_used(const std::vector<std::uint32_t>& faces, const std::vector<VertexMove>& moves, std::vector<std::uint8_t>& used) {
    for (std::uint32_t v : faces) used[v] = 1;
    for (const VertexMove& m : moves) used[m.from] = used[m.to] = 1;
}

CanonicalOrder canonical_order(const std::vector<std::uint8_t>& used, const std::vector<VertexMove>& moves, const char* what) {
    const std::size_t nv = used.size();
    std::vector<std::uint8_t> removed(nv, 0);
    for (const VertexMove& m : moves) {
        if (removed[m.from]) throw Error(Error::Kind::invalid, std::string(what) + ": vertex " + std::to_string(m.from) + " removed twice");
        removed[m.from] = 1;
    }
    const auto total = static_cast<std::uint32_t>(std::count(used.begin(), used.end(), std::uint8_t(1)));
    CanonicalOrder out;
    out.canonical.assign(nv, no_vertex);
    out.input_vertex.assign(total, 0);
    std::uint32_t next = 0;
    for (std::size_t v = 0; v < nv; ++v)
        if (used[v] && !removed[v]) out.canonical[v] = next++;
    for (std::size_t o = 0; o < moves.size(); ++o) out.canonical[moves[o].from] = total - 1 - static_cast<std::uint32_t>(o);
    for (std::size_t v = 0; v < nv; ++v)
        if (out.canonical[v] != no_vertex) out.input_vertex[out.canonical[v]] = static_cast<std::uint32_t>(v);
    return out;
}

void copy_attributes(const Mesh& mesh, const std::vector<std::uint32_t>& input_vertex, ::lodstrips::Data& d) {
    const std::size_t n = input_vertex.size();
    if (mesh.has_colors()) {
        d.colors.resize(4u * n);
        d.colors_8bit = true;
        for (std::size_t c = 0; c < n; ++c) {
            const Vec4f col = mesh.colors[input_vertex[c]];
            const float ch[4] = {col.x, col.y, col.z, col.w};
            for (std::size_t k = 0; k < 4; ++k) {
                d.colors[4 * c + k] = ch[k];
                const float q = std::round(ch[k] * 255.f);
                if (!(q >= 0.f && q <= 255.f) || q / 255.f != ch[k]) d.colors_8bit = false;
            }
        }
    }
    d.texcoords.resize(mesh.texcoords.size());
    for (std::size_t t = 0; t < mesh.texcoords.size(); ++t) {
        d.texcoords[t].resize(2u * n);
        for (std::size_t c = 0; c < n; ++c) {
            const Vec2f uv = mesh.texcoords[t][input_vertex[c]];
            d.texcoords[t][2 * c] = uv.x, d.texcoords[t][2 * c + 1] = uv.y;
        }
    }
    for (const Material& m : mesh.materials) d.materials.push_back(strip_material(m, mesh.texcoords.size()));
}

void lay_out_strips(const std::vector<std::uint32_t>& faces, const std::vector<std::uint32_t>& face_group, std::size_t groups,
                    const std::vector<std::uint32_t>& canonical, const StripLayoutParams& params, ::lodstrips::Data& d) {
    const std::size_t nf = faces.size() / 3;
    const auto piece = static_cast<std::uint32_t>(params.max_strip_length & ~std::size_t(1));
    std::vector<std::vector<std::uint32_t>> pieces;
    d.strip_materials.clear();
    for (std::uint32_t g = 0; g < groups; ++g) {
        std::vector<std::uint32_t> tri;
        for (std::size_t f = 0; f < nf; ++f)
            if (face_group[f] == g)
                for (std::size_t c = 0; c < 3; ++c) tri.push_back(canonical[faces[3 * f + c]]);
        if (tri.empty()) continue;
        StripifyParams sp;
        sp.join = StripJoin::restart;
        sp.cache_size = params.cache_size;
        sp.order = params.strip_order;
        for (const auto& strip : stripify(tri, d.vertex_count, sp).strips) {
            std::size_t at = 0;
            for (; strip.size() - at > piece; at += piece - 2) {
                pieces.emplace_back(strip.begin() + std::ptrdiff_t(at), strip.begin() + std::ptrdiff_t(at + piece));
                d.strip_materials.push_back(g);
            }
            pieces.emplace_back(strip.begin() + std::ptrdiff_t(at), strip.end());
            d.strip_materials.push_back(g);
        }
    }
    d.restart = params.join == StripJoin::restart;
    d.strip_offsets.assign(1, 0);
    std::vector<std::uint32_t>& buf = d.initial_indices;
    buf.clear();
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        buf.insert(buf.end(), pieces[i].begin(), pieces[i].end());
        const std::size_t len = pieces[i].size();
        if (d.restart) {
            buf.push_back(::lodstrips::restart_index);
        } else if (i + 1 < pieces.size()) {
            buf.push_back(pieces[i].back());
            buf.push_back(pieces[i + 1].front());
            if (len % 2) buf.push_back(pieces[i + 1].front());
        } else if (len % 2) {
            buf.push_back(pieces[i].back());
        }
        d.strip_offsets.push_back(static_cast<std::uint32_t>(buf.size()));
    }
}

RecordStats record_collapses(const std::vector<Collapse>& collapses, const std::vector<VertexMove>& moves, std::size_t count,
                             const std::vector<std::uint32_t>& canonical, ::lodstrips::Data& d, Progress* progress,
                             double from, double to, const char* stage) {
    RecordStats stats;
    const std::size_t S = d.strip_count();
    const std::uint32_t N = d.vertex_count;
    std::vector<std::uint32_t> buf = d.initial_indices;
    std::vector<std::uint32_t> live(S);
    for (std::size_t r = 0; r < S; ++r) live[r] = d.strip_offsets[r + 1] - d.strip_offsets[r];
    auto cap = [&](std::size_t r) { return d.strip_offsets[r + 1] - d.strip_offsets[r]; };
    auto drawn = [&](std::size_t r) { return live[r] - (d.restart ? 1u : 0u); };
    std::vector<std::vector<std::uint32_t>> strips_of(N);  // strips holding each vertex (sorted on use)
    for (std::size_t r = 0; r < S; ++r)
        for (std::uint32_t e = d.strip_offsets[r]; e < d.strip_offsets[r + 1]; ++e) {
            const std::uint32_t v = buf[e];
            if (v == ::lodstrips::restart_index) continue;
            if (strips_of[v].empty() || strips_of[v].back() != r) strips_of[v].push_back(static_cast<std::uint32_t>(r));
        }
    std::size_t tris = 0;
    for (std::size_t r = 0; r < S; ++r) tris += region_triangles(buf.data() + d.strip_offsets[r], drawn(r));

    d.collapse_begin.assign(1, 0);
    d.rewrite_begin.assign(1, 0);
    d.removal_begin.assign(1, 0);
    d.triangles.assign(1, static_cast<std::uint32_t>(tris));
    d.targets.clear();
    d.rewrite_positions.clear();
    d.removals.clear();
    std::vector<std::uint32_t> touched;
    for (std::size_t k = 0; k < count; ++k) {
        if (k % 4096 == 0) check_progress(progress, from + (to - from) * double(k) / double(count), stage);
        const Collapse& c = collapses[k];
        touched.clear();
        for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m)
            for (std::uint32_t r : strips_of[canonical[moves[m].from]]) touched.push_back(r);
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        std::size_t before = 0;
        for (std::uint32_t r : touched) before += region_triangles(buf.data() + d.strip_offsets[r], drawn(r));
        for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m) {
            const std::uint32_t v = canonical[moves[m].from], t = canonical[moves[m].to];
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
            std::vector<std::uint32_t>().swap(strips_of[v]);
            d.rewrite_begin.push_back(static_cast<std::uint32_t>(d.rewrite_positions.size()));
        }
        std::size_t after = 0;
        for (std::uint32_t r : touched) {
            std::uint32_t* region = buf.data() + d.strip_offsets[r];
            ::lodstrips::Removal rm;
            while (find_degenerate_run(region, drawn(r), rm)) {
                rm.strip = r;
                d.removals.push_back(rm);
                ++(rm.type == 1 ? stats.removals_type1 : stats.removals_type2);
                remove_run(region, cap(r), live[r], rm);
            }
            after += region_triangles(region, drawn(r));
        }
        tris = tris - before + after;
        d.collapse_begin.push_back(static_cast<std::uint32_t>(d.targets.size()));
        d.removal_begin.push_back(static_cast<std::uint32_t>(d.removals.size()));
        d.triangles.push_back(static_cast<std::uint32_t>(tris));
    }
    check_progress(progress, to, stage);
    return stats;
}

}  // namespace lodforge::strip_replay
