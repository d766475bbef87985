// Seam classes (issue 31, docs/artist-control.md): each class is found where it is built into a mesh and
// nowhere else, real assets have the classes they should, and the collapse simplifier never moves a point
// off a seam of a protected class (a point on such a seam only collapses onto a point of the same class).
#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/simplify/seams.h"
#include "lodforge/simplify/simplify.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

using namespace lodforge;

namespace {

// An n x n grid over [0, 1]² with a gentle bump (so collapses have a cost), split at x = 0.5 by `what`:
// "uv" (the right half's UVs shifted by 1), "color" (red left, blue right), "crease" (folded there, each
// half with its own flat normal), "material" (two materials, shared vertices), "mirror" (the right half's
// UVs mirrored, shared along the middle: no UV seam). The split vertices are copies at the same position.
Mesh split_grid(const std::string& what, int n = 24) {
    Mesh m;
    const bool split = what == "uv" || what == "color" || what == "crease";
    auto height = [&](float x, float y) {
        const float fold = what == "crease" ? 0.4f * std::abs(x - 0.5f) : 0.f;
        return fold + 0.02f * std::sin(6.f * x) * std::cos(5.f * y);
    };
    // Vertex (i, j) of the left (side 0) or right (side 1) half.
    std::vector<std::uint32_t> id(2 * (n + 1) * (n + 1), ~0u);
    if (what != "material") m.texcoords.assign(1, {});
    auto vertex = [&](int i, int j, int side) {
        const int s = split && 2 * i == n ? side : 0;
        std::uint32_t& v = id[(s * (n + 1) + i) * (n + 1) + j];
        if (v != ~0u) return v;
        v = static_cast<std::uint32_t>(m.positions.size());
        const float x = float(i) / n, y = float(j) / n;
        m.positions.push_back({x, y, height(x, y)});
        const bool right = 2 * i > n || (2 * i == n && s == 1);
        if (!m.texcoords.empty())
            m.texcoords[0].push_back(what == "uv" && right       ? Vec2f{x + 1.f, y}
                                     : what == "mirror" && 2 * i > n ? Vec2f{1.f - x, y}
                                                                      : Vec2f{x, y});
        if (what == "color") m.colors.push_back(right ? Vec4f{0, 0, 1, 1} : Vec4f{1, 0, 0, 1});
        if (what == "crease") m.normals.push_back(right ? Vec3f{-0.371f, 0, 0.928f} : Vec3f{0.371f, 0, 0.928f});
        return v;
    };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const int side = 2 * i >= n ? 1 : 0;
            const std::uint32_t a = vertex(i, j, side), b = vertex(i + 1, j, side), c = vertex(i + 1, j + 1, side),
                                d = vertex(i, j + 1, side);
            m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
            if (what == "material") m.face_materials.insert(m.face_materials.end(), 2, std::uint32_t(side));
        }
    if (what == "material") m.materials.resize(2);
    return m;
}

std::size_t count(const SeamReport& r, SeamClass c) { return r.edges[static_cast<int>(c)].size(); }

// Points (of simplify()'s numbering) on a seam of class c.
std::set<std::uint32_t> seam_points(const SeamReport& r, SeamClass c, const SimplifyResult& s) {
    std::set<std::uint32_t> out;
    for (const auto& [a, b] : r.edges[static_cast<int>(c)]) {
        out.insert(s.input_points[a]);
        out.insert(s.input_points[b]);
    }
    return out;
}

// A collapse from a point on a seam of class c lands on a point of that seam (half-edge: seam points of
// every later state are seam points of the input).
void expect_never_crossed(const Mesh& in, SeamClass c, float ratio) {
    SCOPED_TRACE(std::string(to_string(c)));
    const SeamReport r = classify_seams(in);
    ASSERT_GT(count(r, c), 0u);
    SimplifyParams p;
    p.target_ratio = ratio;
    const SimplifyResult s = simplify(in, p);
    const std::set<std::uint32_t> on = seam_points(r, c, s);
    std::size_t along = 0;
    for (const Collapse& k : s.collapses) {
        if (!on.count(k.from_point)) continue;
        EXPECT_TRUE(on.count(k.to_point)) << "point " << k.from_point << " left its seam for " << k.to_point;
        ++along;
    }
    EXPECT_GT(along, 0u);  // the seam was simplified, along itself
}

}  // namespace

TEST(Seams, EachClassIsFoundWhereItIsBuilt) {
    const int n = 24;
    struct Case {
        const char* what;
        SeamClass cls;
    };
    for (const Case& c : {Case{"uv", SeamClass::uv}, Case{"color", SeamClass::color}, Case{"crease", SeamClass::crease},
                          Case{"material", SeamClass::material}, Case{"mirror", SeamClass::uv_mirror}}) {
        SCOPED_TRACE(c.what);
        const SeamReport r = classify_seams(split_grid(c.what, n));
        // The split column: n edges; the open grid's outline: 4n border edges; nothing else.
        for (int k = 0; k < kSeamClasses; ++k) {
            const auto cls = static_cast<SeamClass>(k);
            const std::size_t expected = cls == c.cls ? std::size_t(n) : cls == SeamClass::border ? std::size_t(4 * n) : 0;
            EXPECT_EQ(count(r, cls), expected) << to_string(cls);
        }
        EXPECT_EQ(r.edge_count, std::size_t(3 * n * n + 2 * n));
    }
}

TEST(Seams, NonManifoldEdges) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};  // three faces on edge 0-1
    const SeamReport r = classify_seams(m);
    EXPECT_EQ(count(r, SeamClass::non_manifold), 1u);
    EXPECT_EQ(count(r, SeamClass::border), 6u);
}

TEST(Seams, RealAssets) {
    const Mesh spot = read_mesh(test::sample("spot/spot_triangulated.obj"));
    const SeamReport s = classify_seams(spot);
    EXPECT_GT(count(s, SeamClass::uv), 50u);  // Spot's atlas is cut into charts
    EXPECT_EQ(count(s, SeamClass::border), 0u);  // and closed
    EXPECT_EQ(count(s, SeamClass::non_manifold), 0u);
    const Mesh bunny = read_mesh(test::shared_data("scan-bunny/bun_zipper.ply"));
    const SeamReport b = classify_seams(bunny);
    EXPECT_GT(count(b, SeamClass::border), 100u);  // the scan's holes
    EXPECT_EQ(count(b, SeamClass::uv), 0u);
}

TEST(Seams, ProtectedSeamsAreNeverCrossed) {
    expect_never_crossed(split_grid("uv"), SeamClass::uv, 0.1f);
    expect_never_crossed(split_grid("color"), SeamClass::color, 0.1f);
    expect_never_crossed(split_grid("crease"), SeamClass::crease, 0.1f);
    expect_never_crossed(split_grid("material"), SeamClass::material, 0.1f);
    expect_never_crossed(read_mesh(test::sample("spot/spot_triangulated.obj")), SeamClass::uv, 0.05f);
    expect_never_crossed(read_mesh(test::shared_data("scan-bunny/bun_zipper.ply")), SeamClass::border, 0.05f);
}

// A weight on a class makes its seams dearer to simplify: at the same triangle count the output keeps
// more of them (the bunny's hole borders; Spot's UV seams).
TEST(Seams, WeightedClassesKeepMoreOfTheirEdges) {
    struct Case {
        std::string mesh;
        SeamClass cls;
    };
    for (const Case& c : {Case{test::shared_data("scan-bunny/bun_zipper.ply"), SeamClass::border},
                          Case{test::sample("spot/spot_triangulated.obj"), SeamClass::uv}}) {
        SCOPED_TRACE(std::string(to_string(c.cls)));
        const Mesh in = read_mesh(c.mesh);
        SimplifyParams p;
        p.target_ratio = 0.05f;
        const SimplifyResult plain = simplify(in, p);
        p.seam_weights = parse_seam_weights("weight=" + std::string(to_string(c.cls)) + ":20");
        ASSERT_EQ(p.seam_weights.size(), std::size_t(kSeamClasses));
        const SimplifyResult weighted = simplify(in, p);
        const std::size_t before = count(classify_seams(plain.mesh), c.cls), after = count(classify_seams(weighted.mesh), c.cls);
        std::printf("%s at 5%%: %zu %s edges unweighted, %zu with weight 20 (%zu and %zu triangles)\n", c.mesh.c_str(),
                    before, std::string(to_string(c.cls)).c_str(), after, plain.triangles, weighted.triangles);
        EXPECT_GT(after, before + before / 4);
        EXPECT_NEAR(double(weighted.triangles), double(plain.triangles), 0.01 * double(plain.triangles));
    }
}

TEST(Seams, SeamWeightTextIsChecked) {
    const std::vector<float> w = parse_seam_weights("weight=crease:4,border:2.5");
    EXPECT_EQ(w[static_cast<int>(SeamClass::crease)], 4.f);
    EXPECT_EQ(w[static_cast<int>(SeamClass::border)], 2.5f);
    EXPECT_EQ(w[static_cast<int>(SeamClass::uv)], 1.f);
    for (const char* bad : {"protect=uv", "weight=creases:4", "weight=crease:0", "weight=crease:x", "weight=crease",
                            "weight=crease:nan"})
        EXPECT_THROW(parse_seam_weights(bad), Error) << bad;
    SimplifyParams p;
    p.target_ratio = 0.5f;
    p.seam_weights = {1.f, -1.f};
    EXPECT_THROW(simplify(split_grid("uv"), p), Error);
}
