// The morph LODStrips runtime header alone: no LodForge library, only core/include on the include path,
// C++17. A hand-made two-frame quad checks blending, renormalised normals and refusal of bad data.
#include "lodforge/morph_lodstrips_runtime.h"

#include <gtest/gtest.h>

#include <cmath>

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
