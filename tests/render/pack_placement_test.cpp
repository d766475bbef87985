// The image-space error of pack levels (docs/pack.md, "Placement"): with optimal placement, the default,
// each collapse level has its own vertices moved to the quadric optimum with re-solved UVs and normals,
// and renders closer to the input than the half-edge level (input vertices, one shared buffer) at the
// same triangle count. Spot and the Duck at 20 %, rendered by the front ends' PackParams::image_error.
#include "lodforge/io/mesh_io.h"
#include "lodforge/pack/lod_pack.h"
#include "lodforge/render/image_compare.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace lodforge;

namespace {

// Level 1 of a one-level pack (20 %), with its image error.
PackLevel packLevel(const std::string& source, Placement placement, const test::ScratchDir& dir) {
    PackParams p;
    p.source_path = source;
    p.output_dir = dir.file(placement == Placement::optimal ? "optimal" : "half-edge");
    p.preset.levels = lod_targets_from_ratios({0.2});
    p.preset.placement = placement;
    p.preset.exports = {.glb = false, .ply = false, .obj = false, .lodstrips = false, .image_error = true};
    p.image_error = render::packImageError();
    const PackResult r = write_lod_pack(read_mesh(source), p);
    EXPECT_EQ(r.levels.size(), 2u);
    return r.levels.at(1);
}

}  // namespace

TEST(PackPlacement, OptimalLevelsRenderCloserToTheInputThanHalfEdge) {
    for (const char* asset : {"tex-spot/spot_triangulated.obj", "tex-duck/glTF/Duck.gltf"}) {
        SCOPED_TRACE(asset);
        test::ScratchDir dir("pack-placement-render");
        const std::string source = test::shared_data(asset);
        const PackLevel optimal = packLevel(source, Placement::optimal, dir);
        const PackLevel half = packLevel(source, Placement::half_edge, dir);
        ASSERT_TRUE(optimal.image_error && half.image_error);
        EXPECT_EQ(optimal.triangles, half.triangles);
        std::printf("%s 20 %%: image error optimal %.3f, half-edge %.3f; mean %.3g / %.3g of the diagonal\n", asset,
                    optimal.image_error->mean_abs, half.image_error->mean_abs, optimal.mean_error_relative,
                    half.mean_error_relative);
        EXPECT_LT(optimal.image_error->mean_abs, half.image_error->mean_abs);
        EXPECT_LT(optimal.mean_error_relative, half.mean_error_relative);
    }
}
