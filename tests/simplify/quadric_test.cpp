#include "lodforge/simplify/quadric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

using namespace lodforge;

TEST(Quadric, PlaneQuadricIsWeightedSquaredDistance) {
    const Quadric q = Quadric::from_plane({0, 0, 1}, -2.0, 3.0);  // plane z = 2, weight 3
    EXPECT_NEAR(q.evaluate({5, -7, 2}), 0.0, 1e-12);
    EXPECT_NEAR(q.evaluate({1, 1, 5}), 3.0 * 9.0, 1e-9);
    EXPECT_DOUBLE_EQ(q.weight, 3.0);
}

TEST(Quadric, TriangleQuadricIsItsPlaneWeightedByItsArea) {
    double area = 0;
    // Right triangle in the plane y = 1 with legs 2 and 3: area 3.
    const std::optional<Quadric> q = Quadric::from_triangle({0, 1, 0}, {2, 1, 0}, {0, 1, 3}, area);
    ASSERT_TRUE(q.has_value());
    EXPECT_DOUBLE_EQ(area, 3.0);
    EXPECT_DOUBLE_EQ(q->weight, 3.0);
    EXPECT_NEAR(q->evaluate({7, 1, -4}), 0.0, 1e-12);
    EXPECT_NEAR(q->evaluate({0, 3, 0}), 3.0 * 4.0, 1e-9);  // 2 off the plane
    // Collinear corners: no plane, zero area.
    EXPECT_FALSE(Quadric::from_triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2}, area).has_value());
    EXPECT_EQ(area, 0.0);
}

TEST(Quadric, OptimalPositionIsThePlanesIntersection) {
    Quadric q = Quadric::from_plane({1, 0, 0}, -1.0, 1.0);
    q += Quadric::from_plane({0, 1, 0}, -2.0, 1.0);
    q += Quadric::from_plane({0, 0, 1}, -3.0, 1.0);
    Vec3d p;
    ASSERT_TRUE(optimal_position(q, p));
    EXPECT_NEAR(p.x, 1.0, 1e-9);
    EXPECT_NEAR(p.y, 2.0, 1e-9);
    EXPECT_NEAR(p.z, 3.0, 1e-9);
    // Two planes: the minimisers form a line, no unique answer.
    Quadric flat = Quadric::from_plane({1, 0, 0}, 0.0, 1.0);
    flat += Quadric::from_plane({0, 1, 0}, 0.0, 1.0);
    EXPECT_FALSE(optimal_position(flat, p));
}

TEST(AttributeQuadric, ZeroOnTheInterpolatedAttributesAndGrowsOffThem) {
    AttributeQuadrics aq(1, 2);
    const double s0[2] = {0, 1}, s1[2] = {1, 1}, s2[2] = {0, 3};
    aq.add_triangle(0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, s0, s1, s2, 0.5);
    // At a corner with its own attributes: no error; the attribute field is s = (x, 1 + 2y).
    EXPECT_NEAR(aq.evaluate(0, {1, 0, 0}, s1), 0.0, 1e-12);
    const double mid[2] = {0.25, 1.5};
    EXPECT_NEAR(aq.evaluate(0, {0.25, 0.25, 0}, mid), 0.0, 1e-12);
    // Off the plane the attribute gradient does not change (it lies in the face plane).
    EXPECT_NEAR(aq.evaluate(0, {0.25, 0.25, 4}, mid), 0.0, 1e-12);
    const double off[2] = {0.25 + 0.1, 1.5};
    EXPECT_NEAR(aq.evaluate(0, {0.25, 0.25, 0}, off), 0.5 * 0.01, 1e-12);
    double best[2];
    ASSERT_TRUE(aq.optimal_attributes(0, {0.5, 0.25, 0}, best));
    EXPECT_NEAR(best[0], 0.5, 1e-12);
    EXPECT_NEAR(best[1], 1.5, 1e-12);
    // With the attributes eliminated, the quadric in p alone is zero everywhere (the field is linear).
    const Quadric e = aq.eliminated(0);
    EXPECT_NEAR(e.evaluate({0.3, 0.7, 2}), 0.0, 1e-9);
}

TEST(AttributeQuadric, AccumulateAddsErrors) {
    AttributeQuadrics aq(2, 1);
    const double a[1] = {0}, b[1] = {1}, c[1] = {0};
    aq.add_triangle(0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, a, b, c, 1.0);
    aq.add_triangle(1, {0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, a, c, b, 1.0);
    const double s[1] = {0.7};
    const double e0 = aq.evaluate(0, {0.1, 0.1, 0}, s), e1 = aq.evaluate(1, {0.1, 0.1, 0}, s);
    aq.accumulate(0, 1);
    EXPECT_NEAR(aq.evaluate(0, {0.1, 0.1, 0}, s), e0 + e1, 1e-12);
    EXPECT_DOUBLE_EQ(aq.weight(0), 2.0);
}

// minimum() of several quadrics is the merged quadric evaluated at its optimal attributes, and no
// other attribute value does better (optimal placement's cost).
TEST(AttributeQuadric, MinimumOfASumIsTheMergedQuadricAtItsOptimum) {
    AttributeQuadrics aq(3, 2);
    const double a[2] = {0, 1}, b[2] = {1, 0.5}, c[2] = {0.2, 0}, d[2] = {0.9, 0.3};
    aq.add_triangle(0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, a, b, c, 1.0);
    aq.add_triangle(1, {0, 0, 0}, {0, 1, 0}, {-1, 0.2, 0.3}, a, c, d, 0.7);
    const Vec3d p{0.1, 0.2, 0.05};
    const std::size_t both[2] = {0, 1};
    const double m = aq.minimum(both, 2, p);
    EXPECT_GT(m, 0.0);  // the two faces' fields disagree at p
    aq.accumulate(2, 0);
    aq.accumulate(2, 1);
    double best[2];
    ASSERT_TRUE(aq.optimal_attributes(2, p, best));
    EXPECT_NEAR(m, aq.evaluate(2, p, best), 1e-12);
    for (double dx : {-0.01, 0.01}) {
        const double other[2] = {best[0] + dx, best[1] - dx};
        EXPECT_GT(aq.evaluate(2, p, other), m);
    }
    const std::size_t one[1] = {0};
    double own[2];
    ASSERT_TRUE(aq.optimal_attributes(0, p, own));
    EXPECT_NEAR(aq.minimum(one, 1, p), aq.evaluate(0, p, own), 1e-12);
}

// The simplifier adds each face to its three corners' wedges in one call; the sums must be bit for bit
// those of one call per wedge (its results are compared against runs made that way).
TEST(AttributeQuadric, OneCallForSeveralTargetsGivesTheSameSums) {
    AttributeQuadrics one(4, 3), many(4, 3);
    const double s[4][3] = {{0.1, 0.7, 0.3}, {0.9, 0.2, 0.4}, {0.33, 0.61, 0.05}, {0.5, 0.5, 0.97}};
    const Vec3d p[4] = {{0.1, 0.2, 0.3}, {1.3, 0.1, -0.2}, {0.2, 1.7, 0.4}, {0.9, 0.8, 1.1}};
    const int faces[3][3] = {{0, 1, 2}, {1, 3, 2}, {0, 3, 1}};
    for (const auto& f : faces) {
        const double area = 0.37 + 0.1 * f[1];
        for (int k = 0; k < 3; ++k)
            one.add_triangle(std::size_t(f[k]), p[f[0]], p[f[1]], p[f[2]], s[f[0]], s[f[1]], s[f[2]], area);
        const std::size_t targets[3] = {std::size_t(f[0]), std::size_t(f[1]), std::size_t(f[2])};
        many.add_triangle(targets, 3, p[f[0]], p[f[1]], p[f[2]], s[f[0]], s[f[1]], s[f[2]], area);
    }
    const double at[3] = {0.4, 0.4, 0.4};
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(one.weight(i), many.weight(i)) << i;
        EXPECT_EQ(one.evaluate(i, {0.3, 0.9, -0.4}, at), many.evaluate(i, {0.3, 0.9, -0.4}, at)) << i;
        const Quadric a = one.eliminated(i), b = many.eliminated(i);
        EXPECT_EQ(a.a00, b.a00) << i;
        EXPECT_EQ(a.b1, b.b1) << i;
        EXPECT_EQ(a.c, b.c) << i;
    }
    EXPECT_GT(one.evaluate(3, {0.3, 0.9, -0.4}, at), 0.0);  // the comparison is not of empty quadrics
}
