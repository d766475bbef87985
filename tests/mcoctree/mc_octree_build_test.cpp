// Building and extracting the marching-cube octree on closed inputs: watertight at every priority.
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"
#include "mc_test_support.h"
#include "support/needle.h"
#include "support/test_paths.h"
#include "parallel_for.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <new>

using namespace lodforge;
using lodforge::test::check_watertight;
using lodforge::test::expect_same_tree;

TEST(McOctreeBuild, SphereIsClosedAtEveryPriority) {
    const Mesh pts = lodforge::test::sphere_points(20000);
    McOctreeParams p;
    p.resolution = 32;
    const McOctreeBuildResult r = build_mc_octree(pts, p);
    const McOctree& t = r.tree;
    ASSERT_GT(t.max_priority(), 10u);
    McOctreeExtractor ex(t);
    std::size_t transitions = 0;
    for (std::size_t k = 0; k <= 40; ++k) {
        const std::size_t i = k * t.max_priority() / 40;
        const McExtraction& e = ex.extract(i);
        transitions += e.transition_nodes;
        EXPECT_EQ(e.mesh.triangle_count(), t.triangle_counts[i]) << i;
        const auto w = check_watertight(e.mesh);
        EXPECT_EQ(w.border_edges, 0u) << "priority " << i;
        EXPECT_EQ(w.unpaired_directed, 0u) << "priority " << i;
        if (HasFailure()) break;
    }
    EXPECT_GT(transitions, 0u);
    for (std::size_t i = 1; i < t.triangle_counts.size(); ++i)
        EXPECT_GE(t.triangle_counts[i], t.triangle_counts[i - 1]) << "priority " << i;
}

namespace {

McOctree bunny_tree(std::size_t resolution) {
    const Mesh bunny = read_mesh(lodforge::test::shared_data("scan-bunny/bun_zipper.ply"));
    Mesh pts;  // the scan's points alone: normals come from the faces inside build_mc_octree
    pts.positions = bunny.positions;
    pts.indices = bunny.indices;
    McOctreeParams p;
    p.resolution = resolution;
    return build_mc_octree(pts, p).tree;
}

}  // namespace

TEST(McOctreeBuild, BunnyPointsAreClosedAtEveryPriorityAndCountsAreMonotone) {
    const McOctree t = bunny_tree(48);
    McOctreeExtractor ex(t);
    for (std::size_t k = 0; k <= 24; ++k) {
        const std::size_t i = k * t.max_priority() / 24;
        const McExtraction& e = ex.extract(i);
        EXPECT_EQ(e.mesh.triangle_count(), t.triangle_counts[i]);
        const auto w = check_watertight(e.mesh);
        EXPECT_EQ(w.border_edges, 0u) << "priority " << i;
        EXPECT_EQ(w.unpaired_directed, 0u) << "priority " << i;
    }
    // Non-decreasing at every priority (D10); mc_octree_priority_test.cpp checks the extraction everywhere.
    for (std::size_t i = 1; i < t.triangle_counts.size(); ++i)
        EXPECT_GE(t.triangle_counts[i], t.triangle_counts[i - 1]) << "priority " << i;
    EXPECT_GT(t.triangle_counts.back(), 20 * std::max<std::uint64_t>(1, t.triangle_counts[1]));
}

TEST(McOctreeBuild, CancelStopsTheBuildAndWritesNothing) {
    struct CancelAfter : Progress {
        int left;
        explicit CancelAfter(int n) : left(n) {}
        void report(double, std::string_view) override { --left; }
        bool cancelled() const override { return left <= 0; }
    };
    const Mesh pts = lodforge::test::sphere_points(5000);
    McOctreeParams p;
    p.resolution = 24;
    for (int after : {1, 3, 6}) {
        CancelAfter progress(after);
        try {
            build_mc_octree(pts, p, &progress);
            ADD_FAILURE() << "not cancelled after " << after << " reports";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::cancelled);
        }
    }
    lodforge::test::ScratchDir dir("mco-cancel");
    const McOctree t = build_mc_octree(pts, p).tree;
    CancelAfter now(0);
    EXPECT_THROW(write_mc_octree(t, dir.file("x.mco"), &now), Error);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(McOctreeBuild, SkippedPointsAreReported) {
    Mesh m = lodforge::test::sphere_points(4000);
    m.normals[10] = Vec3f{};
    m.normals[11] = Vec3f{};
    McOctreeParams p;
    p.resolution = 16;
    const auto r = build_mc_octree(m, p);
    ASSERT_FALSE(r.warnings.empty());
    EXPECT_NE(r.warnings[0].find("2 of 4000 points have no usable normal"), std::string::npos) << r.warnings[0];
    EXPECT_EQ(r.tree.input_points, 3998u);
}

TEST(McOctreeBuild, FacesThatCancelGiveNoNormal) {
    // A triangle listed twice with opposite windings, starting at different corners: the two cross
    // products round differently, and their sum used to be noise with an arbitrary direction, used as
    // the point's orientation. Its three points must be skipped like points without faces.
    Mesh m = read_mesh(lodforge::test::shared_data("scan-bunny/bun_zipper.ply"));
    McOctreeParams p;
    p.resolution = 32;
    const auto base = build_mc_octree(m, p);
    // Just outside the bunny's box; the second copy starts at the second corner.
    const auto n = static_cast<std::uint32_t>(m.positions.size());
    const Vec3f a{0.0733091012f, 0.191891015f, 0.0619096979f}, b{0.0827091038f, 0.200421005f, 0.0658297017f},
        c{0.0769091025f, 0.206621006f, 0.0758996978f};
    m.positions.insert(m.positions.end(), {a, b, c});
    for (std::uint32_t i : {n, n + 1, n + 2, n + 1, n, n + 2}) m.indices.push_back(i);
    const Vec3f sum = cross(b - a, c - a) + cross(a - b, c - b);  // as the build sums them
    ASSERT_GT(length(sum), 0.f) << "the fixture must leave rounding noise, not an exact zero";
    const auto r = build_mc_octree(m, p);
    EXPECT_EQ(r.tree.input_points, base.tree.input_points);
    ASSERT_FALSE(r.warnings.empty());
    const std::string skipped = std::to_string(n - base.tree.input_points + 3) + " of " + std::to_string(n + 3);
    EXPECT_NE(r.warnings.back().find(skipped + " points have no usable normal"), std::string::npos)
        << r.warnings.back();
}

TEST(McOctreeBuild, BadlyOrientedScanStaysWithinItsBounds) {
    // The happy Buddha's res3 scan repeats triangles with both windings and has folds whose faces
    // disagree in orientation. The nearest point's normal decides the side of far lattice points, so one
    // such point on the hull used to put a sheet of surface out to the grid's edge (at 128: x up to 0.34
    // for a model ending at 0.035). Every extracted vertex lies within a few cubes of the input's box. At
    // 256 its faces are longer than two cubes: samples oriented by area-weighted vertex normals did the
    // same (1.39 diagonals); with pseudo-normals and the winding number (the doubled faces cancel in it)
    // the leaves are 1.3 % of the diagonal from the input.
    const Mesh buddha = read_mesh(lodforge::test::shared_data("scan-happy-buddha/happy_vrip_res3.ply"));
    const Bounds in = buddha.bounds();
    for (const std::size_t resolution : {64u, 128u, 256u}) {
        McOctreeParams p;
        p.resolution = resolution;
        const McOctree t = build_mc_octree(buddha, p).tree;
        const Mesh leaves = McOctreeExtractor(t).extract(t.max_priority()).mesh;
        ASSERT_FALSE(leaves.positions.empty());
        const Bounds out = leaves.bounds();
        const float slack = 3 * t.cube_size;
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(out.min[a], in.min[a] - slack) << "resolution " << resolution << ", axis " << a;
            EXPECT_LE(out.max[a], in.max[a] + slack) << "resolution " << resolution << ", axis " << a;
        }
    }
}

TEST(McOctreeBuild, AnOpenInputThatRunsToTheGridsEdgeIsWarnedAbout) {
    // frag_115 is one side of a room: without a band its zero set runs on until the grid's boundary
    // closes it. The build says so and names the fix; with the band, or on a closed input, it does not.
    const Mesh frag = read_mesh(lodforge::test::shared_data("color-open3d-frag115/frag_115.ply"));
    McOctreeParams p;
    p.resolution = 32;
    const auto open = build_mc_octree(frag, p);
    EXPECT_TRUE(open.reaches_grid_edge);
    ASSERT_FALSE(open.warnings.empty());
    EXPECT_NE(open.warnings.back().find("the surface runs to the grid's edge ("), std::string::npos)
        << open.warnings.back();
    EXPECT_NE(open.warnings.back().find("--band"), std::string::npos);
    p.band = 2.5;
    const auto banded = build_mc_octree(frag, p);
    EXPECT_FALSE(banded.reaches_grid_edge);
    for (const std::string& w : banded.warnings) EXPECT_EQ(w.find("grid's edge"), std::string::npos) << w;
    McOctreeParams q;
    q.resolution = 32;
    const auto sphere = build_mc_octree(lodforge::test::sphere_points(4000), q);
    EXPECT_FALSE(sphere.reaches_grid_edge);
    for (const std::string& w : sphere.warnings) EXPECT_EQ(w.find("grid's edge"), std::string::npos) << w;
}

TEST(McOctreeBuild, DragonScanWithHolesIsClosedAtEveryPriority) {
    // Bridges across the scan's holes reach coarse levels the first flood did not: the build floods them
    // too (docs/mcoctree.md, D2), or coarse cuts would have holes here.
    const Mesh dragon = read_mesh(lodforge::test::shared_data("scan-dragon/dragon_vrip_res3.ply"));
    McOctreeParams p;
    p.resolution = 64;
    const McOctree t = build_mc_octree(dragon, p).tree;
    McOctreeExtractor ex(t);
    for (std::size_t k = 0; k <= 12; ++k) {
        const std::size_t i = k * t.max_priority() / 12;
        const auto w = check_watertight(ex.extract(i).mesh);
        EXPECT_EQ(w.border_edges, 0u) << "priority " << i;
        EXPECT_EQ(w.unpaired_directed, 0u) << "priority " << i;
    }
}

namespace {

McOctreeBuildResult build_with(const Mesh& m, McOctreeParams p, McFieldMethod field, unsigned threads) {
    p.field = field;
    p.threads = threads;
    return build_mc_octree(m, p);
}

}  // namespace

TEST(McOctreeBuild, FieldMethodsAndThreadCountsGiveTheSameTree) {
    // The field is the nearest point with ties to the lowest index (docs/mcoctree.md, D1), whether it is
    // found by scattering the points or by kd-tree queries, on one thread or two. frag_115: colours,
    // an open scan with a band; the bunny's points: normals from faces; the Duck at 64: a low-poly mesh,
    // face samples and the winding number's sign (made on both threads after a scatter).
    const Mesh frag = read_mesh(lodforge::test::shared_data("color-open3d-frag115/frag_115.ply"));
    const Mesh bunny = read_mesh(lodforge::test::shared_data("scan-bunny/bun_zipper.ply"));
    const Mesh duck = read_mesh(lodforge::test::shared_data("tex-duck/glTF/Duck.gltf"));
    struct Case {
        const Mesh* mesh;
        std::size_t resolution;
        double band;
    };
    for (const Case& c : {Case{&frag, 64, 2.5}, Case{&bunny, 96, 0}, Case{&duck, 64, 0}}) {
        McOctreeParams p;
        p.resolution = c.resolution;
        p.band = c.band;
        const McOctreeBuildResult queries = build_with(*c.mesh, p, McFieldMethod::queries, 1);
        const McOctreeBuildResult scatter = build_with(*c.mesh, p, McFieldMethod::scatter, 2);
        EXPECT_EQ(queries.scattered_samples, 0u);
        EXPECT_GT(scatter.scattered_samples, scatter.field_samples / 2);
        EXPECT_GT(queries.tree.nodes.size(), 1000u);
        expect_same_tree(queries.tree, scatter.tree, "queries, 1 thread / scatter, 2 threads");
        expect_same_tree(queries.tree, build_with(*c.mesh, p, McFieldMethod::queries, 2).tree, "queries, 2 threads");
        expect_same_tree(queries.tree, build_with(*c.mesh, p, McFieldMethod::scatter, 1).tree, "scatter, 1 thread");
    }
}

TEST(McOctreeBuild, DuplicatePointsAreOnePoint) {
    // Points at the same position are merged into the first, with the sum of their normals
    // (docs/mcoctree.md, D1). Copies with flipped normals cancel: the first's own normal stays, so the tree
    // is the one without the copies. Copies with another normal: the tree is that of the input whose
    // points carry the normalised sum. With either method of evaluating the field.
    const Mesh sphere = lodforge::test::sphere_points(6000);
    Mesh flipped = sphere, tilted = sphere, summed = sphere;
    for (std::size_t i = 0; i < sphere.positions.size(); i += 3) {
        flipped.positions.push_back(sphere.positions[i]);
        flipped.normals.push_back(sphere.normals[i] * -1.f);
        const Vec3f other{0.f, 1.f, 0.f};
        tilted.positions.push_back(sphere.positions[i]);
        tilted.normals.push_back(other);
        const Vec3f sum = sphere.normals[i] + other;
        if (length(sum) > 0) summed.normals[i] = sum * (1.f / length(sum));
    }
    McOctreeParams p;
    p.resolution = 40;
    for (const McFieldMethod m : {McFieldMethod::queries, McFieldMethod::scatter}) {
        const char* what = m == McFieldMethod::queries ? "queries" : "scatter";
        const McOctree plain = build_with(sphere, p, m, 2).tree;
        expect_same_tree(plain, build_with(flipped, p, m, 2).tree, what);
        const McOctree tilted_tree = build_with(tilted, p, m, 2).tree;
        // (the build normalises the sum itself; the test's normalised input differs from it by rounding)
        expect_same_tree(build_with(summed, p, m, 2).tree, tilted_tree, what, false);
        EXPECT_NE(plain.positions, tilted_tree.positions) << what;  // the merged normals do matter
        EXPECT_EQ(tilted_tree.input_points, sphere.positions.size());
    }
}

TEST(McOctreeBuild, AnExceptionOnTheHelperThreadReachesTheCaller) {
    // The build runs the kd-tree's construction beside the scatter (docs/mcoctree.md, D1) and the
    // neighbour table beside the vertices through run_beside: a bad_alloc there must arrive here, after
    // both sides have ended, instead of ending the process.
    bool here_ran = false;
    EXPECT_THROW(lodforge::detail::run_beside(
                     2, [&] { here_ran = true; }, [] { throw std::bad_alloc(); }),
                 std::bad_alloc);
    EXPECT_TRUE(here_ran);
    bool beside_ran = false;
    EXPECT_THROW(lodforge::detail::run_beside(
                     2, [] { throw Error(Error::Kind::invalid, "here"); }, [&] { beside_ran = true; }),
                 Error);
    EXPECT_TRUE(beside_ran);
    int order = 0;
    lodforge::detail::run_beside(1, [&] { order = order * 10 + 1; }, [&] { order = order * 10 + 2; });
    EXPECT_EQ(order, 12);
}

TEST(McOctreeBuild, CancelDuringTheNumberingEndsItsCountingThread) {
    // The seam counts run on a second thread while the heap numbers the nodes (docs/mcoctree.md, fourth
    // round); a cancel inside the heap must end that thread too and arrive as Error(cancelled). The bunny's
    // points at 128 have more than 16,384 internal nodes, so the heap reports (and polls) at least once.
    struct CancelInHeap : Progress {
        double at = 0;
        void report(double fraction, std::string_view stage) override {
            if (stage == "mcoctree: priorities" && fraction > 0.8 && at == 0) at = fraction;
        }
        bool cancelled() const override { return at > 0; }
    };
    const Mesh bunny = read_mesh(lodforge::test::shared_data("scan-bunny/bun_zipper.ply"));
    McOctreeParams p;
    p.resolution = 128;
    for (const unsigned threads : {1u, 2u}) {
        p.threads = threads;
        CancelInHeap progress;
        try {
            build_mc_octree(bunny, p, &progress);
            ADD_FAILURE() << "not cancelled, " << threads << " threads";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::cancelled);
        }
        EXPECT_GT(progress.at, 0.8) << "the cancel came from the heap's own report";
        EXPECT_LT(progress.at, 1.0);
    }
}

TEST(McOctreeBuild, HashedBlocksOfALargeGridGiveTheSameLeavesAsTheTiledOnes) {
    // The field's and the flood's blocks are found by position (tiles) up to a root grid of 2048 cubes
    // and by hashing above (mc_octree_build.cpp, Blocks). A sphere alone (grid 128: tiles) and with a far
    // copy (grid 16384: hashed) has the same lattice around the first sphere (same lower box corner, same
    // cube size), so its leaves there must be the same cubes with the same corner signs. 12,000 points per
    // sphere and 50 cubes of radius: the field is scattered (on two threads for the pair).
    const Mesh a = lodforge::test::sphere_points(12000);
    Mesh pair = a;
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
        pair.positions.push_back(a.positions[i] + Vec3f{300, 0, 0});
        pair.normals.push_back(a.normals[i]);
    }
    McOctreeParams p;
    p.cube_size = 0.02;
    p.threads = 2;
    const McOctreeBuildResult alone = build_mc_octree(a, p);
    const McOctreeBuildResult both = build_mc_octree(pair, p);
    ASSERT_LE(alone.tree.levels, 10u);
    ASSERT_GE(both.tree.levels, 11u);
    EXPECT_GT(both.scattered_samples, 0u);
    using Leaf = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>;
    auto leaves_near_origin = [](const McOctree& t) {
        std::vector<Leaf> out;
        for (const McNode& n : t.nodes)
            if (n.level == 0 && float(n.x) * t.cube_size < 150) out.emplace_back(n.x, n.y, n.z, n.inside);
        std::sort(out.begin(), out.end());
        return out;
    };
    const std::vector<Leaf> dense = leaves_near_origin(alone.tree);
    EXPECT_GT(dense.size(), 10000u);
    EXPECT_EQ(dense, leaves_near_origin(both.tree));
    EXPECT_GT(both.tree.leaf_count(), dense.size() + 10000);  // the copy has its leaves too
    // On the hashed blocks as well, the field does not depend on the method or the thread count (D1).
    expect_same_tree(both.tree, build_with(pair, p, McFieldMethod::queries, 1).tree, "hashed, queries, 1 thread");
}

TEST(McOctreeBuild, AFlatAxisAlignedCloudHasASurfaceAtItsPlane) {
    // A planar grid of points with normals +z: its lattice plane is on every point's tangent plane, so it
    // counts as outside (D1) and the cubes holding the points have no sign change; only the cubes below
    // do. Those must be seeded too, or the build finds no surface. Several heights, so that the points
    // fall on either side of the lattice plane's rounding, and with and without a band.
    for (const float z0 : {0.f, 0.5f, 1.f / 3.f, -0.7f}) {
        for (const double band : {0.0, 2.0}) {
            SCOPED_TRACE(testing::Message() << "z " << z0 << ", band " << band);
            Mesh pts;
            for (int i = 0; i <= 40; ++i)
                for (int j = 0; j <= 40; ++j) {
                    pts.positions.push_back({float(i) / 40, float(j) / 40, z0});
                    pts.normals.push_back({0, 0, 1});
                }
            McOctreeParams p;
            p.resolution = 32;
            p.band = band;
            McOctreeBuildResult r;
            ASSERT_NO_THROW(r = build_mc_octree(pts, p));
            McOctreeExtractor ex(r.tree);
            const Mesh& m = ex.extract(r.tree.max_priority()).mesh;
            ASSERT_GT(m.triangle_count(), 0u);
            // The triangles within a cube size of the plane, over the cloud's square, cover that square.
            const float h = r.tree.cube_size;
            double area = 0;
            for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
                const Vec3f a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                            c = m.positions[m.indices[t + 2]];
                const Vec3f centre = (a + b + c) * (1.f / 3);
                if (std::fabs(a.z - z0) > h || std::fabs(b.z - z0) > h || std::fabs(c.z - z0) > h) continue;
                if (centre.x < 0 || centre.x > 1 || centre.y < 0 || centre.y > 1) continue;
                area += 0.5 * double(length(cross(b - a, c - a)));
            }
            EXPECT_NEAR(area, 1.0, 0.05);
            const auto w = check_watertight(m);
            if (band == 0) {  // with a band the surface is open along the cloud's border (D2)
                EXPECT_EQ(w.border_edges, 0u);
                EXPECT_EQ(w.unpaired_directed, 0u);
            }
            EXPECT_EQ(w.degenerate, 0u);
        }
    }
}

TEST(McOctreeBuild, LatticePointsOnTheSurfaceGiveNoZeroAreaTriangles) {
    // A sphere of radius 5 with cubes of 1/4: its integer points ((5,0,0), (3,4,0), ... 30 of them) are
    // lattice points (the box's corner and the cube size are exact in float), and input points, so the
    // field is 0 there. Each has two or more inside neighbours, whose edges' vertices used to meet at it.
    Mesh pts = lodforge::test::sphere_points(6000, 5.f);
    const int r2 = 25;
    for (int x = -5; x <= 5; ++x)
        for (int y = -5; y <= 5; ++y)
            for (int z = -5; z <= 5; ++z)
                if (x * x + y * y + z * z == r2) {
                    const Vec3f q{float(x), float(y), float(z)};
                    pts.positions.push_back(q);
                    pts.normals.push_back(q * 0.2f);
                }
    ASSERT_EQ(pts.positions.size(), 6030u);
    McOctreeParams p;
    p.cube_size = 0.25;
    const McOctreeBuildResult r = build_mc_octree(pts, p);
    ASSERT_EQ(r.tree.origin.x, -5.75f);  // the integer points are lattice points
    const double h = r.tree.cube_size;
    McOctreeExtractor ex(r.tree);
    std::size_t zero_area = 0, coincident = 0;
    for (std::size_t k = 0; k <= 8; ++k) {
        const std::size_t i = r.tree.max_priority() - k * (r.tree.max_priority() / 16);
        const Mesh& m = ex.extract(i).mesh;
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            const Vec3f a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                        c = m.positions[m.indices[t + 2]];
            coincident += a == b || b == c || a == c;
            const Vec3f n = cross(b - a, c - a);
            zero_area += 0.5 * std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z) <= 1e-9 * h * h;
        }
        const auto w = check_watertight(m);
        EXPECT_EQ(w.border_edges, 0u) << "priority " << i;
        EXPECT_EQ(w.unpaired_directed, 0u) << "priority " << i;
    }
    EXPECT_EQ(coincident, 0u);
    EXPECT_EQ(zero_area, 0u);
}

// A part thinner than a cube has no lattice point inside it: the error says so and names the remedy.
TEST(McOctreeBuild, ANeedleThinnerThanACubeNamesTheRemedy) {
    const Mesh needle = lodforge::test::needle(8, 50, 0.001f, 10.f);
    McOctreeParams p;
    p.resolution = 32;
    try {
        build_mc_octree(needle, p);
        ADD_FAILURE() << "a surface was found";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::invalid);
        EXPECT_NE(std::string(e.what()).find("no surface"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("finer --resolution"), std::string::npos) << e.what();
    }
}

namespace {

// A box of 8 vertices and 12 outward triangles: every face is many cubes long.
Mesh low_poly_box(Vec3f lo, Vec3f hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return m;
}

float box_distance(Vec3f p, Vec3f lo, Vec3f hi) {  // unsigned distance to the box's surface
    float outside = 0, inside = INFINITY;
    for (int a = 0; a < 3; ++a) {
        const float below = lo[a] - p[a], above = p[a] - hi[a];
        const float d = std::max(below, above);
        if (d > 0) outside += d * d;
        inside = std::min(inside, -d);
    }
    return outside > 0 ? std::sqrt(outside) : std::max(inside, 0.f);
}

}  // namespace

TEST(McOctreeBuild, ALowPolyBoxIsRebuiltOnItsFaces) {
    // The field's sign comes from the nearest input point's normal. With the eight corners alone, a lattice
    // point above the middle of a face took a corner's diagonal normal and could land on the wrong side:
    // bubbles outside the box, 0.2 of the diagonal from it. Faces longer than two cubes are sampled now.
    const Vec3f lo{0.3f, -0.2f, 0.1f}, hi{1.3f, 0.5f, 0.6f};
    const Mesh box = low_poly_box(lo, hi);
    McOctreeParams p;
    p.resolution = 32;
    const McOctreeBuildResult r = build_mc_octree(box, p);
    EXPECT_GT(r.face_samples, 1000u);
    EXPECT_EQ(r.sampled_faces, 12u);
    EXPECT_EQ(r.tree.input_points, 8u);
    // The samples cover every face: no "exceeds the data density" (8 points for 5,000 cubes).
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    const McOctree& t = r.tree;
    McOctreeExtractor ex(t);
    const Mesh leaves = ex.extract(t.max_priority()).mesh;
    ASSERT_GT(leaves.triangle_count(), 1000u);
    float worst = 0;
    for (const Vec3f& v : leaves.positions) worst = std::max(worst, box_distance(v, lo, hi));
    // Within 1.35 cubes where the corners are rounded off; the bubbles were 5-10 cubes out.
    EXPECT_LT(worst, 1.5f * t.cube_size) << "cube size " << t.cube_size;
    const auto w = check_watertight(leaves);
    EXPECT_EQ(w.border_edges, 0u);
    EXPECT_EQ(w.unpaired_directed, 0u);
    // Every face is reached: leaf vertices within a cube of each face's centre.
    for (int a = 0; a < 3; ++a)
        for (const float side : {lo[a], hi[a]}) {
            Vec3f c = (lo + hi) * 0.5f;
            (a == 0 ? c.x : a == 1 ? c.y : c.z) = side;
            float nearest = INFINITY;
            for (const Vec3f& v : leaves.positions) nearest = std::min(nearest, length(v - c));
            EXPECT_LT(nearest, t.cube_size) << "axis " << a << " side " << side;
        }
}

TEST(McOctreeBuild, OnlyFacesLongerThanTwoCubesAreSampled) {
    // A scan at the resolutions its density allows is used through its vertices alone: the bunny's longest
    // edge is 0.0049 for an extent of 0.156, so at 48 no face is sampled; at 128, 1,486 faces are longer than
    // two cubes (the bunny's hole fills and its sparse base), and only those.
    const Mesh bunny = read_mesh(lodforge::test::shared_data("scan-bunny/bun_zipper.ply"));
    for (const std::size_t resolution : {48u, 128u}) {
        McOctreeParams p;
        p.resolution = resolution;
        const McOctreeBuildResult r = build_mc_octree(bunny, p);
        std::size_t long_faces = 0;
        for (std::size_t f = 0; f < bunny.triangle_count(); ++f) {
            const Vec3f a = bunny.positions[bunny.indices[3 * f]], b = bunny.positions[bunny.indices[3 * f + 1]],
                        c = bunny.positions[bunny.indices[3 * f + 2]];
            if (std::max({length(b - a), length(c - b), length(a - c)}) > 2 * r.tree.cube_size) ++long_faces;
        }
        EXPECT_LE(r.sampled_faces, long_faces) << resolution;
        EXPECT_GE(r.sampled_faces, long_faces * 9 / 10) << resolution;  // less only by folded or orientless faces
        EXPECT_EQ(r.face_samples == 0, long_faces == 0) << resolution;
        if (resolution == 48) EXPECT_EQ(r.face_samples, 0u);
        else EXPECT_GT(r.sampled_faces, 1000u);
    }
}

TEST(McOctreeBuild, AResolutionTooFineForTheFacesIsRefusedBeforeSampling) {
    const Mesh box = low_poly_box({0, 0, 0}, {1, 1, 1});
    McOctreeParams p;
    p.resolution = 30000;  // about 5e9 samples
    try {
        build_mc_octree(box, p);
        ADD_FAILURE() << "built";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::argument);
        EXPECT_NE(std::string(e.what()).find("too high for this mesh's faces"), std::string::npos) << e.what();
    }
}

TEST(McOctreeBuild, ACoarseCageStaysWithinItsBounds) {
    // Spot's control cage (188 vertices, sharp corners): with area-weighted normals at the long faces'
    // corners, lattice points far outside took a corner's wrong side and a sheet of surface ran to the
    // grid's edge (Hausdorff 0.92 of the diagonal). The corners' pseudo-normals tell the side exactly.
    const Mesh cage = read_mesh(lodforge::test::shared_data("tex-spot/spot_control_mesh.obj"));
    const Bounds in = cage.bounds();
    McOctreeParams p;
    p.resolution = 64;
    const McOctreeBuildResult r = build_mc_octree(cage, p);
    EXPECT_GT(r.face_samples, 0u);
    EXPECT_FALSE(r.reaches_grid_edge);
    const Mesh leaves = McOctreeExtractor(r.tree).extract(r.tree.max_priority()).mesh;
    ASSERT_FALSE(leaves.positions.empty());
    const Bounds out = leaves.bounds();
    for (int a = 0; a < 3; ++a) {
        EXPECT_GE(out.min[a], in.min[a] - 2 * r.tree.cube_size) << "axis " << a;
        EXPECT_LE(out.max[a], in.max[a] + 2 * r.tree.cube_size) << "axis " << a;
    }
}

TEST(McOctreeBuild, OverlappingShellsOfALowPolyMeshGiveTheirUnion) {
    // Two boxes, B pushed halfway into A (an accessory through a body, a bill through a head). Signed by the
    // nearest point's normal, B's faces inside A made a second surface there (y from 0.13 to 0.25 under
    // B's lower face); a low-poly mesh is signed by its winding number, which is 2 in the overlap: inside.
    Mesh two = low_poly_box({0, 0, 0}, {1, 1, 1});
    const Mesh b = low_poly_box({0.5f, 0.25f, 0.25f}, {1.5f, 0.75f, 0.75f});
    for (const Vec3f& p : b.positions) two.positions.push_back(p);
    for (const std::uint32_t i : b.indices) two.indices.push_back(i + 8);
    McOctreeParams p;
    p.resolution = 48;
    const McOctreeBuildResult r = build_mc_octree(two, p);
    ASSERT_GT(r.face_samples, r.tree.input_points);
    const Mesh leaves = McOctreeExtractor(r.tree).extract(r.tree.max_priority()).mesh;
    ASSERT_GT(leaves.triangle_count(), 1000u);
    // Inside A below B, at least 0.08 (2.5 cubes) from the union's boundary: no surface there.
    std::size_t inside = 0;
    for (const Vec3f& v : leaves.positions)
        if (v.x > 0.55f && v.x < 0.9f && v.y > 0.08f && v.y < 0.22f && v.z > 0.3f && v.z < 0.7f) ++inside;
    EXPECT_EQ(inside, 0u);
    const auto w = check_watertight(leaves);
    EXPECT_EQ(w.border_edges, 0u);
}

TEST(McOctreeBuild, AnOpenLowPolySheetIsSignedByItsNormals) {
    // Two triangles of a square: mostly samples, but an open sheet, whose winding number goes from +1/2 to
    // -1/2 across it and never passes 1/2 (signed by it, nothing was inside: no surface). The normals
    // give the sheet's surface, ended by the band near its border.
    Mesh sheet;
    sheet.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    sheet.indices = {0, 1, 2, 0, 2, 3};
    McOctreeParams p;
    p.resolution = 16;
    p.band = 2;
    const McOctreeBuildResult r = build_mc_octree(sheet, p);
    EXPECT_GT(r.face_samples, r.tree.input_points);
    const Mesh leaves = McOctreeExtractor(r.tree).extract(r.tree.max_priority()).mesh;
    ASSERT_GT(leaves.triangle_count(), 100u);
    for (const Vec3f& v : leaves.positions) ASSERT_LT(std::fabs(v.z), 3 * r.tree.cube_size) << v.x << " " << v.y;
    // and the whole square is covered: a leaf vertex within 1.5 cubes of every probe
    for (int i = 1; i < 10; ++i)
        for (int j = 1; j < 10; ++j) {
            const Vec3f probe{float(i) / 10, float(j) / 10, 0};
            float nearest = INFINITY;
            for (const Vec3f& v : leaves.positions) nearest = std::min(nearest, length(v - probe));
            EXPECT_LT(nearest, 1.5f * r.tree.cube_size) << probe.x << " " << probe.y;
        }
}

TEST(McOctreeBuild, TheDucksFoldedBillIsSignedByItsWindingNumber) {
    // The Duck's bill has near-degenerate slivers folded against each other: signed by pseudo-normals, a
    // region behind them took the wrong side and the leaves ended up to 2.5 % of the diagonal from the
    // input at 128 (vertices alone: 1.3 %). By the winding number: 0.55 %.
    const Mesh duck = read_mesh(lodforge::test::shared_data("tex-duck/glTF/Duck.gltf"));
    McOctreeParams p;
    p.resolution = 128;
    const McOctree t = build_mc_octree(duck, p).tree;
    const Mesh leaves = McOctreeExtractor(t).extract(t.max_priority()).mesh;
    DistanceParams d;
    d.samples = 200000;
    d.vertex_errors = false;
    const DistanceResult r = compare(duck, leaves, d);
    EXPECT_LT(r.hausdorff_relative, 0.01);
    EXPECT_LT(r.mean_relative, 0.0006);
}
