// The .lfmorph file: round trips in both encodings, and every kind of damage gives a clear error.
#include "lodforge/error.h"
#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_file.h"
#include "lodforge/morph/morph_lod.h"

#include "lodforge/runtime/lodstrips_runtime.h"
#include "support/test_files.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

namespace {

using namespace lodforge;
namespace fs = std::filesystem;

struct Fixture {
    MorphMesh morph;
    MorphLod lod;
};

const Fixture& sphere() {
    static const Fixture f = [] {
        Fixture x;
        MorphLoadOptions o;
        o.frames = 8;
        x.morph = load_morph(test::shared_data("morph-animated-morph-sphere/AnimatedMorphSphere.gltf"), o);
        MorphLodParams p;
        p.levels = {0.5f, 0.1f};
        p.simplify.preserve_seams = false;
        x.lod = build_morph_lod(x.morph, p);
        return x;
    }();
    return f;
}

const Fixture& horse() {
    static const Fixture f = [] {
        Fixture x;
        MorphLoadOptions o;
        o.frames = 3;
        x.morph = load_morph(test::shared_data("seq-horse-gallop"), o);
        MorphLodParams p;
        p.levels = {0.25f};
        x.lod = build_morph_lod(x.morph, p);
        return x;
    }();
    return f;
}

std::vector<std::uint8_t> bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& b) {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

// The container's sections: tag → where the payload starts and its length.
struct Section {
    std::size_t at = 0, size = 0;
};
std::map<std::string, Section> sections_of(const std::vector<std::uint8_t>& b) {
    std::map<std::string, Section> out;
    for (std::size_t at = 32; at + 12 <= b.size();) {
        std::uint32_t len = 0;
        std::memcpy(&len, b.data() + at + 4, 4);
        out[std::string(reinterpret_cast<const char*>(b.data() + at), 4)] = {at + 12, len};
        at += 12 + len;
    }
    return out;
}

// Recomputes every section's checksum, so that structural checks (not the checksums) must catch the lie.
void reseal(std::vector<std::uint8_t>& b) {
    for (const auto& [tag, s] : sections_of(b)) {
        const std::uint32_t crc = lodstrips::detail::crc32(b.data() + s.at, s.size);
        std::memcpy(b.data() + s.at - 4, &crc, 4);
    }
}

std::string error_of(const std::string& path) {
    try {
        read_morph_lod(path);
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        return e.what();
    }
    return "no error";
}

double max_distance(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
    double d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, double(length(a[i] - b[i])));
    return d;
}

}  // namespace

TEST(MorphFile, FloatRoundTripIsExact) {
    test::ScratchDir dir("morph-file-float");
    const Fixture& f = sphere();
    MorphWriteOptions wo;
    wo.encoding = MorphEncoding::float32;
    write_morph_lod(dir.file("s.lfmorph"), f.morph, f.lod, wo);
    const MorphLodFile r = read_morph_lod(dir.file("s.lfmorph"));
    EXPECT_EQ(r.encoding, MorphEncoding::float32);
    EXPECT_EQ(r.file_bytes, fs::file_size(dir.file("s.lfmorph")));
    EXPECT_EQ(r.file_bytes, morph_file_stats(f.morph, f.lod, wo).total_bytes);
    ASSERT_EQ(r.morph.frame_count(), f.morph.frame_count());
    for (std::size_t k = 0; k < f.morph.frame_count(); ++k) {
        EXPECT_TRUE(r.morph.frame_positions[k] == f.morph.frame_positions[k]) << k;
        EXPECT_TRUE(r.morph.frame_normals[k] == f.morph.frame_normals[k]) << k;
    }
    EXPECT_EQ(r.morph.base.indices, f.morph.base.indices);
    EXPECT_EQ(r.lod.order, f.lod.order);
    EXPECT_EQ(r.lod.levels, f.lod.levels);
    EXPECT_EQ(r.lod.triangles, f.lod.triangles);
    ASSERT_EQ(r.lod.sequences.size(), f.lod.sequences.size());
    for (std::size_t l = 0; l < 2; ++l) {
        const auto& a = r.lod.sequences[0];
        const auto& b = f.lod.sequences[0];
        EXPECT_EQ(a.level_collapses, b.level_collapses);
        EXPECT_EQ(morph_level_indices(r.morph, a, a.level_collapses[l]), morph_level_indices(f.morph, b, b.level_collapses[l]));
    }
    // Extraction from the file equals extraction from memory.
    const Mesh x = extract_morph(r.morph, r.lod, 0.37, 0.4), y = extract_morph(f.morph, f.lod, 0.37, 0.4);
    EXPECT_EQ(x.indices, y.indices);
    EXPECT_TRUE(x.positions == y.positions);
}

TEST(MorphFile, QuantisedRoundTripIsWithinTheStep) {
    test::ScratchDir dir("morph-file-q");
    for (const Fixture* f : {&sphere(), &horse()}) {
        const std::string path = dir.file("q.lfmorph");
        write_morph_lod(path, f->morph, f->lod);
        const MorphLodFile r = read_morph_lod(path);
        EXPECT_EQ(r.encoding, MorphEncoding::quantized16);
        Bounds b;
        for (const auto& fr : f->morph.frame_positions)
            for (const Vec3f& p : fr) b.add(p);
        const double step = b.diagonal() / 65535.0;  // half a step per axis, √3/2 steps at most
        for (std::size_t k = 0; k < f->morph.frame_count(); ++k)
            EXPECT_LE(max_distance(r.morph.frame_positions[k], f->morph.frame_positions[k]), step);
        EXPECT_EQ(r.morph.normals_from_input, f->morph.normals_from_input);
        for (std::size_t k = 0; k < f->morph.frame_count(); ++k)
            for (std::size_t v = 0; v < f->morph.vertex_count(); ++v)
                ASSERT_GT(dot(r.morph.frame_normals[k][v], f->morph.frame_normals[k][v]), 0.999f) << f->morph.source;
        EXPECT_EQ(r.lod.sequences[0].level_triangles, f->lod.sequences[0].level_triangles);
        EXPECT_LT(r.file_bytes, morph_file_stats(f->morph, f->lod, {MorphEncoding::float32}).total_bytes);
    }
}

TEST(MorphFile, EveryTruncationIsAFormatError) {
    test::ScratchDir dir("morph-file-trunc");
    const Fixture& f = horse();
    write_morph_lod(dir.file("h.lfmorph"), f.morph, f.lod);
    const std::vector<std::uint8_t> full = bytes_of(dir.file("h.lfmorph"));
    for (std::size_t n : {std::size_t{0}, std::size_t{4}, std::size_t{11}, std::size_t{40}, full.size() / 2, full.size() - 9,
                          full.size() - 1}) {
        write_bytes(dir.file("t.lfmorph"), std::vector<std::uint8_t>(full.begin(), full.begin() + std::ptrdiff_t(n)));
        try {
            read_morph_lod(dir.file("t.lfmorph"));
            ADD_FAILURE() << "prefix " << n << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::format) << n << ": " << e.what();
        }
    }
}

TEST(MorphFile, CorruptAndLyingFilesAreRejected) {
    test::ScratchDir dir("morph-file-bad");
    const Fixture& f = horse();
    const std::string path = dir.file("h.lfmorph");
    write_morph_lod(path, f.morph, f.lod);
    const std::vector<std::uint8_t> good = bytes_of(path);
    const std::string bad = dir.file("bad.lfmorph");
    // A flipped bit anywhere: the checksum.
    auto b = good;
    b[b.size() / 3] ^= 0x10;
    write_bytes(bad, b);
    EXPECT_NE(error_of(bad).find("checksum"), std::string::npos);
    // Wrong magic, future version.
    b = good;
    b[0] = 'X';
    write_bytes(bad, b);
    EXPECT_NE(error_of(bad).find("magic"), std::string::npos);
    b = good;
    b[8] = 9;
    write_bytes(bad, b);
    EXPECT_NE(error_of(bad).find("version 9"), std::string::npos);
    // Resealed lies: a face index out of range (the first index of section MESH).
    const std::map<std::string, Section> sec = sections_of(good);
    ASSERT_EQ(sec.size(), 4u);
    ASSERT_EQ(sec.at("HEAD").size, 4 * 8 + 4 * f.lod.levels.size());  // the layout is docs/formats/lfmorph.md's
    const std::size_t header = sec.at("MESH").at;
    b = good;
    const std::uint32_t huge = 0x7fffffffu;
    std::memcpy(b.data() + header, &huge, 4);
    reseal(b);
    write_bytes(bad, b);
    EXPECT_NE(error_of(bad).find("face 0"), std::string::npos);
    // A vertex count larger than the data.
    b = good;
    const std::uint32_t more = 9000000;
    std::memcpy(b.data() + sec.at("HEAD").at + 4, &more, 4);
    reseal(b);
    write_bytes(bad, b);
    EXPECT_NE(error_of(bad).find("truncated"), std::string::npos);
    // A move cycling back onto a removed vertex (last two moves swapped into a cycle).
    b = good;
    const std::size_t moves_end = sec.at("SEQS").at + sec.at("SEQS").size;
    std::uint32_t from = 0, to = 0;
    std::memcpy(&from, b.data() + moves_end - 8, 4);
    std::memcpy(&to, b.data() + moves_end - 4, 4);
    std::memcpy(b.data() + moves_end - 8, &to, 4);
    std::memcpy(b.data() + moves_end - 4, &from, 4);
    std::memcpy(b.data() + moves_end - 16, &from, 4);
    std::memcpy(b.data() + moves_end - 12, &to, 4);
    reseal(b);
    write_bytes(bad, b);
    const std::string cycle = error_of(bad);
    EXPECT_NE(cycle.find("sequence 0"), std::string::npos) << cycle;
    // A level table that lies about its triangle count: the first sequence's first level_triangles
    // entry, right after its frame, collapse count, move count and L level collapse counts.
    {
        b = good;
        const std::size_t L = f.lod.levels.size();
        const std::size_t seq0 = sec.at("SEQS").at;
        std::uint32_t tris = 0;
        std::memcpy(&tris, b.data() + seq0 + 12 + 4 * L, 4);
        ASSERT_EQ(tris, f.lod.sequences[0].level_triangles[0]);  // the layout is what docs/morph.md says
        tris += 1;
        std::memcpy(b.data() + seq0 + 12 + 4 * L, &tris, 4);
        reseal(b);
        write_bytes(bad, b);
        EXPECT_NE(error_of(bad).find("triangle count"), std::string::npos);
    }
    // Missing file, a directory.
    EXPECT_NE(error_of(dir.file("missing.lfmorph")).find("no such file"), std::string::npos);
    try {
        read_morph_lod(dir.path().string());
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::io);
    }
}

TEST(MorphFile, FailedWriteLeavesNothing) {
    test::ScratchDir dir("morph-file-fail");
    const Fixture& f = horse();
    const std::string path = dir.file("no/such/dir/h.lfmorph");
    EXPECT_THROW(write_morph_lod(path, f.morph, f.lod), Error);
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(MorphFile, StorageIsAtLeastFourTimesBelowTheThesis) {
    // The thesis: 472 KB per frame for FaceToFace (10,520 vertices), i.e. 45 bytes per vertex and frame.
    // The goal is 4x less; measured on the horse with all 48 frames would be slow here, so per-frame
    // bytes come from the stats of the 3-frame build (per-frame data is exact; sequence and connectivity
    // are amortised over 48 frames as in the full build).
    const Fixture& f = horse();
    const MorphFileStats st = morph_file_stats(f.morph, f.lod);
    const double per_frame = double(st.frame_bytes) + double(st.connectivity_bytes + st.sequence_bytes) / 48.0;
    const double thesis = 472.0 * 1024.0 / 10520.0 * double(f.morph.vertex_count());
    EXPECT_LE(per_frame * 4.0, thesis) << per_frame << " bytes per frame";
}

// Files written before the section container (version 1: one body, FNV-1a) are still read, and say so.
TEST(MorphFile, ReadsVersionOneFiles) {
    test::ScratchDir dir("morph-file-v1");
    const std::string v1 = test::suite_file("data/cube-v1.lfmorph");  // AnimatedMorphCube, written by version 1
    const MorphLodFile old = read_morph_lod(v1);
    EXPECT_EQ(old.version, 1u);
    EXPECT_EQ(old.morph.vertex_count(), 24u);
    EXPECT_EQ(old.morph.base.triangle_count(), 12u);
    EXPECT_EQ(old.file_bytes, fs::file_size(v1));
    ASSERT_FALSE(old.lod.sequences.empty());
    // Written again it is a version 2 file with the same content.
    write_morph_lod(dir.file("v2.lfmorph"), old.morph, old.lod, {old.encoding});
    const MorphLodFile now = read_morph_lod(dir.file("v2.lfmorph"));
    EXPECT_EQ(now.version, kMorphFileVersion);
    EXPECT_EQ(now.morph.base.indices, old.morph.base.indices);
    EXPECT_EQ(now.morph.frame_positions, old.morph.frame_positions);
    EXPECT_EQ(now.lod.levels, old.lod.levels);
    EXPECT_EQ(now.lod.sequences[0].level_triangles, old.lod.sequences[0].level_triangles);
    // A flipped byte in a version 1 file is caught by its own checksum.
    std::vector<std::uint8_t> b = bytes_of(v1);
    b[b.size() / 2] ^= 0x10;
    write_bytes(dir.file("bad.lfmorph"), b);
    EXPECT_NE(error_of(dir.file("bad.lfmorph")).find("checksum"), std::string::npos);
}
