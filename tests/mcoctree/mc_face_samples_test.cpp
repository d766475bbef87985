// Samples on a mesh's large faces (core/src/mcoctree/mc_face_samples.h): where they go and which way they face.
#include "mcoctree/mc_face_samples.h"
#include "lodforge/error.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace lodforge;
using lodforge::mc::FaceSampleParams;
using lodforge::mc::sample_large_faces;

namespace {

Vec3f unit(Vec3f v) { return v * (1.f / length(v)); }

// Two triangles over the edge (0,0,0)-(4,0,0), a convex edge of 90 degrees: face A in the plane z = 0
// facing +z, face B in the plane y = 0 facing -y.
struct Hinge {
    Mesh mesh;
    std::vector<Vec3f> normals;
    std::vector<std::uint32_t> ids;
};

Hinge hinge(bool seam) {
    Hinge h;
    h.mesh.positions = {{0, 0, 0}, {4, 0, 0}, {2, 3, 0}, {2, 0, -3}};
    h.mesh.indices = {0, 1, 2, 1, 0, 3};
    if (seam) {  // face B uses its own copies of the edge's ends (a UV seam)
        h.mesh.positions.push_back({0, 0, 0});
        h.mesh.positions.push_back({4, 0, 0});
        h.mesh.indices = {0, 1, 2, 5, 4, 3};
    }
    const Vec3f na{0, 0, 1}, nb{0, -1, 0};
    const Vec3f edge = unit(na + nb);
    h.normals = {edge, edge, na, nb};
    h.ids = {0, 1, 2, 3};
    if (seam) h.normals.push_back(edge), h.normals.push_back(edge), h.ids.push_back(0), h.ids.push_back(1);
    return h;
}

}  // namespace

TEST(McFaceSamples, SharpEdgesGetTheSumOfTheirFacesNormals) {
    for (const bool seam : {false, true}) {
        const Hinge h = hinge(seam);
        FaceSampleParams p;
        p.min_edge = 1;
        p.spacing = 0.5f;
        p.max_samples = 100000;
        const auto s = sample_large_faces(h.mesh, h.normals, h.ids, p);
        ASSERT_EQ(s.points.size(), s.normals.size());
        ASSERT_EQ(s.points.size(), s.shading.size());
        EXPECT_EQ(s.faces, 2u);
        std::size_t on_edge = 0, on_a = 0, on_b = 0;
        for (std::size_t i = 0; i < s.points.size(); ++i) {
            const Vec3f q = s.points[i], n = s.normals[i];
            EXPECT_NEAR(length(n), 1.f, 1e-5f);
            EXPECT_NEAR(length(s.shading[i]), 1.f, 1e-5f);
            if (q.y == 0 && q.z == 0) {  // the hinge: both faces' normals summed, once per point
                ++on_edge;
                EXPECT_NEAR(n.y, -std::sqrt(0.5f), 1e-5f) << q.x;
                EXPECT_NEAR(n.z, std::sqrt(0.5f), 1e-5f) << q.x;
            } else if (std::fabs(q.z) < 1e-6f) {
                ++on_a;  // inside face A or on its outer edges: its own normal
                EXPECT_NEAR(n.z, 1.f, 1e-5f) << q.x << " " << q.y;
            } else {
                ++on_b;
                EXPECT_NEAR(n.y, -1.f, 1e-5f) << q.x << " " << q.z;
            }
            EXPECT_GE(q.x, -1e-6f);
            EXPECT_LE(q.x, 4 + 1e-6f);
        }
        EXPECT_EQ(on_edge, 7u) << "seam " << seam;  // 4 / 0.5 = 8 segments: 7 points inside the edge
        EXPECT_GT(on_a, 10u);
        EXPECT_GT(on_b, 10u);
    }
}

TEST(McFaceSamples, FoldedAndShortFacesGetNone) {
    Hinge h = hinge(false);
    FaceSampleParams p;
    p.min_edge = 10;  // longer than every edge
    p.spacing = 0.5f;
    p.max_samples = 100000;
    EXPECT_TRUE(sample_large_faces(h.mesh, h.normals, h.ids, p).points.empty());
    // Face B turned over onto face A's side: its corners' normals from the faces around them disagree
    // with it (a fold), so only face A is sampled.
    h.mesh.positions[3] = {2, 0.5f, 0.01f};
    p.min_edge = 1;
    const auto s = sample_large_faces(h.mesh, h.normals, h.ids, p);
    EXPECT_EQ(s.faces, 1u);
    for (const Vec3f& n : s.normals) EXPECT_GT(n.z, 0.5f);
}

TEST(McFaceSamples, ColoursAndShadingInterpolateTheCorners) {
    Mesh m;
    m.positions = {{0, 0, 0}, {8, 0, 0}, {0, 8, 0}};
    m.indices = {0, 1, 2};
    m.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}};
    const std::vector<Vec3f> normals = {{0, 0, 1}, unit({1, 0, 1}), unit({0, 1, 1})};
    const std::vector<std::uint32_t> ids = {0, 1, 2};
    FaceSampleParams p;
    p.min_edge = 1;
    p.spacing = 1;
    p.max_samples = 1000;
    const auto s = sample_large_faces(m, normals, ids, p);
    ASSERT_FALSE(s.points.empty());
    ASSERT_EQ(s.colors.size(), s.points.size());
    for (std::size_t i = 0; i < s.points.size(); ++i) {
        const Vec3f q = s.points[i];
        const Vec4f c = s.colors[i];
        EXPECT_NEAR(c.y, q.x / 8, 1e-5f);  // green grows with x, blue with y
        EXPECT_NEAR(c.z, q.y / 8, 1e-5f);
        EXPECT_NEAR(c.x + c.y + c.z, 1.f, 1e-5f);
        EXPECT_EQ(s.normals[i], (Vec3f{0, 0, 1}));  // orientation: the face's
        EXPECT_GE(s.shading[i].x, -1e-6f);           // shading leans towards the corners' normals
        if (q.x > 4) {
            EXPECT_GT(s.shading[i].x, 0.1f);
        }
    }
    p.max_samples = 10;
    EXPECT_THROW(sample_large_faces(m, normals, ids, p), Error);
}
