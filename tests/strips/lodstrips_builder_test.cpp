// LODStrips builder + runtime on real meshes: every tested level equals the indexed mesh's replay.
#include "strips/lodstrips_test_util.h"

#include "lodforge/error.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace lodforge {
namespace {

using test::built;
using test::BuiltModel;

struct Case {
    std::string mesh;
    StripJoin join;
    StripOrder order = StripOrder::run_off;
};

void PrintTo(const Case& c, std::ostream* os) {
    *os << c.mesh << ' ';
    PrintTo(c.join, os);
    if (c.order == StripOrder::cache) *os << " cache order";
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    return info.param.mesh + (info.param.join == StripJoin::restart ? "_restart" : "_degenerate") +
           (info.param.order == StripOrder::cache ? "_cache" : "");
}

class LodStripsReal : public ::testing::TestWithParam<Case> {
protected:
    const BuiltModel& model() const { return built(GetParam().mesh, GetParam().join, GetParam().order); }
    lodstrips::LodStrips runtime() const {
        lodstrips::LodStrips rt;
        std::string why;
        EXPECT_TRUE(rt.assign(model().build.data, &why)) << why;
        return rt;
    }
    // About 40 levels spread over the sequence, the first few and the last.
    std::vector<std::size_t> tested_levels(std::size_t K) const {
        std::vector<std::size_t> ks = {0, 1, 2, 3, K / 2, K - 1, K};
        for (std::size_t i = 1; i < 34; ++i) ks.push_back(K * i / 34);
        std::sort(ks.begin(), ks.end());
        ks.erase(std::unique(ks.begin(), ks.end()), ks.end());
        return ks;
    }

public:
    void EveryTestedLevelEqualsTheIndexedReplayWithItsWinding();
    void CoarsenThenRefineIsByteIdentical();
    void RandomJumpsAgreeWithALinearWalk();
    void ChangedSpansBringAStaleCopyUpToDate();
    void LodFactorAndTriangleBudget();
    void StripsShrinkAndStayWithinTheRegionSize();
};

void LodStripsReal::EveryTestedLevelEqualsTheIndexedReplayWithItsWinding() {
    const BuiltModel& m = model();
    lodstrips::LodStrips rt = runtime();
    const std::size_t K = rt.collapse_count();
    ASSERT_GT(K, m.mesh.triangle_count() / 4) << "the sequence should reach far";
    EXPECT_EQ(K, m.build.simplification.collapses.size());
    std::vector<std::uint32_t> tris;
    for (std::size_t k : tested_levels(K)) {
        rt.go_to_level(k);
        ASSERT_EQ(rt.level(), k);
        rt.triangles(tris);
        const std::vector<test::Tri> got = test::sorted_tris(tris);
        const std::vector<test::Tri> want = test::reference_level(m, k);
        ASSERT_EQ(got.size(), want.size()) << "level " << k;
        ASSERT_TRUE(got == want) << "level " << k << ": triangle sets (with winding) differ";
        EXPECT_EQ(rt.triangle_count(), want.size()) << "level " << k;
        // Every index refers to a vertex the level keeps (the prefix of the canonical order).
        for (std::uint32_t v : tris) ASSERT_LT(v, rt.vertex_count_at(k)) << "level " << k;
    }
}

void LodStripsReal::CoarsenThenRefineIsByteIdentical() {
    lodstrips::LodStrips rt = runtime();
    const std::size_t K = rt.collapse_count();
    const std::vector<std::uint32_t> full(rt.indices(), rt.indices() + rt.index_count());
    const std::vector<std::int32_t> counts(rt.draw_counts(), rt.draw_counts() + rt.strip_count());
    rt.go_to_level(K / 3);
    const std::vector<std::uint32_t> third(rt.indices(), rt.indices() + rt.index_count());
    EXPECT_NE(third, full);
    rt.go_to_level(K);
    rt.go_to_level(K / 3);
    EXPECT_EQ(std::vector<std::uint32_t>(rt.indices(), rt.indices() + rt.index_count()), third);
    rt.go_to_level(0);
    EXPECT_EQ(std::vector<std::uint32_t>(rt.indices(), rt.indices() + rt.index_count()), full);
    EXPECT_EQ(std::vector<std::int32_t>(rt.draw_counts(), rt.draw_counts() + rt.strip_count()), counts);
}

void LodStripsReal::RandomJumpsAgreeWithALinearWalk() {
    lodstrips::LodStrips walk = runtime(), jump = runtime();
    const std::size_t K = walk.collapse_count();
    std::mt19937 rng(7);
    std::vector<std::size_t> targets;
    for (int i = 0; i < 12; ++i) targets.push_back(std::uniform_int_distribution<std::size_t>(0, K)(rng));
    std::vector<std::size_t> order = targets;
    std::sort(order.begin(), order.end());
    std::map<std::size_t, std::vector<std::uint32_t>> snapshot;
    for (std::size_t k = 0; k <= K; ++k) {
        walk.go_to_level(k);  // one collapse at a time
        if (std::binary_search(order.begin(), order.end(), k))
            snapshot[k] = std::vector<std::uint32_t>(walk.indices(), walk.indices() + walk.index_count());
    }
    for (std::size_t k : targets) {
        jump.go_to_level(k);
        ASSERT_EQ(std::vector<std::uint32_t>(jump.indices(), jump.indices() + jump.index_count()), snapshot[k])
            << "jump to " << k;
    }
}

void LodStripsReal::ChangedSpansBringAStaleCopyUpToDate() {
    lodstrips::LodStrips rt = runtime();
    const std::size_t K = rt.collapse_count();
    std::vector<std::uint32_t> engine(rt.indices(), rt.indices() + rt.index_count());
    std::mt19937 rng(3);
    for (int step = 0; step < 20; ++step) {
        rt.clear_changes();
        // Up to three moves between uploads (the runtime collects the spans of every level crossed).
        for (int move = 0; move <= step % 3; ++move) rt.go_to_level(std::uniform_int_distribution<std::size_t>(0, K)(rng));
        for (const auto& span : rt.changes())
            std::copy(rt.indices() + span.offset, rt.indices() + span.offset + span.count, engine.begin() + span.offset);
        ASSERT_EQ(engine, std::vector<std::uint32_t>(rt.indices(), rt.indices() + rt.index_count())) << "step " << step;
    }
}

void LodStripsReal::LodFactorAndTriangleBudget() {
    lodstrips::LodStrips rt = runtime();
    const std::size_t K = rt.collapse_count();
    rt.go_to_lod(0.0);
    EXPECT_EQ(rt.level(), K);
    rt.go_to_lod(1.0);
    EXPECT_EQ(rt.level(), 0u);
    rt.go_to_lod(0.5);
    EXPECT_NEAR(double(rt.level()), K / 2.0, 1.0);
    const std::size_t full = rt.triangle_count_at(0);
    for (std::size_t budget : {full, full / 2, full / 10, std::size_t(0)}) {
        rt.go_to_triangles(budget);
        if (rt.level() < K) {
            EXPECT_LE(rt.triangle_count(), budget);
        }
        if (rt.level() > 0) {
            EXPECT_GT(rt.triangle_count_at(rt.level() - 1), budget);
        }
    }
    // In the multi-draw layout no strip leaves its region and restart mode keeps its separators.
    rt.go_to_level(K);
    for (std::size_t s = 0; s < rt.strip_count(); ++s) {
        ASSERT_LE(rt.strip_offset(s) + rt.strip_index_count(s), rt.strip_offset(s + 1));
        if (rt.primitive_restart()) {
            EXPECT_EQ(rt.indices()[rt.strip_offset(s + 1) - 1], lodstrips::restart_index);
        }
    }
}

void LodStripsReal::StripsShrinkAndStayWithinTheRegionSize() {
    const BuiltModel& m = model();
    lodstrips::LodStrips rt = runtime();
    std::size_t full = 0, coarse = 0;
    for (std::size_t s = 0; s < rt.strip_count(); ++s) full += rt.strip_index_count(s);
    rt.go_to_level(rt.collapse_count());
    for (std::size_t s = 0; s < rt.strip_count(); ++s) coarse += rt.strip_index_count(s);
    EXPECT_LT(coarse, full / 2) << "degenerate runs should be removed as the mesh coarsens";
    EXPECT_GT(m.build.degenerate_runs_type1 + m.build.degenerate_runs_type2, 0u);
    for (std::size_t s = 0; s < rt.strip_count(); ++s)
        EXPECT_LE(rt.strip_offset(s + 1) - rt.strip_offset(s), 256u + 3u);
}

// One test per model, so ctest (a process per test) builds each model once.
TEST_P(LodStripsReal, LevelsRefinementJumpsSpansBudgets) {
    {
        SCOPED_TRACE("EveryTestedLevelEqualsTheIndexedReplayWithItsWinding");
        EveryTestedLevelEqualsTheIndexedReplayWithItsWinding();
    }
    {
        SCOPED_TRACE("CoarsenThenRefineIsByteIdentical");
        CoarsenThenRefineIsByteIdentical();
    }
    {
        SCOPED_TRACE("RandomJumpsAgreeWithALinearWalk");
        RandomJumpsAgreeWithALinearWalk();
    }
    {
        SCOPED_TRACE("ChangedSpansBringAStaleCopyUpToDate");
        ChangedSpansBringAStaleCopyUpToDate();
    }
    {
        SCOPED_TRACE("LodFactorAndTriangleBudget");
        LodFactorAndTriangleBudget();
    }
    {
        SCOPED_TRACE("StripsShrinkAndStayWithinTheRegionSize");
        StripsShrinkAndStayWithinTheRegionSize();
    }
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, LodStripsReal,
                         ::testing::Values(Case{"bunny", StripJoin::restart}, Case{"bunny", StripJoin::degenerate},
                                           Case{"spot", StripJoin::restart}, Case{"spot", StripJoin::degenerate},
                                           Case{"frag_115", StripJoin::restart},
                                           Case{"frag_115", StripJoin::degenerate},
                                           Case{"dragon_res3", StripJoin::restart},
                                           Case{"dragon_res3", StripJoin::degenerate},
                                           Case{"dragon_res4", StripJoin::restart},
                                           Case{"dragon_res4", StripJoin::degenerate},
                                           // The cache strip order (meshoptimizer's order) through the same checks.
                                           Case{"bunny", StripJoin::restart, StripOrder::cache},
                                           Case{"spot", StripJoin::degenerate, StripOrder::cache},
                                           Case{"frag_115", StripJoin::degenerate, StripOrder::cache}),
                         case_name);

TEST(LodStrips, SpotKeepsSeamWedgesAndTexcoords) {
    const BuiltModel& m = built("spot", StripJoin::restart);
    const lodstrips::Data& d = m.build.data;
    ASSERT_EQ(d.texcoords.size(), 1u);
    EXPECT_GT(d.vertex_count, m.mesh.point_count()) << "seam wedges stay separate vertices";
    for (std::uint32_t c = 0; c < d.vertex_count; ++c) {
        const std::uint32_t v = m.build.input_vertex[c];
        ASSERT_EQ(d.texcoords[0][2 * c], m.mesh.texcoords[0][v].x);
        ASSERT_EQ(d.positions[3 * c + 1], m.mesh.positions[v].y);
    }
    ASSERT_EQ(d.materials.size(), m.mesh.materials.size());
}

TEST(LodStrips, Frag115ColoursAreStoredExactlyAs8Bit) {
    const BuiltModel& m = built("frag_115", StripJoin::restart);
    const lodstrips::Data& d = m.build.data;
    EXPECT_TRUE(d.colors_8bit);
    ASSERT_EQ(d.colors.size(), 4u * d.vertex_count);
    ASSERT_EQ(d.normals.size(), 3u * d.vertex_count);
    const std::uint32_t v = m.build.input_vertex[17];
    EXPECT_EQ(d.colors[4 * 17], m.mesh.colors[v].x);
    EXPECT_EQ(d.normals[3 * 17 + 2], m.mesh.normals[v].z);
}

TEST(LodStrips, MaterialsFollowTheirFaces) {
    const BuiltModel& m = built("truck", StripJoin::restart);
    lodstrips::LodStrips rt;
    ASSERT_TRUE(rt.assign(m.build.data));
    const Mesh full = lodstrips_mesh(rt);
    ASSERT_EQ(full.materials.size(), m.mesh.materials.size());
    ASSERT_EQ(full.face_materials.size(), full.triangle_count());
    // Per material, the extracted triangles equal the input's faces of that material.
    std::vector<std::uint32_t> base = replay_collapses(m.mesh, m.build.simplification, 0);
    std::map<std::uint32_t, std::vector<std::uint32_t>> want, got;
    std::size_t f = 0;
    for (std::size_t i = 0; i < base.size(); i += 3) {
        while (!std::equal(base.begin() + i, base.begin() + i + 3, m.mesh.indices.begin() + 3 * f)) ++f;
        for (int k = 0; k < 3; ++k) want[m.mesh.face_materials[f]].push_back(m.build.canonical[base[i + k]]);
        ++f;
    }
    for (std::size_t t = 0; t < full.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) got[full.face_materials[t]].push_back(full.indices[3 * t + k]);
    ASSERT_EQ(got.size(), want.size());
    for (auto& [mat, list] : want) EXPECT_TRUE(test::sorted_tris(list) == test::sorted_tris(got[mat])) << "material " << mat;
}

TEST(LodStrips, BadParametersAndEmptyMeshes) {
    Mesh empty;
    EXPECT_THROW(build_lodstrips(empty), Error);
    const Mesh& m = built("dragon_res4", StripJoin::restart).mesh;
    LodStripsParams p;
    p.max_strip_length = 4;
    EXPECT_THROW(build_lodstrips(m, p), Error);
    p = {};
    p.coarsest_ratio = 2.f;
    EXPECT_THROW(build_lodstrips(m, p), Error);
}

TEST(LodStrips, CancelledBuildThrowsCancelled) {
    CancelFlagProgress progress;
    progress.cancel();
    const Mesh& m = built("dragon_res4", StripJoin::restart).mesh;
    try {
        build_lodstrips(m, {}, &progress);
        FAIL() << "no exception";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::cancelled);
    }
}

}  // namespace
}  // namespace lodforge
