// LODStrips on a morphing mesh: the strips at every tested level and frame draw exactly the faces of
// extract_morph (what `lodforge morph extract` writes), set_frame and go_to_lod commute, the file round
// trips and refuses damaged input.
#include "lodforge/error.h"
#include "lodforge/morph.h"
#include "lodforge/morph_lod.h"
#include "lodforge/morph_lodstrips.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>

namespace {

using namespace lodforge;

struct Fixture {
    MorphMesh morph;
    MorphLod lod;
    MorphStripsBuild strips;
};

const Fixture& horse() {
    static const Fixture f = [] {
        Fixture x;
        MorphLoadOptions o;
        o.frames = 5;
        x.morph = load_morph(test::shared_data("seq-horse-gallop"), o);
        MorphLodParams p;
        p.levels = {0.5f, 0.25f, 0.1f, 0.03f};
        x.lod = build_morph_lod(x.morph, p);
        x.strips = build_morph_lodstrips(x.morph, x.lod);
        return x;
    }();
    return f;
}

const Fixture& sphere() {
    static const Fixture f = [] {
        Fixture x;
        MorphLoadOptions o;
        o.frames = 9;
        x.morph = load_morph(test::shared_data("morph-animated-morph-sphere/AnimatedMorphSphere.gltf"), o);
        MorphLodParams p;
        p.levels = {0.5f, 0.1f};
        x.lod = build_morph_lod(x.morph, p);
        MorphStripsParams sp;
        sp.join = StripJoin::degenerate;  // the other join mode
        sp.max_strip_length = 32;
        x.strips = build_morph_lodstrips(x.morph, x.lod, sp);
        return x;
    }();
    return f;
}

using Tri = std::array<std::array<float, 3>, 3>;

// Triangles as position triples, rotated so the smallest corner comes first (winding kept), sorted.
std::vector<Tri> triangle_set(const std::vector<std::uint32_t>& idx, const float* pos) {
    std::vector<Tri> out;
    for (std::size_t f = 0; f + 2 < idx.size(); f += 3) {
        Tri t;
        for (int c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a) t[std::size_t(c)][std::size_t(a)] = pos[3 * std::size_t(idx[f + std::size_t(c)]) + std::size_t(a)];
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<Tri> mesh_triangle_set(const Mesh& m) {
    std::vector<float> pos;
    for (const Vec3f& p : m.positions) pos.insert(pos.end(), {p.x, p.y, p.z});
    return triangle_set(m.indices, pos.data());
}

// The faces of the runtime, in morph vertex indices, rotated and sorted.
std::vector<std::array<std::uint32_t, 3>> runtime_faces(const lodstrips::MorphLodStrips& rt, const MorphStripsBuild& b) {
    std::vector<std::uint32_t> tri;
    rt.triangles(tri);
    std::vector<std::array<std::uint32_t, 3>> out;
    for (std::size_t f = 0; f < tri.size(); f += 3) {
        std::array<std::uint32_t, 3> t{b.input_vertex[tri[f]], b.input_vertex[tri[f + 1]], b.input_vertex[tri[f + 2]]};
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<std::array<std::uint32_t, 3>> reference_faces(const Fixture& f, double lod_factor) {
    const MorphSequence& seq = f.lod.sequences.front();
    const std::vector<std::uint32_t> idx = morph_level_indices(f.morph, seq, morph_collapses_for(seq, lod_factor));
    std::vector<std::array<std::uint32_t, 3>> out;
    for (std::size_t i = 0; i < idx.size(); i += 3) {
        std::array<std::uint32_t, 3> t{idx[i], idx[i + 1], idx[i + 2]};
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
}

void expect_matches_extraction(const Fixture& f, const char* name) {
    lodstrips::MorphLodStrips rt;
    std::string why;
    ASSERT_TRUE(rt.assign(f.strips.data, &why)) << why;
    for (double lod : {1.0, 0.8, 0.5, 0.2, 0.0}) {
        for (double t : {0.0, 0.3, 0.62, 1.0}) {
            rt.set_frame(t);
            rt.go_to_lod(lod);
            const std::string where = std::string(name) + " t " + std::to_string(t) + " lod " + std::to_string(lod);
            // Same faces (in morph vertices, with winding) as the collapse replay extract_morph uses ...
            ASSERT_EQ(runtime_faces(rt, f.strips), reference_faces(f, lod)) << where;
            // ... and the same triangles in space as the mesh extract_morph returns (exact: same floats).
            const Mesh m = extract_morph(f.morph, f.lod, t, lod);
            std::vector<std::uint32_t> tri;
            rt.triangles(tri);
            ASSERT_EQ(triangle_set(tri, rt.positions()), mesh_triangle_set(m)) << where;
            // Every index the strips draw lies in the blended prefix, and the normals there are the pose's.
            for (std::uint32_t v : tri) ASSERT_LT(v, rt.vertex_count()) << where;
            std::vector<Vec3f> normals;
            morph_normals_at(f.morph, t, normals);
            for (std::size_t c = 0; c < rt.vertex_count(); c += 97) {
                const Vec3f n = normals[f.strips.input_vertex[c]];
                const float* r = rt.normals() + 3 * c;
                ASSERT_NEAR(r[0], n.x, 1e-5) << where;
                ASSERT_NEAR(r[1], n.y, 1e-5) << where;
                ASSERT_NEAR(r[2], n.z, 1e-5) << where;
                ASSERT_NEAR(std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]), 1.0, 1e-5) << where;
            }
        }
    }
}

}  // namespace

TEST(MorphLodStrips, StripsDrawTheExtractedFacesAtEveryLevelAndFrameHorse) { expect_matches_extraction(horse(), "horse"); }

TEST(MorphLodStrips, StripsDrawTheExtractedFacesAtEveryLevelAndFrameSphereDegenerateJoins) {
    expect_matches_extraction(sphere(), "sphere");
}

TEST(MorphLodStrips, OneStripSetAndOneChangeSetServeEveryFrame) {
    const Fixture& f = horse();
    const auto& d = f.strips.data;
    EXPECT_EQ(d.frame_count, f.morph.frame_count());
    EXPECT_EQ(d.strips.collapse_count(), f.lod.sequences.front().level_collapses.back());
    EXPECT_EQ(d.strips.triangles.back(), f.lod.sequences.front().level_triangles.back());
    EXPECT_EQ(d.frame_positions.size(), std::size_t(d.frame_count) * 3u * d.strips.vertex_count);
}

TEST(MorphLodStrips, SetFrameAndGoToLodCommute) {
    const Fixture& f = horse();
    lodstrips::MorphLodStrips a, b;
    ASSERT_TRUE(a.assign(f.strips.data));
    ASSERT_TRUE(b.assign(f.strips.data));
    // a path through several states; a does set_frame first, b go_to_lod first
    const std::pair<double, double> steps[] = {{0.4, 0.1}, {0.9, 0.7}, {0.05, 0.0}, {0.55, 1.0}, {1.0, 0.3}};
    for (const auto& [t, lod] : steps) {
        a.set_frame(t);
        a.go_to_lod(lod);
        b.go_to_lod(lod);
        b.set_frame(t);
        ASSERT_EQ(a.vertex_count(), b.vertex_count());
        ASSERT_TRUE(std::equal(a.indices(), a.indices() + a.index_count(), b.indices())) << t << " " << lod;
        ASSERT_TRUE(std::equal(a.draw_counts(), a.draw_counts() + a.strip_count(), b.draw_counts()));
        ASSERT_TRUE(std::equal(a.positions(), a.positions() + 3 * a.vertex_count(), b.positions())) << t << " " << lod;
        ASSERT_TRUE(std::equal(a.normals(), a.normals() + 3 * a.vertex_count(), b.normals())) << t << " " << lod;
    }
}

TEST(MorphLodStrips, ChangedSpansReproduceTheBuffers) {
    const Fixture& f = horse();
    lodstrips::MorphLodStrips rt;
    ASSERT_TRUE(rt.assign(f.strips.data));
    std::vector<std::uint32_t> gpu_idx(rt.indices(), rt.indices() + rt.index_count());
    std::vector<float> gpu_pos(rt.positions(), rt.positions() + 3 * rt.total_vertex_count());
    rt.clear_changes();
    rt.clear_vertex_changes();
    for (const auto& [t, lod] : {std::pair{0.3, 0.2}, std::pair{0.7, 0.9}, std::pair{0.2, 0.05}}) {
        rt.set_frame(t);
        rt.go_to_lod(lod);
        for (const auto& s : rt.changes()) std::copy(rt.indices() + s.offset, rt.indices() + s.offset + s.count, gpu_idx.begin() + s.offset);
        const auto vs = rt.vertex_changes();
        std::copy(rt.positions() + 3 * vs.offset, rt.positions() + 3 * (vs.offset + vs.count), gpu_pos.begin() + 3 * vs.offset);
        rt.clear_changes();
        rt.clear_vertex_changes();
        ASSERT_TRUE(std::equal(gpu_idx.begin(), gpu_idx.end(), rt.indices()));
        ASSERT_TRUE(std::equal(rt.positions(), rt.positions() + 3 * rt.vertex_count(), gpu_pos.begin()));
    }
}

TEST(MorphLodStrips, FileRoundTripsInBothEncodings) {
    const Fixture& f = sphere();
    test::ScratchDir dir("morph-strips");
    const float diag = f.morph.base.bounds().diagonal();
    for (MorphEncoding e : {MorphEncoding::float32, MorphEncoding::quantized16}) {
        const std::string path = dir.file(e == MorphEncoding::float32 ? "f.lfmstrips" : "q.lfmstrips");
        write_morph_lodstrips(f.strips.data, path, e);
        const MorphStripsStorage st = morph_lodstrips_storage(f.strips.data, e);
        EXPECT_EQ(std::filesystem::file_size(path), st.file_bytes);
        const lodstrips::MorphData d = read_morph_lodstrips(path);
        EXPECT_EQ(d.quantized, e == MorphEncoding::quantized16);
        EXPECT_EQ(d.strips.initial_indices, f.strips.data.strips.initial_indices);
        EXPECT_EQ(d.strips.rewrite_positions, f.strips.data.strips.rewrite_positions);
        ASSERT_EQ(d.frame_positions.size(), f.strips.data.frame_positions.size());
        double worst = 0, worst_n = 0;
        for (std::size_t i = 0; i < d.frame_positions.size(); ++i) {
            worst = std::max(worst, double(std::fabs(d.frame_positions[i] - f.strips.data.frame_positions[i])));
            worst_n = std::max(worst_n, double(std::fabs(d.frame_normals[i] - f.strips.data.frame_normals[i])));
        }
        if (e == MorphEncoding::float32) {
            EXPECT_EQ(worst, 0.0);
            EXPECT_EQ(worst_n, 0.0);
        } else {
            EXPECT_LE(worst, double(diag) / 65535.0);
            EXPECT_LE(worst_n, 1e-4);
        }
        lodstrips::MorphLodStrips rt;
        std::string why;
        ASSERT_TRUE(rt.load_file(path, &why)) << why;
        rt.go_to_lod(0);
        EXPECT_EQ(rt.triangle_count(), f.lod.sequences.front().level_triangles.back());
    }
}

TEST(MorphLodStrips, DamagedFilesAreRefusedWithTheFileNamed) {
    const Fixture& f = sphere();
    test::ScratchDir dir("morph-strips-bad");
    const std::string good = dir.file("good.lfmstrips");
    write_morph_lodstrips(f.strips.data, good);
    std::ifstream in(good, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto write = [&](const std::string& name, std::vector<char> b) {
        const std::string p = dir.file(name);
        std::ofstream(p, std::ios::binary).write(b.data(), std::streamsize(b.size()));
        return p;
    };
    auto expect_format_error = [&](const std::string& path, const std::string& part) {
        try {
            read_morph_lodstrips(path);
            ADD_FAILURE() << path << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::format) << e.what();
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    expect_format_error(write("trunc.lfmstrips", {bytes.begin(), bytes.begin() + std::ptrdiff_t(bytes.size() / 2)}), "truncated");
    expect_format_error(write("short.lfmstrips", {bytes.begin(), bytes.begin() + 10}), "too short");
    std::vector<char> flipped = bytes;
    flipped[bytes.size() - 7] ^= 0x10;  // inside FRMS
    expect_format_error(write("flip.lfmstrips", flipped), "FRMS checksum");
    std::vector<char> flipped2 = bytes;
    flipped2[60] ^= 0x01;  // inside the embedded strips
    expect_format_error(write("flip2.lfmstrips", flipped2), "LSTR");
    std::vector<char> version = bytes;
    version[8] = 9;
    expect_format_error(write("version.lfmstrips", version), "version");
    std::vector<char> magic = bytes;
    magic[0] = 'X';
    expect_format_error(write("magic.lfmstrips", magic), "magic");
    try {
        read_morph_lodstrips(dir.file("missing.lfmstrips"));
        ADD_FAILURE() << "a missing file was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::io);
    }
    // Frames that are not finite are refused by the runtime's assign.
    lodstrips::MorphData bad = f.strips.data;
    bad.frame_positions[5] = std::nanf("");
    lodstrips::MorphLodStrips rt;
    std::string why;
    EXPECT_FALSE(rt.assign(bad, &why));
    EXPECT_NE(why.find("not finite"), std::string::npos) << why;
}

TEST(MorphLodStrips, PerFrameOrdersAreRefusedClearly) {
    MorphLoadOptions o;
    o.frames = 3;
    const MorphMesh m = load_morph(test::shared_data("morph-animated-morph-sphere/AnimatedMorphSphere.gltf"), o);
    MorphLodParams p;
    p.order = MorphOrder::per_frame;
    p.levels = {0.5f};
    const MorphLod lod = build_morph_lod(m, p);
    try {
        build_morph_lodstrips(m, lod);
        ADD_FAILURE() << "per-frame order accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::unsupported);
        EXPECT_NE(std::string(e.what()).find("per-frame"), std::string::npos) << e.what();
    }
}

TEST(MorphLodStrips, StorageIsAtLeastFourTimesBelowTheThesis) {
    // As MorphFile's test: the thesis stores 472 KB per frame for 10,520 vertices (45 bytes per vertex and
    // frame); per-frame data is exact here, the strips and change records are amortised over the
    // horse's 48 frames.
    const Fixture& f = horse();
    const MorphStripsStorage st = morph_lodstrips_storage(f.strips.data);
    EXPECT_EQ(st.file_bytes, encode_morph_lodstrips(f.strips.data).size());
    const double per_frame = double(st.frame_bytes) + double(st.file_bytes - st.frame_bytes * f.morph.frame_count()) / 48.0;
    const double thesis = 472.0 * 1024.0 / 10520.0 * double(f.strips.data.strips.vertex_count);
    EXPECT_LE(per_frame * 4.0, thesis) << per_frame << " bytes per frame";
}
