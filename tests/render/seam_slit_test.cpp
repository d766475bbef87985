// No seam slits: a simplified level of a textured asset, rendered as the studio draws it, must not show a
// cluster of wrong texture along the original's UV seams (texture sampled across charts shows as a
// dark or foreign-coloured slit there). Spot at 20 % and 5 %, the Duck at 20 %, the wedge-UV PLY at 50 %
// and 20 %, with the default (attribute-aware) simplification; the geometry-only level is measured beside
// it as a control. docs/image-compare.md, "Seam slits".
#include "lodforge/io/mesh_io.h"
#include "lodforge/render/image_compare.h"
#include "lodforge/render/surface.h"
#include "lodforge/simplify/simplify.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <cstdlib>
#include <string>
#include <vector>

using namespace lodforge;

namespace {

constexpr int imageSize = 256;
// A pixel of "wrong texture": in the unlit renders (texture only, no shading), some colour channel
// differs by more than this from every pixel of the original's render within matchRadius. A simplified
// surface moves texture features by a pixel or two; texture sampled across charts brings colours that
// are nowhere near.
constexpr int strongDifference = 64;
constexpr int matchRadius = 2;
// How far from a seam line (pixels) a slit is looked for: the seam moves a little with the level.
constexpr int seamReach = 3;
// The largest cluster of wrong-texture pixels along seams allowed per view: a slit of 1 px width and
// 32 px length at 256 px. At coarse levels the surface itself moves the texture by more than
// matchRadius and the geometry-only control (all attribute weights 0) shows clusters too; there the
// attribute-aware level may not exceed the control by more than a quarter (it must not add slits of
// its own). Every case prints both.
constexpr std::size_t largestAllowed = 32;

std::size_t allowedFor(std::size_t control) {
    return control <= largestAllowed ? largestAllowed : control + control / 4;
}

struct SlitMeasure {
    std::size_t largest = 0;  // the largest cluster, pixels
    std::string view;         // where
};

// Connected (8-neighbour) clusters of wrong-texture pixels covered by both renders within seamReach of
// a visible seam (of the original or of the level).
SlitMeasure measureSlits(const std::vector<render::RenderedView>& original, const std::vector<render::RenderedView>& level,
                         const std::vector<std::vector<unsigned char>>& originalSeams,
                         const std::vector<std::vector<unsigned char>>& levelSeams) {
    SlitMeasure out;
    const int n = imageSize;
    for (std::size_t v = 0; v < original.size(); ++v) {
        const auto& a = original[v];
        const auto& b = level[v];
        std::vector<unsigned char> nearSeam(std::size_t(n) * std::size_t(n), 0);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const auto p = std::size_t(y * n + x);
                if (!originalSeams[v][p] && !(levelSeams[v].size() > p && levelSeams[v][p])) continue;
                for (int dy = -seamReach; dy <= seamReach; ++dy)
                    for (int dx = -seamReach; dx <= seamReach; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx >= 0 && yy >= 0 && xx < n && yy < n) nearSeam[std::size_t(yy * n + xx)] = 1;
                    }
            }
        std::vector<unsigned char> wrong(nearSeam.size(), 0);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const auto p = std::size_t(y * n + x);
                if (!nearSeam[p] || !a.mask[p] || !b.mask[p]) continue;
                int closest = 256;
                for (int dy = -matchRadius; dy <= matchRadius && closest > strongDifference; ++dy)
                    for (int dx = -matchRadius; dx <= matchRadius; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= n || yy >= n) continue;
                        const auto q = std::size_t(yy * n + xx);
                        if (!a.mask[q]) continue;
                        int largest = 0;
                        for (std::size_t c = 0; c < 3; ++c)
                            largest = std::max(largest, std::abs(int(a.rgb[3 * q + c]) - int(b.rgb[3 * p + c])));
                        closest = std::min(closest, largest);
                    }
                wrong[p] = closest > strongDifference ? 1 : 0;
            }
        std::vector<int> stack;
        for (std::size_t start = 0; start < wrong.size(); ++start) {
            if (wrong[start] != 1) continue;
            std::size_t size = 0;
            stack.assign(1, int(start));
            wrong[start] = 2;
            while (!stack.empty()) {
                const int p = stack.back();
                stack.pop_back();
                ++size;
                const int x = p % n, y = p / n;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= n || yy >= n) continue;
                        const auto q = std::size_t(yy * n + xx);
                        if (wrong[q] == 1) {
                            wrong[q] = 2;
                            stack.push_back(int(q));
                        }
                    }
            }
            if (size > out.largest) {
                out.largest = size;
                out.view = render::viewNames()[v];
            }
        }
    }
    return out;
}

struct Case {
    const char* name;
    const char* file;  // under the shared data
    float ratio;
};

class SeamSlits : public ::testing::TestWithParam<Case> {};

TEST_P(SeamSlits, SimplifiedLevelShowsNoWrongTextureAlongSeams) {
    const Case c = GetParam();
    const Mesh original = read_mesh(test::shared_data(c.file));
    ASSERT_TRUE(original.has_texcoords()) << c.file;
    const auto images = render::decodeBaseColorTextures(original);
    ASSERT_TRUE(std::any_of(images.begin(), images.end(), [](const auto& i) { return i && !i->empty(); })) << c.file;

    auto level = [&](bool attributes) {
        SimplifyParams p;
        p.target_ratio = c.ratio;
        if (!attributes) p.weights = {0.f, 0.f, 0.f, {}};
        return simplify(original, p).mesh;
    };
    const Mesh withAttributes = level(true);
    const Mesh geometryOnly = level(false);

    const auto reference = render::renderViews(original, images, original, imageSize, true);
    const auto seams = render::seamMasks(original, original, imageSize);
    std::size_t seamPixels = 0;
    for (const auto& m : seams) seamPixels += std::size_t(std::count(m.begin(), m.end(), 1));
    ASSERT_GT(seamPixels, 100u) << "the seams of " << c.file << " must show for the test to mean anything";

    auto measure = [&](const Mesh& simplified) {
        return measureSlits(reference, render::renderViews(simplified, images, original, imageSize, true), seams,
                            render::seamMasks(simplified, original, imageSize));
    };
    const SlitMeasure control = measure(geometryOnly);
    const SlitMeasure measured = measure(withAttributes);
    std::printf("%s at %.0f %%: %zu triangles; largest wrong-texture cluster along seams %zu px (view %s), "
                "geometry-only %zu px (view %s); seam pixels %zu\n",
                c.name, 100.0 * c.ratio, withAttributes.triangle_count(), measured.largest, measured.view.c_str(),
                control.largest, control.view.c_str(), seamPixels);
    EXPECT_LE(measured.largest, allowedFor(control.largest))
        << c.name << ": a slit of " << measured.largest << " px along a UV seam in view " << measured.view
        << " (geometry-only level: " << control.largest << " px)";
}

// The measure can fail: Spot with every seam wedge given the texture coordinates of the first wedge at
// its position (as a collapse that merges wedges across charts does) shows slits along the seams.
TEST(SeamSlitMeasure, CatchesTextureSampledAcrossCharts) {
    const Mesh original = read_mesh(test::shared_data("tex-spot/spot_triangulated.obj"));
    const auto images = render::decodeBaseColorTextures(original);
    Mesh broken = original;
    std::map<std::array<float, 3>, std::uint32_t> firstAt;
    std::size_t changed = 0;
    for (std::uint32_t v = 0; v < broken.vertex_count(); ++v) {
        const Vec3f& p = broken.positions[v];
        const auto [it, inserted] = firstAt.try_emplace(std::array<float, 3>{p.x, p.y, p.z}, v);
        if (inserted) continue;
        auto& uv = broken.texcoords.front();
        if (!(uv[v] == uv[it->second])) {
            uv[v] = uv[it->second];
            ++changed;
        }
    }
    ASSERT_GT(changed, 50u);
    const auto reference = render::renderViews(original, images, original, imageSize, true);
    const SlitMeasure m = measureSlits(reference, render::renderViews(broken, images, original, imageSize, true),
                                       render::seamMasks(original, original, imageSize),
                                       render::seamMasks(broken, original, imageSize));
    std::printf("Spot with %zu wedges sampling across charts: largest cluster %zu px (view %s)\n", changed, m.largest,
                m.view.c_str());
    EXPECT_GT(m.largest, largestAllowed);
}

// Duck at 5 % (186 px against the control's 115) fails today and is an open defect (docs/image-compare.md,
// "Seam slits", issue 26); it joins this list when the simplifier is fixed. laurana500 at 20 % passes
// because the simplifier refuses collapses that fold a face's texture over (Simplifier::texture_kept;
// 389 px without).
INSTANTIATE_TEST_SUITE_P(
    TexturedAssets, SeamSlits,
    ::testing::Values(Case{"Spot20", "tex-spot/spot_triangulated.obj", 0.2f}, Case{"Spot5", "tex-spot/spot_triangulated.obj", 0.05f},
                      Case{"Duck20", "tex-duck/glTF_Binary/Duck.glb", 0.2f},
                      // 494 triangles: 20 % is about as far as its seams let it go.
                      Case{"Laurana50", "tex-ply-wedge-uv/laurana500.ply", 0.5f},
                      Case{"Laurana20", "tex-ply-wedge-uv/laurana500.ply", 0.2f}),
    [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.name); });

}  // namespace
