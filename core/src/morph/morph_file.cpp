// The .lfmorph writer and reader (format: docs/formats/lfmorph.md).
//
// Based on:
//  - Q. Meyer et al., "On Floating-Point Normal Vectors", EGSR 2010, and Z. Cigolle et al., "A Survey of
//    Efficient Representations for Independent Unit Vectors", JCGT 2014 (octahedral normals, 2 × 16 bits);
//  - the LODStrips thesis, §6 (storage per frame of morphing LOD: 472–848 KB for 10–17K vertices, which
//    this format is measured against in docs/benchmarks.md).
// Layout: the tagged section container of io/binary_io.h (CRC-32 per section). Version 1 files (one
// flat body and a 64-bit FNV-1a checksum) are still read: their body is version 2's payloads back to back.
#include "lodforge/morph/morph_file.h"

#include "lodforge/error.h"
#include "io/binary_io.h"
#include "morph/morph_quantize.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace lodforge {
namespace {

constexpr char kMagic[8] = {'L', 'F', 'M', 'O', 'R', 'P', 'H', '\0'};
constexpr std::uint32_t kNormalsStored = 1, kQuantized = 2, kColors = 4;
constexpr std::uint32_t kFlatVersion = 1;  // before the section container

Bounds sequence_bounds(const MorphMesh& morph) {
    Bounds b;
    for (const auto& f : morph.frame_positions)
        for (const Vec3f& p : f) b.add(p);
    return b;
}

std::size_t sequence_size(const MorphSequence& s, std::size_t levels) {
    return 4 * 3 + 8 * levels + 12 * s.sequence.collapses.size() + 8 * s.sequence.moves.size();
}

void check_lod(const MorphMesh& morph, const MorphLod& lod) {
    for (const MorphSequence& s : lod.sequences) {
        if (s.sequence.input_points.size() != morph.vertex_count() || s.level_collapses.size() != lod.levels.size() ||
            s.level_triangles.size() != lod.levels.size() || s.frame >= morph.frame_count())
            throw Error(Error::Kind::argument, "write_morph_lod: the LOD was not built from this morph mesh");
    }
    if (lod.sequences.empty()) throw Error(Error::Kind::argument, "write_morph_lod: the LOD has no sequences");
}

}  // namespace

MorphFileStats morph_file_stats(const MorphMesh& morph, const MorphLod& lod, const MorphWriteOptions& options) {
    MorphFileStats s;
    const std::size_t nv = morph.vertex_count();
    const bool q = options.encoding == MorphEncoding::quantized16;
    s.header_bytes = binary::container_size({0, 0, 0, 0}) + 4 * 8 + 4 * lod.levels.size() + (q ? 24 : 0);
    s.connectivity_bytes = 4 * morph.base.indices.size() + 4 * nv * 2 + (morph.base.has_colors() ? 16 * nv : 0) +
                           8 * nv * morph.base.texcoords.size();
    s.frame_bytes = (q ? 6 : 12) * nv + (morph.normals_from_input ? (q ? 4 : 12) * nv : 0);
    for (const MorphSequence& seq : lod.sequences) s.sequence_bytes += sequence_size(seq, lod.levels.size());
    s.total_bytes = s.header_bytes + s.connectivity_bytes + s.frame_bytes * morph.frame_count() + s.sequence_bytes;
    return s;
}

void write_morph_lod(const std::string& path, const MorphMesh& morph, const MorphLod& lod,
                     const MorphWriteOptions& options, Progress* progress) {
    check_lod(morph, lod);
    check_progress(progress, 0.0, "Writing morph LOD");
    const Mesh& base = morph.base;
    const std::size_t nv = morph.vertex_count();
    const bool q = options.encoding == MorphEncoding::quantized16;
    binary::Writer head, mesh, frames, seqs;
    const std::uint32_t flags = (morph.normals_from_input ? kNormalsStored : 0) | (q ? kQuantized : 0) |
                                (base.has_colors() ? kColors : 0);
    head.put(flags);
    head.put(static_cast<std::uint32_t>(nv));
    head.put(static_cast<std::uint32_t>(base.triangle_count()));
    head.put(static_cast<std::uint32_t>(morph.frame_count()));
    head.put(static_cast<std::uint32_t>(base.texcoords.size()));
    head.put(static_cast<std::uint32_t>(lod.order));
    head.put(static_cast<std::uint32_t>(lod.levels.size()));
    head.put(static_cast<std::uint32_t>(lod.sequences.size()));
    for (float l : lod.levels) head.put(l);
    mesh.put_array(base.indices);
    std::vector<std::uint32_t> ids = base.position_ids;
    if (ids.size() != nv) {
        ids.resize(nv);
        for (std::uint32_t v = 0; v < nv; ++v) ids[v] = v;
    }
    mesh.put_array(ids);
    mesh.put_array(lod.sequences.front().sequence.input_points);
    if (base.has_colors()) mesh.put_array(base.colors);
    for (const auto& set : base.texcoords) mesh.put_array(set);
    const Bounds b = sequence_bounds(morph);
    const Vec3f lo = b.min, ext = b.size();
    if (q) {
        frames.put(lo);
        frames.put(ext);
    }
    for (std::size_t k = 0; k < morph.frame_count(); ++k) {
        check_progress(progress, 0.8 * double(k) / double(morph.frame_count()), "Writing morph LOD");
        const auto& p = morph.frame_positions[k];
        if (q) {
            for (const Vec3f& x : p)
                for (int a = 0; a < 3; ++a) {
                    const float e = ext[a] > 0 ? (x[a] - lo[a]) / ext[a] : 0.f;
                    frames.put(static_cast<std::uint16_t>(std::lround(std::clamp(e, 0.f, 1.f) * 65535.f)));
                }
        } else {
            frames.put_array(p);
        }
        if (!morph.normals_from_input) continue;
        if (q) {
            for (const Vec3f& n : morph.frame_normals[k]) {
                std::int16_t o[2];
                oct_encode(n, o);
                frames.put(o[0]);
                frames.put(o[1]);
            }
        } else {
            frames.put_array(morph.frame_normals[k]);
        }
    }
    for (const MorphSequence& s : lod.sequences) {
        seqs.put(static_cast<std::uint32_t>(s.frame));
        seqs.put(static_cast<std::uint32_t>(s.sequence.collapses.size()));
        seqs.put(static_cast<std::uint32_t>(s.sequence.moves.size()));
        for (std::size_t c : s.level_collapses) seqs.put(static_cast<std::uint32_t>(c));
        for (std::size_t t : s.level_triangles) seqs.put(static_cast<std::uint32_t>(t));
        for (const Collapse& c : s.sequence.collapses) {
            seqs.put(c.from_point);
            seqs.put(c.to_point);
            seqs.put(c.moves_end);
        }
        for (const VertexMove& m : s.sequence.moves) {
            seqs.put(m.from);
            seqs.put(m.to);
        }
    }
    binary::write_file(path, binary::write_container(kMagic, kMorphFileVersion,
                                                     {{"HEAD", &head.bytes}, {"MESH", &mesh.bytes},
                                                      {"FRMS", &frames.bytes}, {"SEQS", &seqs.bytes}}));
    check_progress(progress, 1.0, "Writing morph LOD");
}

MorphLodFile read_morph_lod(const std::string& path, Progress* progress) {
    check_progress(progress, 0.0, "Reading morph LOD");
    const std::vector<std::uint8_t> data = binary::read_file(path, "a .lfmorph file");
    const std::uint32_t version = binary::peek_version(data, path, kMagic, "LodForge morph (.lfmorph)");
    // One reader per section; a version 1 file is one body, so all four are the same reader.
    std::vector<binary::Reader> readers;
    if (version == kFlatVersion) {
        if (data.size() < sizeof kMagic + 4 + 8) throw_error(Error::Kind::format, path, "truncated header");
        const std::size_t body = data.size() - 8;
        std::uint64_t stored = 0;
        std::memcpy(&stored, data.data() + body, 8);
        if (binary::legacy_fnv1a(data.data(), body, binary::lfmorph1_fnv1a_basis) != stored)
            throw_error(Error::Kind::format, path, "checksum mismatch: the file is truncated or corrupt");
        readers.emplace_back(data.data() + 12, body - 12, path, 12);
    } else if (version == kMorphFileVersion) {
        for (const binary::Section& sec : binary::read_container(data, path, kMagic, ".lfmorph", {"HEAD", "MESH", "FRMS", "SEQS"}))
            readers.push_back(sec.reader(path));
    } else {
        throw_error(Error::Kind::unsupported, path, "morph file version " + std::to_string(version) +
                                                        " (this build reads versions 1 and " +
                                                        std::to_string(kMorphFileVersion) + ")");
    }
    binary::Reader& head = readers.front();
    binary::Reader& mesh_in = readers[std::min<std::size_t>(1, readers.size() - 1)];
    binary::Reader& frames_in = readers[std::min<std::size_t>(2, readers.size() - 1)];
    binary::Reader& seqs_in = readers.back();
    MorphLodFile out;
    out.version = version;
    out.file_bytes = data.size();
    const auto flags = head.get<std::uint32_t>("flags");
    if (flags & ~(kNormalsStored | kQuantized | kColors)) head.fail("unknown flags " + std::to_string(flags));
    const auto nv = head.get<std::uint32_t>("vertex count");
    const auto nt = head.get<std::uint32_t>("triangle count");
    const auto nk = head.get<std::uint32_t>("frame count");
    const auto sets = head.get<std::uint32_t>("texcoord set count");
    const auto order = head.get<std::uint32_t>("order");
    const auto nl = head.get<std::uint32_t>("level count");
    const auto ns = head.get<std::uint32_t>("sequence count");
    if (nv == 0 || nt == 0 || nk == 0) head.fail("empty morph mesh (vertices, triangles or frames is 0)");
    if (order > 2) head.fail("unknown order " + std::to_string(order));
    if (nl == 0 || ns == 0) head.fail("no levels or no sequences");
    if (sets > 8) head.fail(std::to_string(sets) + " texcoord sets");
    const bool q = flags & kQuantized;
    out.encoding = q ? MorphEncoding::quantized16 : MorphEncoding::float32;
    MorphLod& lod = out.lod;
    lod.order = static_cast<MorphOrder>(order);
    lod.levels = head.get_array<float>(nl, "levels");
    for (std::size_t i = 0; i < nl; ++i)
        if (!(lod.levels[i] > 0.f && lod.levels[i] < 1.f) || (i > 0 && !(lod.levels[i] < lod.levels[i - 1])))
            head.fail("level ratios must decrease inside (0, 1)");

    MorphMesh& morph = out.morph;
    Mesh& base = morph.base;
    base.indices = mesh_in.get_array<std::uint32_t>(std::size_t(nt) * 3, "faces");
    for (std::size_t i = 0; i < base.indices.size(); ++i)
        if (base.indices[i] >= nv)
            mesh_in.fail("face " + std::to_string(i / 3) + " refers to vertex " + std::to_string(base.indices[i]) + " of " +
                   std::to_string(nv));
    base.position_ids = mesh_in.get_array<std::uint32_t>(nv, "point ids");
    for (std::uint32_t id : base.position_ids)
        if (id >= nv) mesh_in.fail("point id " + std::to_string(id) + " out of range");
    const std::vector<std::uint32_t> points = mesh_in.get_array<std::uint32_t>(nv, "morph points");
    std::uint32_t point_count = 0;
    for (std::uint32_t p : points) {
        if (p >= nv) mesh_in.fail("morph point " + std::to_string(p) + " out of range");
        point_count = std::max(point_count, p + 1);
    }
    if (flags & kColors) base.colors = mesh_in.get_array<Vec4f>(nv, "colours");
    for (const Vec4f& c : base.colors)
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w)) mesh_in.fail("non-finite colour");
    for (std::uint32_t s = 0; s < sets; ++s) {
        base.texcoords.push_back(mesh_in.get_array<Vec2f>(nv, "texcoords"));
        for (const Vec2f& t : base.texcoords.back())
            if (!std::isfinite(t.x) || !std::isfinite(t.y)) mesh_in.fail("non-finite texcoord");
    }
    Vec3f lo{}, ext{};
    if (q) {
        lo = frames_in.get<Vec3f>("box origin");
        ext = frames_in.get<Vec3f>("box size");
        if (!is_finite(lo) || !is_finite(ext) || ext.x < 0 || ext.y < 0 || ext.z < 0) frames_in.fail("invalid quantisation box");
    }
    const bool normals = flags & kNormalsStored;
    for (std::uint32_t k = 0; k < nk; ++k) {
        check_progress(progress, 0.8 * double(k) / double(nk), "Reading morph LOD");
        std::vector<Vec3f> p;
        if (q) {
            const std::vector<std::uint16_t> raw = frames_in.get_array<std::uint16_t>(std::size_t(nv) * 3, "positions");
            p.resize(nv);
            for (std::size_t v = 0; v < nv; ++v)
                p[v] = {lo.x + ext.x * float(raw[3 * v]) / 65535.f, lo.y + ext.y * float(raw[3 * v + 1]) / 65535.f,
                        lo.z + ext.z * float(raw[3 * v + 2]) / 65535.f};
        } else {
            p = frames_in.get_array<Vec3f>(nv, "positions");
        }
        morph.frame_positions.push_back(std::move(p));
        if (!normals) continue;
        std::vector<Vec3f> n;
        if (q) {
            const std::vector<std::int16_t> raw = frames_in.get_array<std::int16_t>(std::size_t(nv) * 2, "normals");
            n.resize(nv);
            for (std::size_t v = 0; v < nv; ++v) n[v] = oct_decode(raw[2 * v], raw[2 * v + 1]);
        } else {
            n = frames_in.get_array<Vec3f>(nv, "normals");
        }
        morph.frame_normals.push_back(std::move(n));
    }
    morph.normals_from_input = normals;
    for (std::uint32_t s = 0; s < ns; ++s) {
        MorphSequence seq;
        seq.frame = seqs_in.get<std::uint32_t>("sequence frame");
        if (seq.frame >= nk) seqs_in.fail("sequence " + std::to_string(s) + " is built on frame " + std::to_string(seq.frame));
        const auto nc = seqs_in.get<std::uint32_t>("collapse count");
        const auto nm = seqs_in.get<std::uint32_t>("move count");
        for (std::uint32_t l = 0; l < nl; ++l) seq.level_collapses.push_back(seqs_in.get<std::uint32_t>("level collapses"));
        for (std::uint32_t l = 0; l < nl; ++l) seq.level_triangles.push_back(seqs_in.get<std::uint32_t>("level triangles"));
        for (std::uint32_t l = 0; l < nl; ++l)
            if (seq.level_collapses[l] > nc || (l > 0 && seq.level_collapses[l] < seq.level_collapses[l - 1]))
                seqs_in.fail("sequence " + std::to_string(s) + ": level " + std::to_string(l) + " ends at collapse " +
                       std::to_string(seq.level_collapses[l]) + " of " + std::to_string(nc));
        const std::vector<std::uint32_t> raw = seqs_in.get_array<std::uint32_t>(std::size_t(nc) * 3, "collapses");
        seq.sequence.collapses.resize(nc);
        std::uint32_t begin = 0;
        for (std::uint32_t c = 0; c < nc; ++c) {
            Collapse& col = seq.sequence.collapses[c];
            col.from_point = raw[3 * c];
            col.to_point = raw[3 * c + 1];
            col.moves_begin = begin;
            col.moves_end = raw[3 * c + 2];
            if (col.from_point >= point_count || col.to_point >= point_count || col.moves_end < begin || col.moves_end > nm)
                seqs_in.fail("sequence " + std::to_string(s) + ": collapse " + std::to_string(c) + " is out of range");
            begin = col.moves_end;
        }
        if (begin != nm) seqs_in.fail("sequence " + std::to_string(s) + ": collapses use " + std::to_string(begin) + " of " +
                                std::to_string(nm) + " moves");
        const std::vector<std::uint32_t> mv = seqs_in.get_array<std::uint32_t>(std::size_t(nm) * 2, "moves");
        seq.sequence.moves.resize(nm);
        for (std::uint32_t m = 0; m < nm; ++m) {
            if (mv[2 * m] >= nv || mv[2 * m + 1] >= nv)
                seqs_in.fail("sequence " + std::to_string(s) + ": move " + std::to_string(m) + " refers to a vertex out of range");
            seq.sequence.moves[m] = {mv[2 * m], mv[2 * m + 1]};
        }
        seq.sequence.input_points = points;
        lod.sequences.push_back(std::move(seq));
    }
    for (const binary::Reader& each : readers) each.expect_end("data");
    morph.source = path;
    finish_morph(morph, path);
    // Each vertex is removed at most once and only onto a vertex still present: replay follows the chains,
    // which then cannot cycle.
    for (std::size_t s = 0; s < lod.sequences.size(); ++s) {
        std::vector<std::uint8_t> removed(nv, 0);
        for (const VertexMove& m : lod.sequences[s].sequence.moves) {
            if (removed[m.from] || removed[m.to] || m.from == m.to)
                throw_error(Error::Kind::format, path, "sequence " + std::to_string(s) + " moves vertex " +
                                                           std::to_string(m.from) + " twice, onto itself or onto a removed vertex");
            removed[m.from] = 1;
        }
    }
    SimplifyResult none;
    none.input_points = points;
    lod.triangles = replay_collapses(base, none, 0).size() / 3;
    // The level table must describe the sequences (info and LOD factors rely on it).
    for (std::size_t s = 0; s < lod.sequences.size(); ++s) {
        const MorphSequence& seq = lod.sequences[s];
        for (std::size_t l = 0; l < seq.level_collapses.size(); ++l)
            if (replay_collapses(base, seq.sequence, seq.level_collapses[l]).size() / 3 != seq.level_triangles[l])
                throw_error(Error::Kind::format, path, "sequence " + std::to_string(s) + ": level " + std::to_string(l) +
                                                           " does not have the triangle count the file states");
    }
    check_progress(progress, 1.0, "Reading morph LOD");
    return out;
}

}  // namespace lodforge
