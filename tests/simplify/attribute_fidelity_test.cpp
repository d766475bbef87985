// Attribute-aware simplification on real textured and coloured assets (issue 26, docs/simplification.md
// "Attribute fidelity"): texture charts never mix, normals do not inflate the geometric error, the result
// does not depend on the model's scale, and the key cells of bench/fidelity_bench.mjs stay at or below the
// bounds measured there.
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/simplify/simplify.h"

#include "simplify/simplify_test_util.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

using namespace lodforge;

namespace {

SimplifyParams at(float ratio) {
    SimplifyParams p;
    p.target_ratio = ratio;
    return p;
}

double mean_error(const Mesh& in, const Mesh& out) {
    DistanceParams d;
    d.vertex_errors = false;
    return compare(in, out, d).mean_relative;
}

// Spot with its faces grouped by a 6x6x6 grid over their centroids and each group's UVs given their own
// wedges (moved into one slot of a 4x4 atlas): hundreds of small charts, every group border a UV seam.
Mesh many_chart_atlas(const Mesh& in) {
    const Bounds b = in.bounds();
    Mesh out;
    out.texcoords.assign(1, {});
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> wedge;  // (chart, input vertex)
    for (std::size_t f = 0; f < in.triangle_count(); ++f) {
        const std::uint32_t* i = &in.indices[3 * f];
        const Vec3f c = (in.positions[i[0]] + in.positions[i[1]] + in.positions[i[2]]) * (1.f / 3.f);
        auto cell = [](float x, float lo, float hi) { return std::min(5, int(6 * (x - lo) / (hi - lo))); };
        const std::uint32_t chart = std::uint32_t(cell(c.x, b.min.x, b.max.x) + 6 * cell(c.y, b.min.y, b.max.y) +
                                                  36 * cell(c.z, b.min.z, b.max.z));
        const Vec2f slot{0.25f * float(chart % 4), 0.25f * float(chart / 4 % 4)};
        for (int k = 0; k < 3; ++k) {
            auto [it, inserted] = wedge.emplace(std::make_pair(chart, i[k]), std::uint32_t(out.positions.size()));
            if (inserted) {
                out.positions.push_back(in.positions[i[k]]);
                const Vec2f t = in.texcoords[0][i[k]];
                out.texcoords[0].push_back({slot.x + 0.25f * t.x, slot.y + 0.25f * t.y});
            }
            out.indices.push_back(it->second);
        }
    }
    return weld_seams(out);
}

}  // namespace

// The seam slits of issue 26: a face whose corners come from two texture charts samples the texture
// across the gap between them. Every textured asset, at the benchmark's three levels.
TEST(AttributeFidelity, NoFaceInterpolatesAcrossUvCharts) {
    const Mesh spot = read_mesh(test::sample("spot/spot_triangulated.obj"));
    const std::pair<std::string, Mesh> assets[] = {
        {"spot", spot},
        {"duck", read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"))},
        {"milk truck", read_mesh(test::shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"))},
        {"water bottle", read_mesh(test::shared_data("tex-water-bottle/WaterBottle.gltf"))},
        {"laurana500", read_mesh(test::shared_data("tex-ply-wedge-uv/laurana500.ply"))},
        {"matteonormb", read_mesh(test::shared_data("tex-ply-wedge-uv/matteonormb.ply"))},
        {"many-chart atlas", many_chart_atlas(spot)},
    };
    for (const auto& [name, in] : assets) {
        ASSERT_TRUE(in.has_texcoords()) << name;
        for (float ratio : {0.5f, 0.2f, 0.05f}) {
            const SimplifyResult r = simplify(in, at(ratio));
            EXPECT_LT(r.mesh.triangle_count(), in.triangle_count()) << name << " at " << ratio;
            EXPECT_EQ(test::faces_across_islands(in, r.mesh, r.vertex_map), 0u) << name << " at " << ratio;
        }
    }
}

// The cause of issue 26's 4x geometric error: a normal change cost the same whatever the size of the
// region it spans, so at fine scale it outweighed every geometric error. The Duck's normals (smooth, with
// creases) at 20 %: the default weights may cost a little geometric accuracy (1.08x), not double it (it
// was 2.33x).
TEST(AttributeFidelity, NormalsDoNotInflateTheGeometricError) {
    const Mesh in = read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"));
    ASSERT_TRUE(in.has_normals());
    SimplifyParams geometry = at(0.2f);
    geometry.weights = {0, 0, 0, {}};
    const double with = mean_error(in, simplify(in, at(0.2f)).mesh);
    const double without = mean_error(in, simplify(in, geometry).mesh);
    std::printf("Duck 20%%: mean error %.3e with attributes, %.3e geometry only\n", with, without);
    EXPECT_LT(with, 1.25 * without);
}

// The attribute cost is measured against the size of the region a collapse disturbs, relative to the
// bounding-box diagonal, so a model scaled by 0.01 or 100 simplifies the same way (attribute values do not
// scale with the model; a cost in model units would swing between attributes-only and geometry-only).
TEST(AttributeFidelity, ResultDoesNotDependOnTheModelScale) {
    const Mesh in = read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"));
    const double reference = mean_error(in, simplify(in, at(0.2f)).mesh);
    for (float scale : {0.01f, 100.f}) {
        Mesh scaled = in;
        for (Vec3f& p : scaled.positions) p = p * scale;
        const double e = mean_error(scaled, simplify(scaled, at(0.2f)).mesh);
        EXPECT_NEAR(e, reference, 0.1 * reference) << "scale " << scale;
    }
}

// Key cells of the fidelity benchmark (docs/bench-fidelity.md), measured as `lodforge compare` measures
// them: mean error relative to the diagonal at 20 %. The bounds are LodForge's measured values with a
// ~15 % margin; gltfpack 1.3 -sv (run to the same count with -se 1) measured 8.1e-4 (Spot) and 1.79e-3
// (Duck). Spot's gap is the geometric simplifier's (geometry-only gives the same 1.26e-3), not attributes'.
TEST(AttributeFidelity, KeyCellsStayWithinTheirMeasuredBounds) {
    const Mesh spot = read_mesh(test::sample("spot/spot_triangulated.obj"));
    const Mesh duck = read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"));
    const double spot_mean = mean_error(spot, simplify(spot, at(0.2f)).mesh);
    const double duck_mean = mean_error(duck, simplify(duck, at(0.2f)).mesh);
    std::printf("20%%: Spot mean %.3e, Duck mean %.3e\n", spot_mean, duck_mean);
    EXPECT_LT(spot_mean, 1.5e-3);  // measured 1.29e-3; gltfpack 8.1e-4
    EXPECT_LT(duck_mean, 2.4e-3);  // measured 2.08e-3 (4.51e-3 before); gltfpack 1.79e-3
}
