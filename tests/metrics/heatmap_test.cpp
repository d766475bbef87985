#include "lodforge/error.h"
#include "lodforge/metrics/heatmap.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/io/ply.h"
#include "lodforge/simplify/simplify_cluster.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <tuple>

using namespace lodforge;

TEST(Heatmap, ViridisRunsFromPurpleToYellow) {
    const Vec4f lo = viridis(0.f), hi = viridis(1.f), mid = viridis(0.5f);
    EXPECT_NEAR(lo.x, 68 / 255.f, 1e-6f);
    EXPECT_NEAR(hi.y, 231 / 255.f, 1e-6f);
    EXPECT_GT(mid.y, lo.y);
    EXPECT_LT(mid.y, hi.y);
    EXPECT_EQ(viridis(-1.f), lo);
    EXPECT_EQ(viridis(2.f), hi);
    EXPECT_EQ(viridis(NAN), lo);
    EXPECT_EQ(lo.w, 1.f);
}

TEST(Heatmap, ClusteredBunnyHeatmapReadsBackWithColoursAndQuality) {
    // Clustered vertices leave the surface (half-edge collapses keep them on it: distance 0 everywhere).
    const Mesh in = read_mesh(test::shared_data("scan-bunny/bun_zipper.ply"));
    ClusterParams p;
    p.target_ratio = 0.05f;
    const ClusterResult s = simplify_cluster(in, p);
    const DistanceResult d = compare(in, s.mesh);
    ASSERT_EQ(d.vertex_errors.size(), s.mesh.vertex_count());
    const Heatmap h = make_heatmap(s.mesh, d.vertex_errors);
    EXPECT_FLOAT_EQ(h.range_max, *std::max_element(d.vertex_errors.begin(), d.vertex_errors.end()));
    test::ScratchDir dir("heatmap");
    const std::string path = dir.file("heat.ply");
    write_heatmap_ply(h, path);

    const Mesh back = read_ply(path);
    ASSERT_EQ(back.vertex_count(), s.mesh.vertex_count());
    ASSERT_EQ(back.triangle_count(), s.mesh.triangle_count());
    EXPECT_EQ(back.indices, s.mesh.indices);
    ASSERT_TRUE(back.has_colors());
    std::set<std::tuple<int, int, int>> distinct;
    for (const Vec4f& c : back.colors) distinct.insert({int(std::lround(c.x * 255)), int(std::lround(c.y * 255)), int(std::lround(c.z * 255))});
    EXPECT_GT(distinct.size(), 2u);
    for (std::size_t v = 0; v < back.vertex_count(); ++v) ASSERT_EQ(back.positions[v], s.mesh.positions[v]);

    // The quality property carries the distances themselves.
    PlyReader reader(path);
    const PlyElement* vertex = reader.header().find_element("vertex");
    ASSERT_NE(vertex, nullptr);
    const int q = vertex->find_property("quality");
    ASSERT_GE(q, 0);
    EXPECT_EQ(vertex->properties[q].type, PlyType::float32);
    EXPECT_EQ(reader.header().format, PlyEncoding::binary_little_endian);
    // Record layout: x y z quality (4 floats) + 4 uchar; check one value by hand.
    std::ifstream raw(path, std::ios::binary);
    raw.seekg(static_cast<std::streamoff>(reader.header().data_offset + 20 * 7 + 12));
    float quality = -1;
    raw.read(reinterpret_cast<char*>(&quality), sizeof quality);
    EXPECT_EQ(quality, d.vertex_errors[7]);
}

TEST(Heatmap, RangeSaturatesAndBadInputIsRejected) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    const Heatmap h = make_heatmap(m, {0.f, 0.5f, 3.f}, 1.f);
    EXPECT_EQ(h.mesh.colors[0], viridis(0.f));
    EXPECT_EQ(h.mesh.colors[1], viridis(0.5f));
    EXPECT_EQ(h.mesh.colors[2], viridis(1.f));
    EXPECT_EQ(h.quality[2], 3.f);
    EXPECT_THROW(make_heatmap(m, {0.f, 1.f}), Error);
    EXPECT_THROW(make_heatmap(m, {0.f, -1.f, 1.f}), Error);
    EXPECT_THROW(make_heatmap(m, {0.f, NAN, 1.f}), Error);
    test::ScratchDir dir("heatmap-io");
    EXPECT_THROW(write_heatmap_ply(h, dir.file("missing/dir/h.ply")), Error);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

namespace {

// A grid of n x n vertices in the plane z = 0, two triangles per cell.
Mesh grid(int n) {
    Mesh m;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) m.positions.push_back({float(x), float(y), 0.f});
    for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
            const auto v = static_cast<std::uint32_t>(y * n + x), w = static_cast<std::uint32_t>(n);
            m.indices.insert(m.indices.end(), {v, v + 1, v + w, v + 1, v + w + 1, v + w});
        }
    return m;
}

}  // namespace

TEST(HeatmapRange, IgnoresVerticesNoTriangleUses) {
    Mesh m = grid(20);
    std::vector<float> values(m.vertex_count());
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(i % 10) * 0.1f;  // 0 .. 0.9
    // Unused vertices far away with a large distance, as scans carry them.
    for (int k = 0; k < 50; ++k) {
        m.positions.push_back({1000.f, 0.f, float(k)});
        values.push_back(87.f);
    }
    const float top = 9.f * 0.1f;
    EXPECT_EQ(heatmap_range(m, values, 1.f), top);
    EXPECT_EQ(heatmap_range(m, values), top);  // a tenth of the used vertices are at the top
}

TEST(HeatmapRange, OneOutlierDoesNotSetTheRange) {
    const Mesh m = grid(30);  // 900 used vertices
    std::vector<float> values(m.vertex_count(), 1.f);
    values[123] = 500.f;
    EXPECT_FLOAT_EQ(heatmap_range(m, values), 1.f);
    EXPECT_FLOAT_EQ(heatmap_range(m, values, 1.f), 500.f);
    // Many large values are not outliers: the range follows them.
    for (std::size_t i = 0; i < 100; ++i) values[i] = 7.f;
    EXPECT_FLOAT_EQ(heatmap_range(m, values), 7.f);
}

TEST(HeatmapRange, NearestRankPercentile) {
    const Mesh m = grid(10);  // 100 used vertices
    std::vector<float> values(m.vertex_count());
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(i + 1);  // 1 .. 100
    EXPECT_FLOAT_EQ(heatmap_range(m, values, 0.99f), 99.f);
    EXPECT_FLOAT_EQ(heatmap_range(m, values, 0.5f), 50.f);
    EXPECT_FLOAT_EQ(heatmap_range(m, values, 0.001f), 1.f);
}

TEST(HeatmapRange, ZeroFieldsAndBadArguments) {
    const Mesh m = grid(4);
    EXPECT_EQ(heatmap_range(m, std::vector<float>(m.vertex_count(), 0.f)), 0.f);
    std::vector<float> values(m.vertex_count(), 2.f);
    values[0] = NAN;
    values[1] = -1.f;
    EXPECT_FLOAT_EQ(heatmap_range(m, values), 2.f);  // skipped, not fatal
    EXPECT_THROW(heatmap_range(m, std::vector<float>(3, 1.f)), Error);
    EXPECT_THROW(heatmap_range(m, values, 0.f), Error);
    EXPECT_THROW(heatmap_range(m, values, 1.5f), Error);
    Mesh noTriangles = m;
    noTriangles.indices.clear();
    EXPECT_EQ(heatmap_range(noTriangles, std::vector<float>(m.vertex_count(), 3.f)), 0.f);
}

TEST(HeatmapRange, RealScanWithStrayVerticesKeepsTheLevelsRange) {
    // A clustered bunny's field on the original's vertices, then stray unused vertices at a large distance.
    Mesh in = read_mesh(test::shared_data("scan-bunny/bun_zipper.ply"));
    ClusterParams p;
    p.target_ratio = 0.05f;
    const ClusterResult s = simplify_cluster(in, p);
    std::vector<float> field = compare(s.mesh, in).vertex_errors;
    const float before = heatmap_range(in, field);
    const float largest = *std::max_element(field.begin(), field.end());
    ASSERT_GT(before, 0.f);
    EXPECT_LE(before, largest);
    for (int k = 0; k < 2735; ++k) {
        in.positions.push_back({10.f, 10.f, float(k) * 1e-3f});
        field.push_back(largest * 10.f);
    }
    if (!in.colors.empty()) in.colors.resize(in.positions.size());
    if (!in.normals.empty()) in.normals.resize(in.positions.size());
    EXPECT_FLOAT_EQ(heatmap_range(in, field), before);
}
