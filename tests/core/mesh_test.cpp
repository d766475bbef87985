#include "lodforge/mesh.h"

#include <gtest/gtest.h>

using namespace lodforge;

namespace {
Mesh two_triangles() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.normals.assign(4, Vec3f{0, 0, 1});
    m.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 1, 1}};
    m.texcoords = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}
}  // namespace

TEST(Mesh, CountsWithoutPositionIdsTreatEveryVertexAsAPoint) {
    const Mesh m = two_triangles();
    EXPECT_EQ(m.vertex_count(), 4u);
    EXPECT_EQ(m.point_count(), 4u);
    EXPECT_EQ(m.triangle_count(), 2u);
}

TEST(Mesh, DuplicateVertexMakesAWedgeOfTheSamePoint) {
    Mesh m = two_triangles();
    const std::uint32_t w = duplicate_vertex(m, 2);
    EXPECT_EQ(w, 4u);
    ASSERT_EQ(m.vertex_count(), 5u);
    EXPECT_EQ(m.point_count(), 4u) << "a wedge is not a new surface point";
    EXPECT_EQ(m.position_ids[4], 2u);
    EXPECT_EQ(m.positions[4], m.positions[2]);
    EXPECT_EQ(m.normals[4], m.normals[2]);
    EXPECT_EQ(m.colors[4], m.colors[2]);
    EXPECT_EQ(m.texcoords[0][4], m.texcoords[0][2]);
    m.texcoords[0][4] = {0.5f, 0.5f};  // the wedge's own UV: the seam is representable
    EXPECT_NE(m.texcoords[0][4], m.texcoords[0][2]);
}

TEST(Mesh, BoundsAndDiagonal) {
    const Mesh m = two_triangles();
    const Bounds b = m.bounds();
    EXPECT_EQ(b.min, (Vec3f{0, 0, 0}));
    EXPECT_EQ(b.max, (Vec3f{1, 1, 0}));
    EXPECT_NEAR(b.diagonal(), std::sqrt(2.f), 1e-6);
    EXPECT_TRUE(Mesh{}.bounds().empty());
}

TEST(Mesh, ResolvesRelativeTexturePathsAgainstTheSourceDirectory) {
    Mesh m;
    m.source_dir = "/data/models";
    TextureRef rel, abs, embedded;
    rel.path = "tex/a.png";
    abs.path = "/x/b.png";
    embedded.bytes = {1, 2, 3};
    EXPECT_EQ(m.resolve_texture_path(rel), "/data/models/tex/a.png");
    EXPECT_EQ(m.resolve_texture_path(abs), "/x/b.png");
    EXPECT_EQ(m.resolve_texture_path(embedded), "");
}

TEST(Mesh, PointsFirstLayoutPutsOneVertexPerPointBeforeExtraWedges) {
    // Items 0..5 in groups {2, 0, 2, 1, 0, 3}; item 5 unused, group 3 therefore has no point.
    const std::vector<std::uint8_t> used{1, 1, 1, 1, 1, 0};
    const std::vector<std::uint32_t> group{2, 0, 2, 1, 0, 3};
    const PointsFirstLayout layout = points_first_layout(used, group, 4);
    EXPECT_EQ(layout.order, (std::vector<std::uint32_t>{0, 1, 3, 2, 4}));
    EXPECT_EQ(layout.point_of_group, (std::vector<std::uint32_t>{1, 2, 0, UINT32_MAX}));
}
