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
#include "lodforge/morph/morph_lodstrips.h"

#include "lodforge/error.h"
#include "io/binary_io.h"
#include "lodforge/strips/lodstrips.h"
#include "strips/lodstrips_record.h"
#include "morph/morph_quantize.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>

namespace lodforge {
namespace {

std::vector<std::uint8_t> frames_payload(const lodstrips::MorphData& d, MorphEncoding encoding) {
    const std::uint32_t n = d.strips.vertex_count;
    const bool q = encoding == MorphEncoding::quantized16;
    binary::Writer out;
    out.put(d.frame_count);
    out.put(n);
    out.put(q ? lodstrips::morph_flag_quantized : 0u);
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
        for (float x : lo) out.put(x);
        for (float x : size) out.put(x);
    }
    for (std::uint32_t k = 0; k < d.frame_count; ++k) {
        const float* pos = d.frame_positions.data() + std::size_t(k) * 3u * n;
        const float* nrm = d.frame_normals.data() + std::size_t(k) * 3u * n;
        if (q) {
            for (std::size_t i = 0; i < 3u * std::size_t(n); ++i) {
                const float a = size[i % 3] > 0 ? (pos[i] - lo[i % 3]) / size[i % 3] : 0.f;
                out.put(static_cast<std::uint16_t>(std::lround(std::clamp(a, 0.f, 1.f) * 65535.f)));
            }
            for (std::size_t v = 0; v < n; ++v) {
                std::int16_t o[2];
                oct_encode({nrm[3 * v], nrm[3 * v + 1], nrm[3 * v + 2]}, o);
                out.put(o[0]);
                out.put(o[1]);
            }
        } else {
            const auto* pp = reinterpret_cast<const std::uint8_t*>(pos);
            const auto* np = reinterpret_cast<const std::uint8_t*>(nrm);
            out.bytes.insert(out.bytes.end(), pp, pp + 12u * std::size_t(n));
            out.bytes.insert(out.bytes.end(), np, np + 12u * std::size_t(n));
        }
    }
    return std::move(out.bytes);
}

// Section SETS (version 2, docs/formats/lfmstrips.md): every change set's frame, then per further set its numbering
// and its records (vertices, targets, rewrite positions, removals, triangles lost per collapse).
std::vector<std::uint8_t> sets_payload(const lodstrips::MorphData& d) {
    const std::uint32_t n = d.strips.vertex_count;
    binary::Writer out;
    out.varint(d.change_set_count());
    out.varint(d.strips_frame);
    for (const lodstrips::MorphChangeSet& cs : d.frame_sets) out.varint(cs.frame);
    for (std::size_t i = 0; i < d.frame_sets.size(); ++i) {
        const lodstrips::MorphChangeSet& cs = d.frame_sets[i];
        const lodstrips::Data& r = cs.records;
        const std::string what = "morph strips: change set " + std::to_string(i + 1);
        if (cs.to_base.size() != n) throw Error(Error::Kind::invalid, what + ": numbering has the wrong size");
        for (std::uint32_t v : cs.to_base) out.varint(v);
        const std::size_t C = r.collapse_count();
        const auto ranges = [](const std::vector<std::uint32_t>& begin, std::size_t end) {
            return !begin.empty() && begin.front() == 0 && begin.back() == end && std::is_sorted(begin.begin(), begin.end());
        };
        if (r.triangles.size() != C + 1 || r.removal_begin.size() != C + 1 || r.rewrite_begin.size() != r.targets.size() + 1 ||
            !ranges(r.collapse_begin, r.targets.size()) || !ranges(r.rewrite_begin, r.rewrite_positions.size()) ||
            !ranges(r.removal_begin, r.removals.size()) || r.targets.size() > n)
            throw Error(Error::Kind::invalid, what + ": records have inconsistent sizes");
        out.varint(C);
        for (std::size_t k = 0; k < C; ++k) {
            out.varint(r.collapse_begin[k + 1] - r.collapse_begin[k]);
            out.zigzag(std::int64_t(r.triangles[k]) - std::int64_t(r.triangles[k + 1]));
            for (std::uint32_t o = r.collapse_begin[k]; o < r.collapse_begin[k + 1]; ++o) {
                const std::uint32_t v = n - 1 - o;
                if (r.targets[o] >= v) throw Error(Error::Kind::invalid, what + ": a target is not below its vertex");
                out.varint(v - r.targets[o]);
                out.varint(r.rewrite_begin[o + 1] - r.rewrite_begin[o]);
                for (std::uint32_t j = r.rewrite_begin[o]; j < r.rewrite_begin[o + 1]; ++j) {
                    if (j > r.rewrite_begin[o] && r.rewrite_positions[j] <= r.rewrite_positions[j - 1])
                        throw Error(Error::Kind::invalid, what + ": rewrite positions are not increasing");
                    out.varint(j == r.rewrite_begin[o] ? r.rewrite_positions[j] : r.rewrite_positions[j] - r.rewrite_positions[j - 1] - 1);
                }
            }
            out.varint(r.removal_begin[k + 1] - r.removal_begin[k]);
            std::int64_t strip = 0;
            for (std::uint32_t j = r.removal_begin[k]; j < r.removal_begin[k + 1]; ++j) {
                const lodstrips::Removal& x = r.removals[j];
                if (x.count == 0 || x.count % 2 || (x.type != 1 && x.type != 2))
                    throw Error(Error::Kind::invalid, what + ": a removal has an odd count or unknown type");
                out.zigzag(std::int64_t(x.strip) - strip);
                strip = x.strip;
                out.varint(x.pos);
                out.varint(std::uint64_t(x.count / 2 - 1) << 1 | std::uint64_t(x.type - 1));
            }
        }
    }
    return std::move(out.bytes);
}

}  // namespace

MorphStripsBuild build_morph_lodstrips(const MorphMesh& morph, const MorphLod& lod, const MorphStripsParams& params,
                                       Progress* progress) {
    if (lod.sequences.empty()) throw Error(Error::Kind::argument, "morph strips: the LOD has no collapse sequence");
    if (params.max_strip_length < 16 || params.max_strip_length > 65000)
        throw Error(Error::Kind::argument, "morph strips: max_strip_length must be in [16, 65000]");
    const Mesh& mesh = morph.base;
    const std::size_t nv = mesh.vertex_count();
    if (mesh.triangle_count() == 0 || morph.frame_count() == 0)
        throw Error(Error::Kind::argument, "morph strips: the morph mesh has no triangles or no frames");
    if (nv >= lodstrips::restart_index) throw Error(Error::Kind::argument, "morph strips: too many vertices");
    const std::size_t Q = lod.sequences.size();
    if (Q > morph.frame_count()) throw Error(Error::Kind::invalid, "morph strips: more sequences than frames");

    // Each sequence up to its coarsest level: the runtime's go_to_lod(f) then is morph_collapses_for(f).
    std::vector<SimplifyResult> seqs(Q);
    for (std::size_t q = 0; q < Q; ++q) {
        const MorphSequence& seq = lod.sequences[q];
        if (seq.frame >= morph.frame_count() || (q > 0 && seq.frame <= lod.sequences[q - 1].frame))
            throw Error(Error::Kind::invalid, "morph strips: sequence frames must be increasing keyframes");
        if (seq.sequence.input_points != lod.sequences.front().sequence.input_points)
            throw Error(Error::Kind::invalid, "morph strips: the sequences disagree on the points");
        SimplifyResult& s = seqs[q];
        s.input_points = seq.sequence.input_points;
        const std::size_t C = seq.level_collapses.empty() ? 0 : seq.level_collapses.back();
        if (C > seq.sequence.collapses.size()) throw Error(Error::Kind::invalid, "morph strips: level beyond the sequence");
        s.collapses.assign(seq.sequence.collapses.begin(), seq.sequence.collapses.begin() + std::ptrdiff_t(C));
        s.moves.assign(seq.sequence.moves.begin(),
                       seq.sequence.moves.begin() + std::ptrdiff_t(C ? s.collapses.back().moves_end : 0));
    }
    check_progress(progress, 0.0, "morph strips");

    // Full detail = replay at 0 (faces degenerate on points dropped; the same for every sequence, which
    // share the points), matched back to input faces for their materials.
    const std::vector<std::uint32_t> faces = replay_collapses(mesh, seqs.front(), 0);
    const std::vector<std::uint32_t> face_group = strip_replay::face_groups(mesh, faces, "morph strips");
    const std::size_t groups = std::max<std::size_t>(1, mesh.materials.size());

    // One vertex set for every change set (a vertex some sequence moves is in all of them), so every
    // set's canonical order is a permutation of the same N vertices.
    std::vector<std::uint8_t> used(nv, 0);
    for (const SimplifyResult& s : seqs) strip_replay::mark_used(faces, s.moves, used);
    MorphStripsBuild out;
    {
        strip_replay::CanonicalOrder order = strip_replay::canonical_order(used, seqs.front().moves, "morph strips");
        out.canonical = std::move(order.canonical);
        out.input_vertex = std::move(order.input_vertex);
    }
    const auto N = static_cast<std::uint32_t>(out.input_vertex.size());

    lodstrips::MorphData& md = out.data;
    lodstrips::Data& d = md.strips;
    d.vertex_count = N;
    md.frame_count = static_cast<std::uint32_t>(morph.frame_count());
    md.strips_frame = static_cast<std::uint32_t>(lod.sequences.front().frame);
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
    strip_replay::copy_attributes(mesh, out.input_vertex, d);
    check_progress(progress, 0.2, "morph strips");

    // One strip set, in change set 0's numbering (the file's base numbering).
    strip_replay::lay_out_strips(faces, face_group, groups, out.canonical,
                                 {params.join, params.max_strip_length, params.cache_size}, d);
    check_progress(progress, 0.4, "morph strips");

    const double share = 0.6 / double(Q);
    auto record = [&](std::size_t q, const std::vector<std::uint32_t>& canonical, lodstrips::Data& into) {
        const SimplifyResult& s = seqs[q];
        const strip_replay::RecordStats rs =
            strip_replay::record_collapses(s.collapses, s.moves, s.collapses.size(), canonical, into, progress,
                                           0.4 + share * double(q), 0.4 + share * double(q + 1), "morph strips");
        out.degenerate_runs += rs.removals_type1 + rs.removals_type2;
    };
    record(0, out.canonical, d);

    // Per-frame orders: change set q's canonical order is its own sequence's; the shared strips are the
    // base strips renumbered into it, and to_base maps its numbering back.
    for (std::size_t q = 1; q < Q; ++q) {
        const strip_replay::CanonicalOrder order = strip_replay::canonical_order(used, seqs[q].moves, "morph strips");
        lodstrips::MorphChangeSet& set = md.frame_sets.emplace_back();
        set.frame = static_cast<std::uint32_t>(lod.sequences[q].frame);
        set.to_base.resize(N);
        for (std::uint32_t c = 0; c < N; ++c) set.to_base[c] = out.canonical[order.input_vertex[c]];
        lodstrips::Data& r = set.records;
        r.vertex_count = N;
        r.restart = d.restart;
        r.strip_offsets = d.strip_offsets;
        r.initial_indices = d.initial_indices;
        for (std::uint32_t& e : r.initial_indices)
            if (e != lodstrips::restart_index) e = order.canonical[out.input_vertex[e]];
        record(q, order.canonical, r);
        // Only the records travel: the layout is the base strips'.
        std::vector<std::uint32_t>().swap(r.strip_offsets);
        std::vector<std::uint32_t>().swap(r.initial_indices);
    }
    check_progress(progress, 1.0, "morph strips");
    return out;
}

std::vector<std::uint8_t> encode_morph_lodstrips(const lodstrips::MorphData& data, MorphEncoding encoding) {
    const std::size_t values = std::size_t(data.frame_count) * 3u * data.strips.vertex_count;
    if (data.frame_count == 0 || data.frame_positions.size() != values || data.frame_normals.size() != values)
        throw Error(Error::Kind::invalid, "morph strips: frame arrays have inconsistent sizes");
    const std::vector<std::uint8_t> strips = encode_lodstrips(data.strips);
    const std::vector<std::uint8_t> frames = frames_payload(data, encoding);
    const std::vector<std::uint8_t> sets = sets_payload(data);
    return binary::write_container(lodstrips::morph_file_magic, lodstrips::morph_format_version,
                                   {{"LSTR", &strips}, {"FRMS", &frames}, {"SETS", &sets}});
}

MorphStripsStorage morph_lodstrips_storage(const lodstrips::MorphData& data, MorphEncoding encoding) {
    MorphStripsStorage st;
    st.strips_bytes = encode_lodstrips(data.strips).size();
    st.frame_bytes = std::size_t(data.strips.vertex_count) * (encoding == MorphEncoding::quantized16 ? 10u : 24u);
    st.sets_bytes = sets_payload(data).size();
    st.file_bytes = binary::container_size({st.strips_bytes, 12 + (encoding == MorphEncoding::quantized16 ? 24u : 0u) +
                                                                 st.frame_bytes * data.frame_count,
                                            st.sets_bytes});
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
    binary::write_file(path, bytes);
}

lodstrips::MorphData read_morph_lodstrips(const std::string& path) {
    const std::vector<std::uint8_t> bytes = binary::read_file(path, "a .lfmstrips file");
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
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the probe
    std::ifstream in(path, std::ios::binary);
    char magic[8] = {};
    return in.read(magic, 8) && std::memcmp(magic, lodstrips::morph_file_magic, 8) == 0;
}

}  // namespace lodforge
