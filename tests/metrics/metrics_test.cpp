#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/simplify/simplify.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace lodforge;

namespace {

Mesh unit_square(float z) {
    Mesh m;
    m.positions = {{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

}  // namespace

TEST(Metrics, IdenticalMeshesAreAtDistanceZero) {
    const Mesh m = read_mesh(test::shared_data("scan-bunny/bun_zipper.ply"));
    const DistanceResult r = compare(m, m);
    EXPECT_LT(r.hausdorff_relative, 1e-7);
    EXPECT_LT(r.mean_relative, 1e-9);
    EXPECT_GE(r.test_to_reference.samples, 100000u);
    ASSERT_EQ(r.vertex_errors.size(), m.vertex_count());
    std::vector<std::uint8_t> used(m.vertex_count(), 0);  // the scan has stray vertices off the surface
    for (std::uint32_t i : m.indices) used[i] = 1;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        if (used[v]) {
            ASSERT_LT(r.vertex_errors[v], 1e-6f) << v;
        }
    }
}

// Attributes too, where faces coincide with other attributes: the milk truck has overlapping faces with
// their own texture coordinates (the sweep measured a UV RMS of 0.005 of the truck against itself when the
// first equally close face was taken), and a square doubled with a second UV layout must compare as zero.
TEST(Metrics, IdenticalMeshesHaveNoAttributeErrorWhereFacesCoincide) {
    const Mesh truck = read_mesh(test::shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"));
    const DistanceResult t = compare(truck, truck);
    ASSERT_TRUE(t.has_texcoord_error);
    EXPECT_LT(t.texcoord_rms, 1e-9);
    EXPECT_LT(t.hausdorff_relative, 1e-7);

    Mesh two = unit_square(0.f);
    const Mesh second = unit_square(0.f);
    for (std::uint32_t i : second.indices) two.indices.push_back(i + 4);
    two.positions.insert(two.positions.end(), second.positions.begin(), second.positions.end());
    two.texcoords = {{{0, 0}, {0.5f, 0}, {0.5f, 0.5f}, {0, 0.5f}, {0.5f, 0.5f}, {1, 0.5f}, {1, 1}, {0.5f, 1}}};
    const DistanceResult d = compare(two, two);
    ASSERT_TRUE(d.has_texcoord_error);
    EXPECT_LT(d.texcoord_rms, 1e-9);
    // Against one layer only, the other layer's samples do differ: the tie-break picks the best match, it
    // does not hide a real difference.
    Mesh one = two;
    one.indices.resize(6);
    EXPECT_GT(compare(one, two).texcoord_rms + compare(two, one).texcoord_rms, 0.1);
}

TEST(Metrics, ParallelPlanesAreAtTheirOffset) {
    const Mesh a = unit_square(0), b = unit_square(0.25f);
    DistanceParams p;
    p.samples = 5000;
    const DistanceResult r = compare(a, b, p);
    EXPECT_NEAR(r.hausdorff, 0.25, 1e-6);
    EXPECT_NEAR(r.mean, 0.25, 1e-6);
    EXPECT_NEAR(r.rms, 0.25, 1e-6);
    EXPECT_NEAR(r.diagonal, std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(r.hausdorff_relative, 0.25 / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(double(r.test_to_reference.samples), 5000.0, 200.0);
}

TEST(Metrics, HausdorffIsAsymmetricPerSideAndSymmetricOverall) {
    // The test square covers only half of the reference: reference samples far from it count.
    const Mesh ref = unit_square(0);
    Mesh half = unit_square(0);
    for (Vec3f& v : half.positions) v.x *= 0.5f;
    DistanceParams p;
    p.samples = 20000;
    const DistanceResult r = compare(ref, half, p);
    EXPECT_LT(r.test_to_reference.max, 1e-6);
    EXPECT_NEAR(r.reference_to_test.max, 0.5, 1e-6);  // the far corners are vertex samples
    EXPECT_NEAR(r.hausdorff, 0.5, 1e-6);
    EXPECT_NEAR(r.reference_to_test.mean, 0.125, 0.01);  // half the area at mean distance 0.25
}

TEST(Metrics, SameSeedSameResult) {
    const Mesh m = read_mesh(test::shared_data("scan-dragon/dragon_vrip_res4.ply"));
    SimplifyParams sp;
    sp.target_ratio = 0.2f;
    const Mesh s = simplify(m, sp).mesh;
    const DistanceResult a = compare(m, s), b = compare(m, s);
    EXPECT_EQ(a.hausdorff, b.hausdorff);
    EXPECT_EQ(a.mean, b.mean);
    DistanceParams other;
    other.seed = 7;
    const DistanceResult c = compare(m, s, other);
    EXPECT_NEAR(c.mean, a.mean, 0.05 * a.mean);
    EXPECT_GT(a.hausdorff, 0.0);
}

TEST(Metrics, TwoThreadsAndAPreparedReferenceGiveTheSameResult) {
    const Mesh in = read_mesh(test::shared_data("scan-bunny/bun_zipper.ply"));
    SimplifyParams sp;
    sp.target_ratio = 0.05f;
    const Mesh s = simplify(in, sp).mesh;
    DistanceParams one;
    one.samples = 30000;
    one.region_errors = true;
    DistanceParams two = one;
    two.threads = 2;
    const DistanceResult a = compare(in, s, one), b = compare(in, s, two);
    EXPECT_GT(a.hausdorff, 0.0);
    EXPECT_EQ(a.hausdorff, b.hausdorff);
    EXPECT_EQ(a.mean, b.mean);
    EXPECT_EQ(a.rms, b.rms);
    EXPECT_EQ(a.test_to_reference.samples, b.test_to_reference.samples);
    EXPECT_EQ(a.reference_to_test.max, b.reference_to_test.max);
    EXPECT_EQ(a.vertex_errors, b.vertex_errors);
    EXPECT_EQ(a.region_errors, b.region_errors);
    // A prepared reference, measured against twice, gives the same result again.
    const DistanceReference prepared(in);
    for (int k = 0; k < 2; ++k) {
        const DistanceResult c = compare(prepared, s, two);
        EXPECT_EQ(c.hausdorff, a.hausdorff);
        EXPECT_EQ(c.mean, a.mean);
        EXPECT_EQ(c.region_errors, a.region_errors);
    }
    EXPECT_THROW(DistanceReference{Mesh{}}, Error);
}

TEST(Metrics, ColourErrorOnTheByteScale) {
    Mesh a = unit_square(0), b = unit_square(0);
    a.colors.assign(4, Vec4f{0.5f, 0.5f, 0.5f, 1});
    b.colors.assign(4, Vec4f{0.5f + 10.f / 255.f, 0.5f, 0.5f, 1});  // R differs by 10 levels
    DistanceParams p;
    p.samples = 2000;
    const DistanceResult r = compare(a, b, p);
    ASSERT_TRUE(r.has_color_error);
    EXPECT_NEAR(r.color_rms, 10.0 / std::sqrt(3.0), 1e-3);  // RMS over R, G, B
    EXPECT_FALSE(r.has_texcoord_error);
}

TEST(Metrics, VertexErrorsMeasureTheTestVertices) {
    const Mesh ref = unit_square(0);
    Mesh t = unit_square(0);
    t.positions[2].z = 0.5f;
    const DistanceResult r = compare(ref, t);
    ASSERT_EQ(r.vertex_errors.size(), 4u);
    EXPECT_NEAR(r.vertex_errors[2], 0.5f, 1e-6f);
    EXPECT_NEAR(r.vertex_errors[0], 0.f, 1e-6f);
}

TEST(Metrics, RegionErrorsCollectTheSamplesAroundEachVertex) {
    const Mesh ref = unit_square(0);
    Mesh t = unit_square(0);
    t.positions[2].z = 0.5f;  // the test surface rises to 0.5 at vertex 2
    DistanceParams p;
    p.samples = 20000;
    p.region_errors = true;
    const DistanceResult r = compare(ref, t, p);
    ASSERT_EQ(r.region_errors.size(), 4u);
    EXPECT_NEAR(r.region_errors[2], 0.5f, 1e-6f);
    // Where vertex 0 has the largest weight, vertex 2's weight (the height over 0.5) is below one half;
    // the samples there are off the reference, so the field is positive but under 0.25.
    EXPECT_GT(r.region_errors[0], 0.05f);
    EXPECT_LT(r.region_errors[0], 0.25f + 1e-6f);
    EXPECT_EQ(*std::max_element(r.region_errors.begin(), r.region_errors.end()), static_cast<float>(r.hausdorff));
}

TEST(Metrics, RegionErrorsShowWhereAHalfEdgeSimplificationDeparts) {
    // A half-edge collapse keeps its vertices on the input, so their own distances are all zero; the
    // field of the samples around them is not, and its largest value is the Hausdorff distance.
    const Mesh in = read_mesh(test::shared_data("scan-bunny/bun_zipper.ply"));
    SimplifyParams sp;
    sp.target_ratio = 0.02f;
    const Mesh s = simplify(in, sp).mesh;
    DistanceParams p;
    p.samples = 50000;
    p.region_errors = true;
    const DistanceResult r = compare(in, s, p);
    ASSERT_EQ(r.region_errors.size(), s.vertex_count());
    ASSERT_EQ(r.vertex_errors.size(), s.vertex_count());
    std::size_t positive = 0;
    for (std::size_t v = 0; v < s.vertex_count(); ++v) {
        ASSERT_LT(r.vertex_errors[v], 1e-6f) << v;
        ASSERT_GE(r.region_errors[v], r.vertex_errors[v]) << v;
        if (r.region_errors[v] > 1e-4f * float(r.diagonal)) ++positive;
    }
    EXPECT_GT(positive, s.vertex_count() * 9 / 10);
    EXPECT_GT(r.hausdorff, 0.0);
    EXPECT_EQ(*std::max_element(r.region_errors.begin(), r.region_errors.end()), static_cast<float>(r.hausdorff));
}

TEST(Metrics, EmptyMeshIsInvalid) {
    const Mesh a = unit_square(0);
    Mesh empty;
    EXPECT_THROW(compare(a, empty), Error);
    EXPECT_THROW(compare(empty, a), Error);
}

TEST(Metrics, CancellationThrows) {
    CancelFlagProgress progress;
    progress.cancel();
    const Mesh a = unit_square(0);
    EXPECT_THROW(compare(a, a, {}, &progress), Error);
}
