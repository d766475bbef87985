// LODStrips on a morphing mesh: the MorphLod's collapse sequence recorded on one strip set, plus the
// frames' vertex data (.lfmstrips writer and reader).
//
// Based on:
//  - J. F. Ramos, "LODStrips: Continuous Level of Detail using Triangle Strips", PhD thesis, Universitat
//    Jaume I, 2008: chapter 6 (one strip set over a supermesh, change sets from the collapse sequences),
//    §3.3 (canonical vertex order, W[]), §4.2.2 (degenerate-run removal of types 1 and 2), ch. 5 (records
//    grouped per strip in one element buffer);
//  - the octahedral normal encoding of Meyer et al. (EGSR 2010), as in the .lfmorph file.
//
// Why not build_lodstrips(): it runs its own simplification of one mesh, while the strips here must
// follow the MorphLod's sequence (whose costs see every frame) so that a runtime level is exactly the
// face set extract_morph gives. The public lodstrips.h API has no "record this given sequence" entry, so
// the recording loop is here, built from the builder's own replay steps (lodstrips_record.h), and checked
// by the runtime's own replay (LodStrips::assign) and by encode_lodstrips.
#include "lodforge/morph_lodstrips.h"

#include "lodforge/atomic_file.h"
#include "lodforge/error.h"
#include "lodforge/lodstrips.h"
#include "lodstrips_record.h"
#include "morph_quantize.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numeric>

namespace lodforge {
namespace {

constexpr std::uint32_t kUnused = 0xFFFFFFFFu;

// The strips of one region while the sequence is replayed offline: `live` counts the used slots
// (restart index included), the rest repeats the region's last slot. The steps are the builder's
// (lodstrips_record.h), so the records replay as the runtime expects.
struct Region {
    std::uint32_t* p = nullptr;
    std::uint32_t cap = 0, live = 0;
    bool restart = true;
    std::uint32_t drawn() const { return live - (restart ? 1u : 0u); }
    std::size_t triangles() const { return strip_replay::region_triangles(p, drawn()); }
    bool next_run(lodstrips::Removal& r) const { return strip_replay::find_degenerate_run(p, drawn(), r); }
    void erase(const lodstrips::Removal& r) { strip_replay::remove_run(p, cap, live, r); }
};

template <class T>
void put(std::vector<std::uint8_t>& out, const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    out.insert(out.end(), p, p + sizeof v);
}

void put_section(std::vector<std::uint8_t>& out, const char (&tag)[5], const std::vector<std::uint8_t>& payload) {
    put(out, lodstrips::section_tag(tag));
    put(out, static_cast<std::uint32_t>(payload.size()));
    put(out, lodstrips::detail::crc32(payload.data(), payload.size()));
    out.insert(out.end(), payload.begin(), payload.end());
}

std::vector<std::uint8_t> frames_payload(const lodstrips::MorphData& d, MorphEncoding encoding) {
    const std::uint32_t n = d.strips.vertex_count;
    const bool q = encoding == MorphEncoding::quantized16;
    std::vector<std::uint8_t> out;
    put(out, d.frame_count);
    put(out, n);
    put(out, q ? lodstrips::morph_flag_quantized : 0u);
    float lo[3] = {0, 0, 0}, size[3] = {0, 0, 0};
    if (q) {
        float hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = hi[a] = d.frame_positions.empty() ? 0.f : d.frame_positions[std::size_t(a)];
            for (std::size_t i = std::size_t(a); i < d.frame_positions.size(); i += 3) {
                lo[a] = std::min(lo[a], d.frame_positions[i]);
                hi[a] = std::max(hi[a], d.frame_positions[i]);
            }
            size[a] = hi[a] - lo[a];
        }
        for (float x : lo) put(out, x);
        for (float x : size) put(out, x);
    }
    for (std::uint32_t k = 0; k < d.frame_count; ++k) {
        const float* pos = d.frame_positions.data() + std::size_t(k) * 3u * n;
        const float* nrm = d.frame_normals.data() + std::size_t(k) * 3u * n;
        if (q) {
            for (std::size_t i = 0; i < 3u * std::size_t(n); ++i) {
                const float a = size[i % 3] > 0 ? (pos[i] - lo[i % 3]) / size[i % 3] : 0.f;
                put(out, static_cast<std::uint16_t>(std::lround(std::clamp(a, 0.f, 1.f) * 65535.f)));
            }
            for (std::size_t v = 0; v < n; ++v) {
                std::int16_t o[2];
                oct_encode({nrm[3 * v], nrm[3 * v + 1], nrm[3 * v + 2]}, o);
                put(out, o[0]);
                put(out, o[1]);
            }
        } else {
            const auto* pp = reinterpret_cast<const std::uint8_t*>(pos);
            const auto* np = reinterpret_cast<const std::uint8_t*>(nrm);
            out.insert(out.end(), pp, pp + 12u * std::size_t(n));
            out.insert(out.end(), np, np + 12u * std::size_t(n));
        }
    }
    return out;
}

}  // namespace

MorphStripsBuild build_morph_lodstrips(const MorphMesh& morph, const MorphLod& lod, const MorphStripsParams& params,
                                       Progress* progress) {
    if (lod.sequences.size() != 1)
        throw Error(Error::Kind::unsupported,
                    "morph strips: the LOD has " + std::to_string(lod.sequences.size()) +
                        " collapse sequences (per-frame order); one strip set needs one order (use --order single)");
    if (params.max_strip_length < 16 || params.max_strip_length > 65000)
        throw Error(Error::Kind::argument, "morph strips: max_strip_length must be in [16, 65000]");
    const Mesh& mesh = morph.base;
    const std::size_t nv = mesh.vertex_count();
    if (mesh.triangle_count() == 0 || morph.frame_count() == 0)
        throw Error(Error::Kind::argument, "morph strips: the morph mesh has no triangles or no frames");
    if (nv >= lodstrips::restart_index) throw Error(Error::Kind::argument, "morph strips: too many vertices");
    const MorphSequence& seq = lod.sequences.front();

    // The sequence up to the coarsest level: the runtime's go_to_lod(f) then is morph_collapses_for(f).
    SimplifyResult s;
    s.input_points = seq.sequence.input_points;
    const std::size_t C = seq.level_collapses.empty() ? 0 : seq.level_collapses.back();
    if (C > seq.sequence.collapses.size()) throw Error(Error::Kind::invalid, "morph strips: level beyond the sequence");
    s.collapses.assign(seq.sequence.collapses.begin(), seq.sequence.collapses.begin() + std::ptrdiff_t(C));
    s.moves.assign(seq.sequence.moves.begin(),
                   seq.sequence.moves.begin() + std::ptrdiff_t(C ? s.collapses.back().moves_end : 0));
    check_progress(progress, 0.0, "morph strips");

    // Full detail = replay at 0 (faces degenerate on points dropped), matched back to input faces for
    // their materials: they are a subsequence of the input faces, in order.
    const std::vector<std::uint32_t> faces = replay_collapses(mesh, s, 0);
    const std::size_t nf = faces.size() / 3;
    const std::vector<std::uint32_t> face_group = strip_replay::face_groups(mesh, faces, "morph strips");
    const std::size_t groups = std::max<std::size_t>(1, mesh.materials.size());

    // Canonical order: never-removed vertices first (input order), then the last collapse's, ..., the
    // first collapse's vertices last, so level k uses a prefix.
    MorphStripsBuild out;
    std::vector<std::uint8_t> used(nv, 0), removed(nv, 0);
    for (std::uint32_t v : faces) used[v] = 1;
    for (const VertexMove& m : s.moves) {
        if (removed[m.from]) throw Error(Error::Kind::invalid, "morph strips: vertex " + std::to_string(m.from) + " removed twice");
        removed[m.from] = 1;
        used[m.from] = used[m.to] = 1;
    }
    const auto N = static_cast<std::uint32_t>(std::count(used.begin(), used.end(), std::uint8_t(1)));
    out.canonical.assign(nv, kUnused);
    std::uint32_t next = 0;
    for (std::size_t v = 0; v < nv; ++v)
        if (used[v] && !removed[v]) out.canonical[v] = next++;
    for (std::size_t o = 0; o < s.moves.size(); ++o) out.canonical[s.moves[o].from] = N - 1 - static_cast<std::uint32_t>(o);
    out.input_vertex.assign(N, 0);
    for (std::size_t v = 0; v < nv; ++v)
        if (out.canonical[v] != kUnused) out.input_vertex[out.canonical[v]] = static_cast<std::uint32_t>(v);

    lodstrips::MorphData& md = out.data;
    lodstrips::Data& d = md.strips;
    d.vertex_count = N;
    md.frame_count = static_cast<std::uint32_t>(morph.frame_count());
    md.frame_positions.resize(std::size_t(md.frame_count) * 3u * N);
    md.frame_normals.resize(md.frame_positions.size());
    for (std::size_t k = 0; k < morph.frame_count(); ++k)
        for (std::uint32_t c = 0; c < N; ++c) {
            const Vec3f p = morph.frame_positions[k][out.input_vertex[c]];
            const Vec3f n = morph.frame_normals[k][out.input_vertex[c]];
            float* pp = &md.frame_positions[(k * N + c) * 3];
            float* np = &md.frame_normals[(k * N + c) * 3];
            pp[0] = p.x, pp[1] = p.y, pp[2] = p.z;
            np[0] = n.x, np[1] = n.y, np[2] = n.z;
        }
    d.positions.assign(md.frame_positions.begin(), md.frame_positions.begin() + std::ptrdiff_t(3u * N));
    d.normals.assign(md.frame_normals.begin(), md.frame_normals.begin() + std::ptrdiff_t(3u * N));
    if (mesh.has_colors()) {
        d.colors.resize(4u * N);
        d.colors_8bit = true;
        for (std::uint32_t c = 0; c < N; ++c) {
            const Vec4f col = mesh.colors[out.input_vertex[c]];
            const float ch[4] = {col.x, col.y, col.z, col.w};
            for (int i = 0; i < 4; ++i) {
                d.colors[4 * c + std::uint32_t(i)] = ch[i];
                const float q = std::round(ch[i] * 255.f);
                if (!(q >= 0.f && q <= 255.f) || q / 255.f != ch[i]) d.colors_8bit = false;
            }
        }
    }
    for (const auto& set : mesh.texcoords) {
        std::vector<float>& t = d.texcoords.emplace_back(2u * N);
        for (std::uint32_t c = 0; c < N; ++c) t[2 * c] = set[out.input_vertex[c]].x, t[2 * c + 1] = set[out.input_vertex[c]].y;
    }
    for (const Material& m : mesh.materials) d.materials.push_back(strip_replay::strip_material(m, mesh.texcoords.size()));
    check_progress(progress, 0.2, "morph strips");

    // Strips once at full detail, per material, cut into pieces at even positions (a piece repeats the
    // two indices before its cut, so no triangle is lost and winding holds).
    const auto piece = static_cast<std::uint32_t>(params.max_strip_length & ~std::size_t(1));
    d.restart = params.join == StripJoin::restart;
    d.strip_offsets.assign(1, 0);
    std::vector<std::vector<std::uint32_t>> pieces;
    for (std::uint32_t g = 0; g < groups; ++g) {
        std::vector<std::uint32_t> tri;
        for (std::size_t f = 0; f < nf; ++f)
            if (face_group[f] == g)
                for (int c = 0; c < 3; ++c) tri.push_back(out.canonical[faces[3 * f + std::size_t(c)]]);
        if (tri.empty()) continue;
        StripifyParams sp;
        sp.join = StripJoin::restart;
        sp.cache_size = params.cache_size;
        for (const auto& strip : stripify(tri, N, sp).strips) {
            std::size_t at = 0;
            for (; strip.size() - at > piece; at += piece - 2) {
                pieces.emplace_back(strip.begin() + std::ptrdiff_t(at), strip.begin() + std::ptrdiff_t(at + piece));
                d.strip_materials.push_back(g);
            }
            pieces.emplace_back(strip.begin() + std::ptrdiff_t(at), strip.end());
            d.strip_materials.push_back(g);
        }
    }
    // Regions: restart mode, piece + restart index; degenerate mode, piece + the join to the next piece,
    // padded so that every region is even and every piece starts on an even position.
    std::vector<std::uint32_t>& buf0 = d.initial_indices;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        buf0.insert(buf0.end(), pieces[i].begin(), pieces[i].end());
        const std::size_t len = pieces[i].size();
        if (d.restart) {
            buf0.push_back(lodstrips::restart_index);
        } else if (i + 1 < pieces.size()) {
            buf0.push_back(pieces[i].back());
            buf0.push_back(pieces[i + 1].front());
            if (len % 2) buf0.push_back(pieces[i + 1].front());
        } else if (len % 2) {
            buf0.push_back(pieces[i].back());
        }
        d.strip_offsets.push_back(static_cast<std::uint32_t>(buf0.size()));
    }
    const std::size_t S = pieces.size();
    pieces.clear();
    check_progress(progress, 0.4, "morph strips");

    // Offline replay: per collapse, every position of each removed vertex (rewritten to its target), then
    // every degenerate run of the strips it touched, each removed before the next is looked for.
    std::vector<std::uint32_t> buf = d.initial_indices;
    std::vector<Region> regions(S);
    for (std::size_t r = 0; r < S; ++r) {
        const std::uint32_t a = d.strip_offsets[r], b = d.strip_offsets[r + 1];
        regions[r] = {buf.data() + a, b - a, b - a, d.restart};
    }
    std::vector<std::vector<std::uint32_t>> strips_of(N);  // strips holding each vertex (sorted on use)
    for (std::size_t r = 0; r < S; ++r)
        for (std::uint32_t e = d.strip_offsets[r]; e < d.strip_offsets[r + 1]; ++e)
            if (buf[e] != lodstrips::restart_index && (strips_of[buf[e]].empty() || strips_of[buf[e]].back() != r))
                strips_of[buf[e]].push_back(static_cast<std::uint32_t>(r));
    std::size_t tris = 0;
    for (const Region& r : regions) tris += r.triangles();
    d.collapse_begin.assign(1, 0);
    d.rewrite_begin.assign(1, 0);
    d.removal_begin.assign(1, 0);
    d.triangles.assign(1, static_cast<std::uint32_t>(tris));
    std::vector<std::uint32_t> touched;
    for (std::size_t k = 0; k < C; ++k) {
        if (k % 4096 == 0) check_progress(progress, 0.4 + 0.6 * double(k) / double(C), "morph strips");
        const Collapse& c = s.collapses[k];
        touched.clear();
        for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m) {
            const auto& list = strips_of[out.canonical[s.moves[m].from]];
            touched.insert(touched.end(), list.begin(), list.end());
        }
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        std::size_t before = 0;
        for (std::uint32_t r : touched) before += regions[r].triangles();
        for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m) {
            const std::uint32_t v = out.canonical[s.moves[m].from], t = out.canonical[s.moves[m].to];
            d.targets.push_back(t);
            std::sort(strips_of[v].begin(), strips_of[v].end());  // records in strip order, as in the file
            for (std::uint32_t r : strips_of[v]) {
                Region& g = regions[r];
                // degenerate joins: the fill repeats the last index and must keep doing so
                const std::uint32_t end = d.restart ? g.drawn() : g.cap;
                for (std::uint32_t i = 0; i < end; ++i)
                    if (g.p[i] == v) {
                        g.p[i] = t;
                        d.rewrite_positions.push_back(d.strip_offsets[r] + i);
                    }
                if (std::find(strips_of[t].begin(), strips_of[t].end(), r) == strips_of[t].end()) strips_of[t].push_back(r);
            }
            std::vector<std::uint32_t>().swap(strips_of[v]);
            d.rewrite_begin.push_back(static_cast<std::uint32_t>(d.rewrite_positions.size()));
        }
        std::size_t after = 0;
        for (std::uint32_t r : touched) {
            Region& g = regions[r];
            lodstrips::Removal rm;
            while (g.next_run(rm)) {
                rm.strip = r;
                d.removals.push_back(rm);
                g.erase(rm);
            }
            after += g.triangles();
        }
        tris = tris - before + after;
        d.collapse_begin.push_back(static_cast<std::uint32_t>(d.targets.size()));
        d.removal_begin.push_back(static_cast<std::uint32_t>(d.removals.size()));
        d.triangles.push_back(static_cast<std::uint32_t>(tris));
    }
    out.degenerate_runs = d.removals.size();
    check_progress(progress, 1.0, "morph strips");
    return out;
}

std::vector<std::uint8_t> encode_morph_lodstrips(const lodstrips::MorphData& data, MorphEncoding encoding) {
    const std::size_t values = std::size_t(data.frame_count) * 3u * data.strips.vertex_count;
    if (data.frame_count == 0 || data.frame_positions.size() != values || data.frame_normals.size() != values)
        throw Error(Error::Kind::invalid, "morph strips: frame arrays have inconsistent sizes");
    const std::vector<std::uint8_t> strips = encode_lodstrips(data.strips);
    const std::vector<std::uint8_t> frames = frames_payload(data, encoding);
    std::vector<std::uint8_t> out(lodstrips::morph_file_magic, lodstrips::morph_file_magic + 8);
    put(out, lodstrips::morph_format_version);
    put(out, lodstrips::endian_tag);
    put(out, std::uint32_t{2});
    put(out, lodstrips::detail::crc32(out.data(), 20));
    put(out, static_cast<std::uint64_t>(32 + 12 + strips.size() + 12 + frames.size()));
    put_section(out, "LSTR", strips);
    put_section(out, "FRMS", frames);
    return out;
}

MorphStripsStorage morph_lodstrips_storage(const lodstrips::MorphData& data, MorphEncoding encoding) {
    MorphStripsStorage st;
    st.strips_bytes = encode_lodstrips(data.strips).size();
    st.frame_bytes = std::size_t(data.strips.vertex_count) * (encoding == MorphEncoding::quantized16 ? 10u : 24u);
    st.file_bytes = 32 + 12 + st.strips_bytes + 12 + 12 + (encoding == MorphEncoding::quantized16 ? 24u : 0u) +
                    st.frame_bytes * data.frame_count;
    st.bytes_per_frame = data.frame_count ? double(st.file_bytes) / double(data.frame_count) : 0.0;
    return st;
}

void write_morph_lodstrips(const lodstrips::MorphData& data, const std::string& path, MorphEncoding encoding) {
    std::vector<std::uint8_t> bytes;
    try {
        bytes = encode_morph_lodstrips(data, encoding);
    } catch (const Error& e) {
        throw_error(e.kind(), path, e.what());
    }
    AtomicFile file(path, true);
    file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.commit();
}

lodstrips::MorphData read_morph_lodstrips(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_error(Error::Kind::io, path, "cannot open for reading");
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw_error(Error::Kind::io, path, "read error");
    lodstrips::MorphData d;
    std::string why;
    if (!lodstrips::decode_morph(bytes.data(), bytes.size(), d, &why)) throw_error(Error::Kind::format, path, why);
    lodstrips::MorphLodStrips check;
    if (!check.assign(d, &why)) throw_error(Error::Kind::format, path, why);
    return d;
}

Mesh morph_lodstrips_mesh(const lodstrips::MorphLodStrips& runtime) {
    Mesh m = lodstrips_mesh(runtime.strips());
    const float* p = runtime.positions();
    const float* n = runtime.normals();
    m.normals.resize(m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        m.positions[v] = {p[3 * v], p[3 * v + 1], p[3 * v + 2]};
        m.normals[v] = {n[3 * v], n[3 * v + 1], n[3 * v + 2]};
    }
    return m;
}

bool is_morph_lodstrips_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[8] = {};
    return in.read(magic, 8) && std::memcmp(magic, lodstrips::morph_file_magic, 8) == 0;
}

}  // namespace lodforge
