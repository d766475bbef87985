// Priority levels of the marching-cube octree: the triangle count never decreases with the priority, the
// table is what the extraction really produces, and every level is still crack-free (docs/mcoctree.md, D10).
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/io/mesh_io.h"
#include "mc_test_support.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace lodforge;

namespace {

struct Case {
    const char* name;
    Mesh points;
    double band;
    bool closed;
};

Case bunny_points() {
    const Mesh bunny = read_mesh(lodforge::test::shared_data("scan-bunny/bun_zipper.ply"));
    Mesh pts;  // the scan's points: normals from the faces inside build_mc_octree
    pts.positions = bunny.positions;
    pts.indices = bunny.indices;
    return {"bunny points", pts, 0, true};
}

Case frag_points() {
    const Mesh frag = read_mesh(lodforge::test::shared_data("color-open3d-frag115/frag_115.ply"));
    Mesh pts;  // a coloured RGB-D point cloud with normals; open, so the surface ends near its border
    pts.positions = frag.positions;
    pts.normals = frag.normals;
    pts.colors = frag.colors;
    return {"frag_115", pts, 2.5, false};
}

void check_levels(const Case& c, std::size_t resolution, std::size_t extract_every) {
    SCOPED_TRACE(std::string(c.name) + " at resolution " + std::to_string(resolution));
    McOctreeParams p;
    p.resolution = resolution;
    p.band = c.band;
    const McOctreeBuildResult r = build_mc_octree(c.points, p);
    const McOctree& t = r.tree;
    ASSERT_GT(t.max_priority(), 500u);
    ASSERT_EQ(t.triangle_counts.size(), t.max_priority() + 1);
    ASSERT_EQ(t.cuts.size(), t.max_priority() + 1);
    EXPECT_EQ(t.cuts.front(), 0u);
    EXPECT_EQ(t.cuts.back(), t.order.size());
    // Every priority: the table never decreases, and each level expands more nodes than the one before.
    for (std::size_t i = 1; i <= t.max_priority(); ++i) {
        ASSERT_GE(t.triangle_counts[i], t.triangle_counts[i - 1]) << "priority " << i;
        ASSERT_GT(t.cuts[i], t.cuts[i - 1]) << "priority " << i;
    }
    // Left out: about one cut per refinement that removes triangles, and (open scans) the cuts late in the
    // order with more triangles than the full-resolution mesh.
    EXPECT_EQ(t.order.size() + 1, t.cuts.size() + r.hidden_cuts);
    EXPECT_LE(r.hidden_cuts * (c.closed ? 100 : 10), t.order.size());
    EXPECT_GT(t.triangle_counts.back(), 20 * std::max<std::uint64_t>(1, t.triangle_counts[1]));

    // The real extraction, on a dense sample of the priorities (every one where the tree is small): the
    // count is the table's, hence non-decreasing too; closed input stays closed.
    McOctreeExtractor ex(t);
    std::uint64_t previous = 0;
    std::size_t checked = 0;
    std::vector<std::size_t> sample;
    for (std::size_t i = 0; i < t.max_priority(); i += extract_every) sample.push_back(i);
    sample.push_back(t.max_priority());
    const std::size_t watertight_every = sample.size() / 12 + 1;  // the check is slow (std::map welding)
    for (const std::size_t i : sample) {
        const McExtraction& e = ex.extract(i);
        const std::uint64_t tris = e.mesh.triangle_count();
        ASSERT_EQ(tris, t.triangle_counts[i]) << "priority " << i;
        ASSERT_GE(tris, previous) << "priority " << i;
        previous = tris;
        // every output vertex is used by a triangle (seam nodes output only the crossings they use)
        std::vector<bool> referenced(e.mesh.positions.size(), false);
        for (const std::uint32_t v : e.mesh.indices) referenced[v] = true;
        ASSERT_EQ(std::count(referenced.begin(), referenced.end(), false), 0) << "priority " << i;
        if (c.points.has_colors()) {
            ASSERT_EQ(e.mesh.colors.size(), e.mesh.positions.size()) << "priority " << i;
        }
        if (c.closed && (checked % watertight_every == 0 || i == t.max_priority())) {
            const auto w = lodforge::test::check_watertight(e.mesh);
            EXPECT_EQ(w.border_edges, 0u) << "priority " << i;
            EXPECT_EQ(w.unpaired_directed, 0u) << "priority " << i;
        }
        ++checked;
    }
    EXPECT_EQ(previous, t.triangle_counts.back());
    EXPECT_GT(checked, 400u);
}

}  // namespace

TEST(McOctreePriority, BunnyPointsCountIsMonotoneAtEveryPriority) {
    const Case c = bunny_points();
    check_levels(c, 48, 1);
    check_levels(c, 96, 7);
}

TEST(McOctreePriority, Frag115CountIsMonotoneAtEveryPriority) {
    const Case c = frag_points();
    check_levels(c, 40, 1);
    check_levels(c, 96, 7);
}
