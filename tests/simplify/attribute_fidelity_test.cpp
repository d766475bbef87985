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

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

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

// Every textured asset of the corpus (and the many-chart atlas), for the chart tests below.
std::vector<std::pair<std::string, Mesh>> textured_assets() {
    const Mesh spot = read_mesh(test::sample("spot/spot_triangulated.obj"));
    return {
        {"spot", spot},
        {"duck", read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"))},
        {"milk truck", read_mesh(test::shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"))},
        {"water bottle", read_mesh(test::shared_data("tex-water-bottle/WaterBottle.gltf"))},
        {"laurana500", read_mesh(test::shared_data("tex-ply-wedge-uv/laurana500.ply"))},
        {"matteonormb", read_mesh(test::shared_data("tex-ply-wedge-uv/matteonormb.ply"))},
        {"many-chart atlas", many_chart_atlas(spot)},
    };
}

}  // namespace

// The seam slits of issue 26: a face whose corners come from two texture charts samples the texture
// across the gap between them. Every textured asset, at the benchmark's three levels.
TEST(AttributeFidelity, NoFaceInterpolatesAcrossUvCharts) {
    for (const auto& [name, in] : textured_assets()) {
        ASSERT_TRUE(in.has_texcoords()) << name;
        for (float ratio : {0.5f, 0.2f, 0.05f}) {
            const SimplifyResult r = simplify(in, at(ratio));
            EXPECT_LT(r.mesh.triangle_count(), in.triangle_count()) << name << " at " << ratio;
            EXPECT_EQ(test::faces_across_islands(in, r.mesh, r.vertex_map), 0u) << name << " at " << ratio;
        }
    }
}

// Faces of a half-edge level whose texture is turned over: the UV triangle of the input face, with its
// corners moved as the collapses move them, has the opposite orientation (or none) while the input's had one.
std::size_t folded_texture_faces(const Mesh& in, const SimplifyResult& r) {
    std::vector<std::uint32_t> to(in.vertex_count());
    std::iota(to.begin(), to.end(), 0u);
    for (const VertexMove& m : r.moves) to[m.from] = m.to;
    auto last = [&](std::uint32_t v) {
        while (to[v] != v) v = to[v];
        return v;
    };
    const auto& uv = in.texcoords[0];
    auto area = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        return (double(uv[b].x) - uv[a].x) * (double(uv[c].y) - uv[a].y) -
               (double(uv[b].y) - uv[a].y) * (double(uv[c].x) - uv[a].x);
    };
    std::size_t folded = 0;
    for (std::size_t f = 0; f < in.triangle_count(); ++f) {
        const std::uint32_t* i = &in.indices[3 * f];
        const std::uint32_t a = last(i[0]), b = last(i[1]), c = last(i[2]);
        const auto& pt = r.input_points;
        if (pt[a] == pt[b] || pt[b] == pt[c] || pt[a] == pt[c]) continue;  // collapsed away
        const double before = area(i[0], i[1], i[2]);
        if (before != 0 && !(area(a, b, c) * before > 0)) ++folded;
    }
    return folded;
}

// A collapse must not fold a face's texture over (Simplifier::texture_kept): a folded UV triangle draws a
// mirrored strip of texture from beyond its neighbours, often from another chart. Without the check the
// same runs fold 4, 12 and 9 of Spot's faces at 50, 20 and 5 % and 20, 56 and 24 of the Duck's, unseen
// by the normal test (a face may turn by up to 78 degrees) and by the attribute cost.
TEST(AttributeFidelity, NoFaceTurnsItsTextureOver) {
    for (const auto& [name, in] : textured_assets()) {
        ASSERT_TRUE(in.has_texcoords()) << name;
        for (float ratio : {0.5f, 0.2f, 0.05f}) {
            const SimplifyResult r = simplify(in, at(ratio));
            EXPECT_LT(r.mesh.triangle_count(), in.triangle_count()) << name << " at " << ratio;
            EXPECT_EQ(folded_texture_faces(in, r), 0u) << name << " at " << ratio;
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

// Normals weigh as directions: color.ply's PLY normals are up to 6.3 long (its glTF conversion holds
// them normalised), and the same mesh must simplify alike with either. Unnormalised normals used to
// weigh their differences up to 40x and starve the colours (351 triangles: colour RMS 9.1 from the PLY,
// 4.9 from its GLB).
TEST(AttributeFidelity, UnnormalisedNormalsWeighLikeUnitOnes) {
    const Mesh raw = read_mesh(test::shared_data("color-open3d-small/color.ply"));
    ASSERT_TRUE(raw.has_normals() && raw.has_colors());
    float longest = 0;
    for (const Vec3f& n : raw.normals) longest = std::max(longest, length(n));
    ASSERT_GT(longest, 2.f);  // the case this test is about
    Mesh unit = raw;
    for (Vec3f& n : unit.normals)
        if (length(n) > 0) n = n * (1.f / length(n));
    SimplifyParams p;
    p.target_triangles = 351;
    DistanceParams d;
    d.samples = 100000;
    const DistanceResult from_raw = compare(raw, simplify(raw, p).mesh, d);
    const DistanceResult from_unit = compare(raw, simplify(unit, p).mesh, d);
    ASSERT_TRUE(from_raw.has_color_error && from_unit.has_color_error);
    std::printf("color.ply at 351 triangles: colour RMS %.2f from raw normals, %.2f from unit normals\n",
                from_raw.color_rms, from_unit.color_rms);
    EXPECT_LT(from_raw.color_rms, 1.1 * from_unit.color_rms);
    EXPECT_LT(from_raw.color_rms, 6.0);
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

namespace {

SimplifyParams optimal_at(float ratio) {
    SimplifyParams p = at(ratio);
    p.placement = Placement::optimal;
    return p;
}

// Normal error, measured as compare() measures colour: the unit normals written as colours (n + 1) / 2,
// interpolated at the test samples and at their closest reference points; RMS on the 0-255 scale.
double normal_rms(const Mesh& in, const Mesh& out) {
    auto as_colours = [](Mesh m) {
        m.colors.resize(m.vertex_count());
        for (std::size_t i = 0; i < m.vertex_count(); ++i) {
            const Vec3f n = m.normals[i];
            m.colors[i] = {0.5f * (n.x + 1), 0.5f * (n.y + 1), 0.5f * (n.z + 1), 1.f};
        }
        return m;
    };
    DistanceParams d;
    d.vertex_errors = false;
    const DistanceResult r = compare(as_colours(in), as_colours(out), d);
    EXPECT_TRUE(r.has_color_error);
    return r.color_rms;
}

DistanceResult distances(const Mesh& in, const Mesh& out) {
    DistanceParams d;
    d.vertex_errors = false;
    return compare(in, out, d);
}

}  // namespace

// Optimal placement moves the kept point and re-solves its wedges' attributes there (docs/
// simplification.md "Placement"): the texture and shading must not get worse than half-edge's, which keeps
// the input values, while the geometric error drops.
TEST(AttributeFidelity, OptimalPlacementLowersGeometricErrorWithoutWorseAttributes) {
    const std::pair<std::string, Mesh> assets[] = {
        {"spot", read_mesh(test::sample("spot/spot_triangulated.obj"))},
        {"duck", read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"))},
    };
    for (const auto& [name, in] : assets) {
        const SimplifyResult half = simplify(in, at(0.2f));
        const SimplifyResult opt = simplify(in, optimal_at(0.2f));
        const DistanceResult dh = distances(in, half.mesh), dopt = distances(in, opt.mesh);
        std::printf("%s 20%%: mean %.3e -> %.3e, UV RMS %.3e -> %.3e (half-edge -> optimal)\n", name.c_str(),
                    dh.mean_relative, dopt.mean_relative, dh.texcoord_rms, dopt.texcoord_rms);
        EXPECT_LT(dopt.mean_relative, dh.mean_relative) << name;
        ASSERT_TRUE(dopt.has_texcoord_error) << name;
        EXPECT_LE(dopt.texcoord_rms, dh.texcoord_rms) << name;
        if (in.has_normals()) {
            const double nh = normal_rms(in, half.mesh), nopt = normal_rms(in, opt.mesh);
            std::printf("%s 20%%: normal RMS %.3f -> %.3f\n", name.c_str(), nh, nopt);
            EXPECT_LE(nopt, nh) << name;
        }
    }
}

// The solved attributes come from one wedge's quadric, which only holds faces of that wedge's chart: on
// an atlas of many small charts (each in its own slot of the texture) every output UV stays inside the
// UV box of its input chart, no face spans two charts, and every normal is unit length.
TEST(AttributeFidelity, OptimalPlacementSolvesUvsWithinTheirChart) {
    const Mesh spot = read_mesh(test::sample("spot/spot_triangulated.obj"));
    const Mesh duck = read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"));
    const std::pair<std::string, Mesh> assets[] = {{"many-chart atlas", many_chart_atlas(spot)}, {"duck", duck}};
    for (const auto& [name, in] : assets) {
        const std::vector<std::uint32_t> island = test::wedge_islands(in);
        std::map<std::uint32_t, std::pair<Vec2f, Vec2f>> box;  // island -> UV min, max
        for (std::size_t v = 0; v < in.vertex_count(); ++v) {
            const Vec2f t = in.texcoords[0][v];
            auto [it, inserted] = box.emplace(island[v], std::make_pair(t, t));
            auto& [lo, hi] = it->second;
            lo = {std::min(lo.x, t.x), std::min(lo.y, t.y)};
            hi = {std::max(hi.x, t.x), std::max(hi.y, t.y)};
        }
        for (float ratio : {0.2f, 0.05f}) {
            const SimplifyResult r = simplify(in, optimal_at(ratio));
            EXPECT_EQ(test::faces_across_islands(in, r.mesh, r.vertex_map), 0u) << name << " at " << ratio;
            std::size_t outside = 0, moved = 0;
            for (std::size_t i = 0; i < r.mesh.vertex_count(); ++i) {
                const std::uint32_t v = r.vertex_map[i];
                const auto& [lo, hi] = box.at(island[v]);
                const Vec2f t = r.mesh.texcoords[0][i];
                constexpr float eps = 1e-4f;
                outside += t.x < lo.x - eps || t.y < lo.y - eps || t.x > hi.x + eps || t.y > hi.y + eps;
                moved += t.x != in.texcoords[0][v].x || t.y != in.texcoords[0][v].y;
            }
            EXPECT_EQ(outside, 0u) << name << " at " << ratio;
            EXPECT_GT(moved, r.mesh.vertex_count() / 2) << name << " at " << ratio << ": UVs were not re-solved";
            for (const Vec3f& n : r.mesh.normals) EXPECT_NEAR(length(n), 1.f, 1e-4f) << name;
        }
    }
}

namespace {

// Border edges (one face, on points) of a mesh, as position pairs.
std::vector<std::pair<Vec3f, Vec3f>> border_segments(const Mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<int, std::pair<std::uint32_t, std::uint32_t>>> edges;
    auto pid = [&](std::uint32_t v) { return m.position_ids.empty() ? v : m.position_ids[v]; };
    for (std::size_t f = 0; f < m.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t va = m.indices[3 * f + k], vb = m.indices[3 * f + (k + 1) % 3];
            const std::uint32_t a = pid(va), b = pid(vb);
            if (a == b) continue;
            auto& e = edges[{std::min(a, b), std::max(a, b)}];
            ++e.first;
            e.second = {va, vb};
        }
    std::vector<std::pair<Vec3f, Vec3f>> out;
    for (const auto& [key, e] : edges)
        if (e.first == 1) out.push_back({m.positions[e.second.first], m.positions[e.second.second]});
    return out;
}

double point_segment_distance(Vec3f p, Vec3f a, Vec3f b) {
    const Vec3f ab = b - a;
    const float l2 = dot(ab, ab);
    const float t = l2 > 0.f ? std::clamp(dot(p - a, ab) / l2, 0.f, 1.f) : 0.f;
    const Vec3f d = p - (a + ab * t);
    return std::sqrt(double(dot(d, d)));
}

// Mean distance of the input's border vertices to the output's border, relative to the diagonal: how far
// the outline of an open surface moved.
double outline_error(const Mesh& in, const Mesh& out) {
    const auto before = border_segments(in), after = border_segments(out);
    EXPECT_FALSE(before.empty());
    EXPECT_FALSE(after.empty());
    double sum = 0;
    for (const auto& [a, b] : before) {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& [c, d] : after) best = std::min(best, point_segment_distance(a, c, d));
        sum += best;
    }
    return sum / double(before.size()) / double(in.bounds().diagonal());
}

}  // namespace

// The outline of an open scan is what the eye sees first: its border edges carry heavy constraint planes
// (kBorderPlaneWeight, docs/simplification.md "Borders"), so at 5 % the border stays close. With
// GH97's weight 1 the coloured scans lost to gltfpack in the image compare by their silhouette.
TEST(AttributeFidelity, OpenScansKeepTheirOutline) {
    const Mesh scan = read_mesh(test::shared_data("color-open3d-small/color.ply"));
    for (Placement placement : {Placement::optimal, Placement::half_edge}) {
        SimplifyParams p;
        p.target_triangles = 352;  // 5 %: gltfpack's count in bench/fidelity_bench.mjs
        p.placement = placement;
        const Mesh out = simplify(scan, p).mesh;
        const double e = outline_error(scan, out);
        std::printf("color.ply at 352 triangles, %s: outline error %.3e\n",
                    placement == Placement::optimal ? "optimal" : "half-edge", e);
        // Measured: 2.48e-3 optimal, 2.23e-3 half-edge; 3.60e-3 both with weight 1; gltfpack -sv 1.99e-3.
        EXPECT_LT(e, 2.9e-3);
    }
}
