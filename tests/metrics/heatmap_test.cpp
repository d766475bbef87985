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
