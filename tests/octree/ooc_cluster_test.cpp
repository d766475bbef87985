#include "lodforge/error.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/octree/ooc_cluster.h"
#include "lodforge/io/ply.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

namespace lodforge {
namespace {

using test::shared_data;

TEST(OocCluster, CoarserGridsGiveFewerTrianglesAndKeepTheShape) {
    const std::string input = shared_data("scan-dragon/dragon_vrip_res3.ply");
    const Mesh ref = read_ply(input);
    std::size_t previous = ~std::size_t{0};
    for (std::size_t grid : {100u, 50u, 25u}) {
        OocClusterParams p;
        p.grid_resolution = grid;
        p.memory_bytes = 8u << 20;
        const OocClusterResult r = ooc_cluster(input, p);
        EXPECT_EQ(r.input_triangles, ref.triangle_count());
        EXPECT_LT(r.mesh.triangle_count(), previous);
        previous = r.mesh.triangle_count();
        EXPECT_EQ(r.grid_dims[0] <= grid && r.grid_dims[1] <= grid && r.grid_dims[2] <= grid, true);
        for (std::uint32_t i : r.mesh.indices) ASSERT_LT(i, r.mesh.vertex_count());
        DistanceParams dp;
        dp.samples = 5000;
        dp.vertex_errors = false;
        const DistanceResult d = compare(ref, r.mesh, dp);
        // Every representative stays in its cell: the error is bounded by about one cell diagonal.
        EXPECT_LT(d.hausdorff, 2.0 * r.cell_size * std::sqrt(3.0)) << grid;
    }
}

TEST(OocCluster, ColoursSurvive) {
    const std::string input = shared_data("color-open3d-frag115/frag_115.ply");
    OocClusterParams p;
    p.grid_resolution = 64;
    const OocClusterResult r = ooc_cluster(input, p);
    ASSERT_EQ(r.mesh.colors.size(), r.mesh.vertex_count());
    ASSERT_EQ(r.mesh.normals.size(), r.mesh.vertex_count());
    DistanceParams dp;
    dp.samples = 5000;
    dp.vertex_errors = false;
    const DistanceResult d = compare(read_ply(input), r.mesh, dp);
    ASSERT_TRUE(d.has_color_error);
    EXPECT_LT(d.color_rms, 25.0);
    OocClusterParams bad;
    bad.grid_resolution = 1;
    EXPECT_THROW(ooc_cluster(input, bad), Error);
}

}  // namespace
}  // namespace lodforge
