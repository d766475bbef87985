// "levels": "auto" on the shared meshes: every chosen level at least halves the one before it, the last
// one still switches in at the preset's smallest size, the choice is deterministic, and the pack built
// from it validates.
#include "pack_test_util.h"
#include "support/test_paths.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/pack/auto_levels.h"
#include "lodforge/pack/lod_pack.h"
#include "lodforge/pack/preset_levels.h"

#include <gtest/gtest.h>

namespace {

using namespace lodforge;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;

TEST(AutoLevels, OneCandidatePerHalvingOfTheScreenSize) {
    EXPECT_EQ(auto_level_sizes(SwitchParams{}, 16),
              (std::vector<double>{1080, 540, 270, 135, 67.5, 33.75, 16.875}));
    SwitchParams small;
    small.height = 10;
    EXPECT_EQ(auto_level_sizes(small, 16), std::vector<double>{10});  // at least one
}

Mesh read_placed(const std::string& path) {
    ReadOptions read;
    read.place_every_instance = true;
    return read_mesh(path, read);
}

// The rule's promises on one mesh, through build_preset_levels (what the pack, `lod` and the studio call).
void check_auto(const std::string& path, double min_pixels) {
    SCOPED_TRACE(path);
    const Mesh mesh = read_placed(path);
    Preset preset;
    preset.auto_levels = true;
    preset.min_screen_pixels = min_pixels;
    PresetLevelsParams params;
    params.source_path = path;
    const PresetLevels built = build_preset_levels(mesh, preset, params);
    ASSERT_FALSE(built.levels.empty());
    ASSERT_EQ(built.targets.size(), built.levels.size());
    std::size_t previous = mesh.triangle_count();
    for (std::size_t k = 0; k < built.levels.size(); ++k) {
        EXPECT_LE(2 * built.levels[k].triangle_count(), previous) << "level " << k + 1 << " does not halve";
        previous = built.levels[k].triangle_count();
    }
    // The last level takes over where its error is one pixel: a sphere diameter of 1 / error pixels.
    const double last = built.distance.back().hausdorff_relative;
    ASSERT_GT(last, 0.0);
    EXPECT_GE(1.0 / last, min_pixels);
    const std::string& note = built.notes.back();
    EXPECT_NE(note.find("automatic levels"), std::string::npos) << note;
}

TEST(AutoLevels, DuckSpotAndDragon) {
    check_auto(shared_data("tex-duck/glTF_Binary/Duck.glb"), 16);
    check_auto(shared_data("tex-spot/spot_triangulated.obj"), 16);
    check_auto(shared_data("scan-dragon/dragon_vrip_res3.ply"), 16);
}

TEST(AutoLevels, ASmallerMinimumGivesAtLeastAsManyLevels) {
    const std::string path = shared_data("tex-spot/spot_triangulated.obj");
    const Mesh mesh = read_placed(path);
    AutoLevelsParams p;
    p.min_screen_pixels = 64;
    const AutoLevelsResult coarse = choose_auto_levels(mesh, p);
    p.min_screen_pixels = 8;
    const AutoLevelsResult fine = choose_auto_levels(mesh, p);
    EXPECT_GE(fine.targets.size(), coarse.targets.size());
    EXPECT_GT(fine.candidates.size(), coarse.candidates.size());
    // Deterministic: the same input and parameters choose the same levels.
    EXPECT_EQ(choose_auto_levels(mesh, p).targets, fine.targets);
    for (const AutoLevelCandidate& c : fine.candidates)
        EXPECT_NEAR(c.error_target, 1.0 / c.screen_pixels, 1e-15);
}

// The studio builds without measuring; its automatic levels must still be the pack's.
TEST(AutoLevels, SameLevelsWithoutTheMeasurements) {
    const std::string path = shared_data("tex-spot/spot_triangulated.obj");
    const Mesh mesh = read_placed(path);
    Preset preset;
    preset.auto_levels = true;
    preset.min_screen_pixels = 40;
    PresetLevelsParams params;
    params.source_path = path;
    const PresetLevels measured = build_preset_levels(mesh, preset, params);
    params.measure = false;
    const PresetLevels quick = build_preset_levels(mesh, preset, params);
    EXPECT_TRUE(quick.distance.empty());
    ASSERT_EQ(quick.levels.size(), measured.levels.size());
    for (std::size_t k = 0; k < quick.levels.size(); ++k)
        EXPECT_EQ(quick.levels[k].triangle_count(), measured.levels[k].triangle_count()) << k;
}

TEST(AutoLevels, PackValidatesAndRecordsTheRule) {
    ScratchDir dir("auto-pack");
    PackParams params;
    params.preset.auto_levels = true;
    params.source_path = shared_data("tex-duck/glTF_Binary/Duck.glb");
    params.output_dir = dir.file("duck");
    const PackResult r = write_lod_pack(read_placed(params.source_path), params);
    ASSERT_GE(r.levels.size(), 2u);
    const auto j = nlohmann::json::parse(r.manifest);
    EXPECT_EQ(j["preset"]["levels"], "auto");
    EXPECT_EQ(j["levels"].size(), r.levels.size());
    // The last level's switch in: at least the minimum size (16 px diameter) on the reference screen.
    EXPECT_GE(r.levels[r.levels.size() - 2].switching.screen_size * 1080, 16.0 * (1 - 1e-9));
    const auto v = test::validate_gltf(params.output_dir + "/" + r.glb);
    ASSERT_EQ(v.exit_code, 0) << v.raw;
    EXPECT_EQ(test::unexplained_warnings(v), std::vector<std::string>{}) << v.raw;
}

TEST(AutoLevels, OtherMethodsAreRefused) {
    Preset preset;
    preset.auto_levels = true;
    preset.method = LodMethod::cluster;
    const Mesh mesh = read_placed(shared_data("tex-duck/glTF_Binary/Duck.glb"));
    try {
        PresetLevelsParams params;
        params.source_path = "Duck.glb";
        build_preset_levels(mesh, preset, params);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::argument);
        EXPECT_NE(std::string(e.what()).find("collapse"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("Duck.glb"), std::string::npos) << e.what();
    }
}

}  // namespace
