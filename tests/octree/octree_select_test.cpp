#include "lodforge/error.h"
#include "lodforge/octree/octree_build.h"
#include "lodforge/octree/octree_select.h"

#include "octree_test_util.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

namespace lodforge {
namespace {

using test::ScratchDir;
using test::shared_data;

class OctreeSelect : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new ScratchDir("octree-select");
        OctreeBuildParams p;
        p.max_triangles = 300;
        build_octree(shared_data("scan-happy-buddha/happy_vrip_res3.ply"), dir_->file("b.lfo"), p);
    }
    static void TearDownTestSuite() { delete dir_; }
    static ScratchDir* dir_;
};
ScratchDir* OctreeSelect::dir_ = nullptr;

Camera looking_at(const OctreeStore& s, float distance_in_diagonals) {
    const Bounds& b = s.header().bounds;
    Camera c;
    c.target = b.center();
    c.eye = b.center() + Vec3f{0, 0, b.diagonal() * distance_in_diagonals};
    c.fov_y_degrees = 50;
    return c;
}

TEST_F(OctreeSelect, FartherAndLooserMeansFewerTriangles) {
    OctreeStore store(dir_->file("b.lfo"));
    std::uint64_t previous = ~0ull;
    for (float d : {2.f, 4.f, 8.f, 40.f}) {
        const SelectResult r = select_cut(store, looking_at(store, d));
        ASSERT_TRUE(is_valid_cut(store, r.cut, true));
        EXPECT_EQ(r.culled_nodes, 0u) << "the whole model is in view at distance " << d;
        ASSERT_TRUE(is_valid_cut(store, r.cut)) << d;
        EXPECT_LE(r.triangles, previous) << d;
        previous = r.triangles;
        // Every node drawn simplified really is within tolerance; every refined one is not.
        const Camera cam = looking_at(store, d);
        for (const CutNode& c : r.cut) {
            if (!c.raw) {
                EXPECT_LE(projected_error_pixels(store.node(c.node), cam), 1.0);
            }
        }
        // Watertight although levels are mixed.
        const Mesh m = extract_mesh(store, r.cut);
        EXPECT_EQ(m.triangle_count(), r.triangles);
        EXPECT_EQ(test::edge_counts(m).border, 0u) << d;
    }
    EXPECT_LT(previous, store.header().input_triangles / 4);
    SelectParams loose;
    loose.screen_error_pixels = 50;
    EXPECT_LT(select_cut(store, looking_at(store, 2.f), loose).triangles, select_cut(store, looking_at(store, 2.f)).triangles);
}

TEST_F(OctreeSelect, FrustumCullsWhatIsBehindOrBesideTheCamera) {
    OctreeStore store(dir_->file("b.lfo"));
    const Bounds& b = store.header().bounds;
    Camera away = looking_at(store, 2.f);
    away.target = away.eye + (away.eye - away.target);  // looking away from the model
    const SelectResult none = select_cut(store, away);
    EXPECT_TRUE(none.cut.empty());
    EXPECT_GE(none.culled_nodes, 1u);
    // Close up on the top half: the lower nodes go.
    Camera top;
    top.target = {b.center().x, b.max.y - 0.1f * b.size().y, b.center().z};
    top.eye = top.target + Vec3f{0, 0, 0.15f * b.diagonal()};
    top.fov_y_degrees = 30;
    const SelectResult part = select_cut(store, top);
    EXPECT_GT(part.culled_nodes, 0u);
    EXPECT_FALSE(part.cut.empty());
    for (const CutNode& c : part.cut) EXPECT_TRUE(in_frustum(store.node(c.node), top));
    // Loading through the bounded cache: a small limit is respected.
    OctreeStore small(dir_->file("b.lfo"), 256u << 10);
    extract_mesh(small, part.cut);
    EXPECT_LE(small.cache_bytes(), small.cache_limit());
    EXPECT_GT(small.cache_misses(), 0u);
    extract_mesh(small, select_cut(small, top).cut);
    EXPECT_GT(small.cache_hits(), 0u);
}

TEST_F(OctreeSelect, BadCamerasAreRefused) {
    OctreeStore store(dir_->file("b.lfo"));
    Camera c = looking_at(store, 2.f);
    c.fov_y_degrees = 0;
    EXPECT_THROW(select_cut(store, c), Error);
    c = looking_at(store, 2.f);
    c.target = c.eye;
    EXPECT_THROW(select_cut(store, c), Error);
    SelectParams p;
    p.screen_error_pixels = 0;
    EXPECT_THROW(select_cut(store, looking_at(store, 2.f), p), Error);
}

}  // namespace
}  // namespace lodforge
