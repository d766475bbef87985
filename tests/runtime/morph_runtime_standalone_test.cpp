// The morph LODStrips runtime header alone: no LodForge library, only core/include on the include path,
// C++17. A hand-made two-frame quad checks blending, renormalised normals and refusal of bad data; a
// per-frame file the core wrote (morph_strips_fixture) checks the change sets against each frame's own
// collapses, both call orders, coarsen-then-refine and damaged bytes.
#include "lodforge/runtime/morph_lodstrips_runtime.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

namespace {

lodstrips::MorphData quad() {
    lodstrips::MorphData m;
    lodstrips::Data& d = m.strips;
    d.vertex_count = 4;
    d.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    d.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    d.restart = true;
    d.strip_offsets = {0, 5};
    d.strip_materials = {0};
    d.initial_indices = {0, 1, 2, 3, lodstrips::restart_index};
    d.collapse_begin = {0};
    d.rewrite_begin = {0};
    d.removal_begin = {0};
    d.triangles = {2};
    m.frame_count = 2;
    m.frame_positions = d.positions;
    m.frame_normals = d.normals;
    for (int v = 0; v < 4; ++v) {
        m.frame_positions.insert(m.frame_positions.end(), {d.positions[3 * v] * 3.f, d.positions[3 * v + 1], 2.f});
        m.frame_normals.insert(m.frame_normals.end(), {1, 0, 0});
    }
    return m;
}

}  // namespace

TEST(MorphRuntimeStandalone, BlendsPositionsAndRenormalisesNormals) {
    lodstrips::MorphLodStrips rt;
    std::string why;
    ASSERT_TRUE(rt.assign(quad(), &why)) << why;
    EXPECT_EQ(rt.frame_count(), 2u);
    EXPECT_EQ(rt.vertex_count(), 4u);
    rt.set_frame(0.25);
    EXPECT_FLOAT_EQ(rt.positions()[3], 0.75f * 1.f + 0.25f * 3.f);  // vertex 1, x
    EXPECT_FLOAT_EQ(rt.positions()[5], 0.5f);                       // z
    const float* n = rt.normals();
    EXPECT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-6);
    EXPECT_NEAR(n[0], 0.25 / std::sqrt(0.25 * 0.25 + 0.75 * 0.75), 1e-6);
    rt.set_frame(1.0);
    EXPECT_FLOAT_EQ(rt.positions()[3], 3.f);
    rt.set_frame(std::nan(""));  // clamped to 0
    EXPECT_FLOAT_EQ(rt.positions()[3], 1.f);
    std::vector<std::uint32_t> tri;
    rt.triangles(tri);
    EXPECT_EQ(tri.size(), 6u);
}

TEST(MorphRuntimeStandalone, RefusesBadData) {
    lodstrips::MorphLodStrips rt;
    std::string why;
    lodstrips::MorphData m = quad();
    m.frame_positions.pop_back();
    EXPECT_FALSE(rt.assign(m, &why));
    EXPECT_NE(why.find("inconsistent"), std::string::npos);
    m = quad();
    m.strips.initial_indices[1] = 9;
    EXPECT_FALSE(rt.assign(m, &why));
    const char junk[40] = "LFMSTRPS but not really a file at all";
    EXPECT_FALSE(rt.load_memory(junk, sizeof junk, &why));
    EXPECT_FALSE(rt.load_file("/nonexistent/x.lfmstrips", &why));
}

namespace {

std::string fixture(const std::string& name) { return std::string(MORPH_STRIPS_FIXTURE_DIR) + "/" + name; }

std::vector<char> read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {(std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()};
}

struct Case {
    double t = 0, lod = 0;
    std::uint32_t set = 0;
    std::vector<std::array<std::uint32_t, 3>> faces;
};

std::vector<Case> reference() {
    const std::vector<char> b = read_all(fixture("sphere_per_frame.ref"));
    std::size_t at = 0;
    auto get = [&](auto& v) {
        if (at + sizeof v > b.size()) throw std::runtime_error("reference file truncated");
        std::memcpy(&v, b.data() + at, sizeof v);
        at += sizeof v;
    };
    std::uint32_t n = 0;
    get(n);
    std::vector<Case> out(n);
    for (Case& c : out) {
        std::uint32_t tris = 0;
        get(c.t), get(c.lod), get(c.set), get(tris);
        c.faces.resize(tris);
        for (auto& f : c.faces)
            for (std::uint32_t& v : f) get(v);
    }
    return out;
}

// The runtime's faces in the file's vertex numbering, smallest first (winding kept), sorted.
std::vector<std::array<std::uint32_t, 3>> faces(const lodstrips::MorphLodStrips& rt) {
    std::vector<std::uint32_t> tri;
    rt.triangles(tri);
    std::vector<std::array<std::uint32_t, 3>> out;
    for (std::size_t i = 0; i < tri.size(); i += 3) {
        std::array<std::uint32_t, 3> f{rt.vertex_ids()[tri[i]], rt.vertex_ids()[tri[i + 1]], rt.vertex_ids()[tri[i + 2]]};
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        out.push_back(f);
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST(MorphRuntimeStandalone, PerFrameChangeSetsDrawEachFramesOwnCollapses) {
    lodstrips::MorphLodStrips a, b;
    std::string why;
    ASSERT_TRUE(a.load_file(fixture("sphere_per_frame.lfmstrips"), &why)) << why;
    ASSERT_TRUE(b.load_file(fixture("sphere_per_frame.lfmstrips"), &why)) << why;
    EXPECT_EQ(a.change_set_count(), a.frame_count());
    const std::vector<Case> cases = reference();
    ASSERT_EQ(cases.size(), 20u);
    std::size_t sets_seen = 0, last_set = 99;
    for (const Case& c : cases) {
        a.set_frame(c.t);
        a.go_to_lod(c.lod);
        b.go_to_lod(c.lod);
        b.set_frame(c.t);
        ASSERT_EQ(a.change_set(), c.set) << c.t;
        ASSERT_EQ(faces(a), c.faces) << c.t << " " << c.lod;
        // the other call order: the same buffers
        ASSERT_EQ(b.change_set(), c.set);
        ASSERT_EQ(a.index_count(), b.index_count());
        ASSERT_TRUE(std::equal(a.indices(), a.indices() + a.index_count(), b.indices())) << c.t << " " << c.lod;
        ASSERT_EQ(a.vertex_count(), b.vertex_count());
        ASSERT_TRUE(std::equal(a.positions(), a.positions() + 3 * a.vertex_count(), b.positions()));
        ASSERT_TRUE(std::equal(a.normals(), a.normals() + 3 * a.vertex_count(), b.normals()));
        sets_seen += c.set != last_set;
        last_set = c.set;
    }
    EXPECT_GE(sets_seen, 4u);
}

TEST(MorphRuntimeStandalone, PerFrameCoarsenThenRefineIsByteIdentical) {
    lodstrips::MorphLodStrips rt;
    std::string why;
    ASSERT_TRUE(rt.load_file(fixture("sphere_per_frame.lfmstrips"), &why)) << why;
    for (double t : {0.0, 0.5, 1.0}) {
        rt.set_frame(t);
        rt.go_to_lod(1.0);
        const std::vector<std::uint32_t> full(rt.indices(), rt.indices() + rt.index_count());
        rt.go_to_lod(0.0);
        ASSERT_GT(rt.collapse_count(), 0u);
        ASSERT_FALSE(std::equal(full.begin(), full.end(), rt.indices()));
        rt.go_to_lod(1.0);
        ASSERT_TRUE(std::equal(full.begin(), full.end(), rt.indices())) << t;
    }
}

TEST(MorphRuntimeStandalone, DamagedPerFrameFilesAreRefused) {
    const std::vector<char> good = read_all(fixture("sphere_per_frame.lfmstrips"));
    ASSERT_GT(good.size(), 100u);
    lodstrips::MorphLodStrips rt;
    std::string why;
    ASSERT_TRUE(rt.load_memory(good.data(), good.size(), &why)) << why;
    std::vector<char> bad = good;
    bad[bad.size() - 20] ^= 0x08;  // inside SETS, the last section
    EXPECT_FALSE(rt.load_memory(bad.data(), bad.size(), &why));
    EXPECT_NE(why.find("SETS"), std::string::npos) << why;
    EXPECT_FALSE(rt.load_memory(good.data(), good.size() - 3, &why));
    EXPECT_NE(why.find("truncated"), std::string::npos) << why;
    EXPECT_EQ(rt.change_set_count(), 0u);  // left empty
}
