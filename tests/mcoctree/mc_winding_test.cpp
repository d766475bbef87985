// The generalized winding number by a tree of dipoles (core/src/mcoctree/mc_winding.h).
#include "mcoctree/mc_winding.h"
#include "lodforge/io/mesh_io.h"
#include "support/icosphere.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace lodforge;
using lodforge::mc::build_winding_tree;
using lodforge::mc::winding_number;

TEST(McWinding, OneInsideZeroOutsideTwoInAnOverlap) {
    const Mesh sphere = lodforge::test::icosphere(4);  // unit sphere, outward
    Mesh two = sphere;
    for (const Vec3f& p : sphere.positions) two.positions.push_back(p + Vec3f{1, 0, 0});
    for (const std::uint32_t i : sphere.indices) two.indices.push_back(i + static_cast<std::uint32_t>(sphere.positions.size()));
    const auto tree = build_winding_tree(two);
    EXPECT_NEAR(winding_number(tree, {-0.5f, 0, 0}), 1.0, 0.05);
    EXPECT_NEAR(winding_number(tree, {0.5f, 0, 0}), 2.0, 0.05);  // in both spheres
    EXPECT_NEAR(winding_number(tree, {1.7f, 0.1f, 0}), 1.0, 0.05);
    EXPECT_NEAR(winding_number(tree, {0.5f, 1.5f, 0}), 0.0, 0.05);
    EXPECT_NEAR(winding_number(tree, {30, -20, 5}), 0.0, 0.05);
    // Turned inside out, the sign flips.
    Mesh inverted = sphere;
    for (std::size_t t = 0; t < inverted.indices.size(); t += 3) std::swap(inverted.indices[t + 1], inverted.indices[t + 2]);
    EXPECT_NEAR(winding_number(build_winding_tree(inverted), {0.1f, 0.2f, 0}), -1.0, 0.05);
}

TEST(McWinding, TheDipoleTreeAgreesWithTheExactSumOnTheDuck) {
    // An infinite beta opens every node: the exact sum of the triangles' solid angles. At 1.5 (the build's)
    // the far nodes are dipoles, and the two agree far inside the 0.5 that is read.
    const Mesh duck = read_mesh(lodforge::test::shared_data("tex-duck/glTF/Duck.gltf"));
    const auto tree = build_winding_tree(duck);
    const Bounds box = duck.bounds();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    double worst = 0;
    int inside = 0;
    for (int i = 0; i < 300; ++i) {
        const Vec3f q{box.min.x + u(rng) * (box.max.x - box.min.x), box.min.y + u(rng) * (box.max.y - box.min.y),
                      box.min.z + u(rng) * (box.max.z - box.min.z)};
        const double exact = winding_number(tree, q, INFINITY), fast = winding_number(tree, q, 1.5);
        worst = std::max(worst, std::fabs(exact - fast));
        inside += exact > 0.5;
        EXPECT_EQ(exact > 0.5, fast > 0.5) << q.x << " " << q.y << " " << q.z;
    }
    EXPECT_LT(worst, 0.2);  // 0.11 measured
    EXPECT_GT(inside, 30);   // the duck fills a good part of its box...
    EXPECT_LT(inside, 270);  // ...not all of it
}

TEST(McWinding, OpennessTellsASheetFromAClosedSurface) {
    EXPECT_LT(lodforge::mc::openness(lodforge::test::icosphere(3)), 1e-4);
    Mesh sheet;
    sheet.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1f}, {0, 1, 0}};
    sheet.indices = {0, 1, 2, 0, 2, 3};
    EXPECT_GT(lodforge::mc::openness(sheet), 0.9);
    // A sphere with one cap removed: small, but not zero.
    Mesh open = lodforge::test::icosphere(3);
    std::vector<std::uint32_t> kept;
    for (std::size_t t = 0; t < open.indices.size(); t += 3)
        if (open.positions[open.indices[t]].z < 0.9f) kept.insert(kept.end(), open.indices.begin() + long(t), open.indices.begin() + long(t) + 3);
    open.indices = kept;
    const double o = lodforge::mc::openness(open);
    EXPECT_GT(o, 1e-3);
    EXPECT_LT(o, 0.1);
}
