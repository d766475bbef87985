// Priorities, budgets, colours and bad input of the marching-cube octree.
#include "lodforge/error.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/io/mesh_io.h"
#include "mc_test_support.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace lodforge;

namespace {

const McOctree& sphere_tree() {
    static const McOctree tree = [] {
        McOctreeParams p;
        p.resolution = 24;
        return build_mc_octree(lodforge::test::sphere_points(8000, 1.f, true), p).tree;
    }();
    return tree;
}

}  // namespace

TEST(McOctreePriority, ChildrenAreNumberedAfterTheirParent) {
    const McOctree& t = sphere_tree();
    ASSERT_EQ(t.nodes[0].priority, 1u);
    std::size_t checked = 0;
    for (const McNode& n : t.nodes) {
        if (n.level == 0) continue;
        for (int c = 0; c < std::popcount(unsigned(n.child_mask)); ++c) {
            const McNode& ch = t.nodes[n.first_child + std::uint32_t(c)];
            EXPECT_GT(ch.priority, n.priority);  // leaves are UINT32_MAX: never expanded
            ++checked;
        }
    }
    EXPECT_GT(checked, t.order.size());
    for (std::size_t k = 0; k < t.order.size(); ++k) EXPECT_EQ(t.nodes[t.order[k]].priority, k + 1);
}

TEST(McOctreePriority, NeighboursNeverDifferByTwoLevels) {
    const McOctree& t = sphere_tree();
    McOctreeExtractor ex(t);
    for (std::size_t i : {t.max_priority() / 5, t.max_priority() / 2, 4 * t.max_priority() / 5}) {
        const auto cells = ex.cells(i);
        ASSERT_FALSE(cells.empty());
        for (std::size_t a = 0; a < cells.size(); ++a)
            for (std::size_t b = a + 1; b < cells.size(); ++b) {
                const McCell &p = cells[a], &q = cells[b];
                const float eps = 1e-4f * t.cube_size;
                const bool touch = p.min.x <= q.min.x + q.size + eps && q.min.x <= p.min.x + p.size + eps &&
                                   p.min.y <= q.min.y + q.size + eps && q.min.y <= p.min.y + p.size + eps &&
                                   p.min.z <= q.min.z + q.size + eps && q.min.z <= p.min.z + p.size + eps;
                if (touch) {
                    EXPECT_LE(std::abs(int(p.level) - int(q.level)), 1) << "priority " << i;
                }
            }
    }
}

TEST(McOctreeExtract, BudgetInverseStaysWithinTheBudget) {
    const McOctree& t = sphere_tree();
    McOctreeExtractor ex(t);
    const std::uint64_t full = t.triangle_counts.back();
    for (std::uint64_t budget : {std::uint64_t(0), std::uint64_t(10), full / 7, full / 3, full / 2, full - 1, full, full * 2}) {
        const std::size_t i = ex.priority_for_triangles(budget);
        const std::size_t tris = ex.extract(i).mesh.triangle_count();
        if (i > 0) {
            EXPECT_LE(tris, budget);
        }
        // the next priority would not fit (or there is none)
        if (i < t.max_priority()) {
            EXPECT_GT(t.triangle_counts[i + 1], budget);
        }
    }
    EXPECT_EQ(ex.priority_for_triangles(full), t.max_priority());
    EXPECT_THROW(ex.extract(t.max_priority() + 1), Error);
}

TEST(McOctreeExtract, ColoursInterpolateTheInput) {
    const Mesh in = read_mesh(lodforge::test::shared_data("color-open3d-small/color.ply"));
    ASSERT_TRUE(in.has_colors() && in.has_normals());
    Mesh pts;  // a point cloud: the PLY's vertices with their normals and colours
    pts.positions = in.positions;
    pts.normals = in.normals;
    pts.colors = in.colors;
    McOctreeParams p;
    p.resolution = 40;
    p.band = 2.5;  // an open scan: end the surface near its border
    const McOctree t = build_mc_octree(pts, p).tree;
    ASSERT_TRUE(t.has_colors());
    Vec4f lo{1, 1, 1, 1}, hi{0, 0, 0, 0};
    for (const Vec4f& c : in.colors) {
        lo = {std::fmin(lo.x, c.x), std::fmin(lo.y, c.y), std::fmin(lo.z, c.z), 0};
        hi = {std::fmax(hi.x, c.x), std::fmax(hi.y, c.y), std::fmax(hi.z, c.z), 0};
    }
    for (std::size_t i : {t.max_priority() / 3, t.max_priority()}) {
        const Mesh& m = extract_mc_octree(t, i).mesh;
        ASSERT_EQ(m.colors.size(), m.positions.size());
        double diff = 0;
        for (std::size_t v = 0; v < m.positions.size(); ++v) {
            const Vec4f c = m.colors[v];
            EXPECT_TRUE(c.x >= lo.x - 1e-6f && c.x <= hi.x + 1e-6f && c.y >= lo.y - 1e-6f && c.y <= hi.y + 1e-6f &&
                        c.z >= lo.z - 1e-6f && c.z <= hi.z + 1e-6f);
            // the nearest input point's colour
            float best = std::numeric_limits<float>::max();
            std::size_t bi = 0;
            for (std::size_t k = 0; k < in.positions.size(); ++k) {
                const Vec3f d = in.positions[k] - m.positions[v];
                if (dot(d, d) < best) best = dot(d, d), bi = k;
            }
            const Vec4f ref = in.colors[bi];
            diff += (std::fabs(c.x - ref.x) + std::fabs(c.y - ref.y) + std::fabs(c.z - ref.z)) / 3;
        }
        EXPECT_LT(diff / double(m.positions.size()), 0.06) << "priority " << i;
    }
}

TEST(McOctreeBuild, MalformedInputsGiveClearErrors) {
    auto message = [](const Mesh& m, const McOctreeParams& p = {}) -> std::string {
        try {
            build_mc_octree(m, p);
        } catch (const Error& e) {
            return e.what();
        }
        return "no error";
    };
    EXPECT_NE(message(Mesh{}).find("no points"), std::string::npos);
    Mesh no_normals;
    no_normals.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    EXPECT_NE(message(no_normals).find("no normals and there are no faces"), std::string::npos);
    Mesh nan = lodforge::test::sphere_points(100);
    nan.positions[7].y = std::nanf("");
    EXPECT_NE(message(nan).find("point 7 is not finite"), std::string::npos);
    Mesh nan_normal = lodforge::test::sphere_points(100);
    nan_normal.normals[3].x = INFINITY;
    EXPECT_NE(message(nan_normal).find("normal of point 3"), std::string::npos);
    // A face past the points, with the file's normals (normals from faces checked the indices; the face
    // samples and the winding number read them either way).
    Mesh bad_face = lodforge::test::sphere_points(100);
    bad_face.indices = {0, 1, 2, 3, 4, 100};
    EXPECT_NE(message(bad_face).find("face 1 has an index out of range"), std::string::npos) << message(bad_face);
    McOctreeParams zero;
    zero.resolution = 0;
    EXPECT_NE(message(lodforge::test::sphere_points(100), zero).find("resolution"), std::string::npos);
    McOctreeParams huge;
    huge.resolution = 1000000;
    EXPECT_NE(message(lodforge::test::sphere_points(100), huge).find("resolution too high"), std::string::npos);
}

TEST(McOctreeBuild, WarnsWhenTheResolutionExceedsTheDensity) {
    McOctreeParams p;
    p.resolution = 40;  // 500 points on a unit sphere are ~0.16 apart, cubes 0.05
    const McOctreeBuildResult r = build_mc_octree(lodforge::test::sphere_points(500), p);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("exceeds the data density"), std::string::npos);
    p.resolution = 8;
    EXPECT_TRUE(build_mc_octree(lodforge::test::sphere_points(500), p).warnings.empty());

    // Uneven sampling (the bunny's scan): the median spacing is below the cube size, but there are more
    // surface cubes than points, so most cubes hold none; that is warned about too.
    const Mesh bunny = read_mesh(lodforge::test::shared_data("scan-bunny/bun_zipper.ply"));
    auto density_warning = [&](std::size_t resolution) {
        McOctreeParams q;
        q.resolution = resolution;
        const McOctreeBuildResult b = build_mc_octree(bunny, q);
        for (const std::string& w : b.warnings)
            if (w.find("exceeds the data density") != std::string::npos) {
                EXPECT_NE(w.find("surface cubes for"), std::string::npos) << w;
                EXPECT_GT(b.leaf_cubes, b.tree.input_points);
                return true;
            }
        EXPECT_LE(b.leaf_cubes, b.tree.input_points);
        return false;
    };
    EXPECT_FALSE(density_warning(64));
    EXPECT_TRUE(density_warning(100));
}

// Every edge of a cut has exactly two triangles, by vertex index and by position (docs/mcoctree.md, D6).
// Lucy at 64 had edges with four triangles at priorities 702-744 (two nodes touching along one edge, each
// fanning a diagonal along it) and a few more elsewhere; the crack-free checks did not see them, since
// every directed edge still had its opposite.
TEST(McOctreeExtract, EveryEdgeOfACutHasTwoTriangles) {
    McOctreeParams p;
    p.resolution = 64;
    const McOctree tree = build_mc_octree(read_mesh(lodforge::test::shared_data("scan-lucy100k/Lucy100k.ply")), p).tree;
    McOctreeExtractor ex(tree);
    std::vector<std::size_t> priorities;
    for (std::size_t i = 690; i <= 750 && i <= tree.max_priority(); ++i) priorities.push_back(i);
    for (std::size_t i = 0; i <= tree.max_priority(); i += 37) priorities.push_back(i);
    priorities.push_back(tree.max_priority());
    for (const std::size_t i : priorities) {
        SCOPED_TRACE("priority " + std::to_string(i));
        const Mesh& m = ex.extract(i).mesh;
        const auto w = lodforge::test::check_watertight(m);
        EXPECT_EQ(w.border_edges, 0u);
        EXPECT_EQ(w.unpaired_directed, 0u);
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> by_index;
        std::map<std::pair<std::tuple<float, float, float>, std::tuple<float, float, float>>, int> by_position;
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = m.indices[t + std::size_t(k)], b = m.indices[t + std::size_t((k + 1) % 3)];
                ++by_index[{std::min(a, b), std::max(a, b)}];
                auto pa = std::make_tuple(m.positions[a].x, m.positions[a].y, m.positions[a].z);
                auto pb = std::make_tuple(m.positions[b].x, m.positions[b].y, m.positions[b].z);
                ++by_position[{std::min(pa, pb), std::max(pa, pb)}];
            }
        std::size_t over_index = 0, over_position = 0;
        for (const auto& [e, c] : by_index) over_index += c != 2;
        for (const auto& [e, c] : by_position) over_position += c != 2;
        EXPECT_EQ(over_index, 0u);
        EXPECT_EQ(over_position, 0u);
    }
}
