#include "lodforge/error.h"
#include "lodforge/pack/preset.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <fstream>

using namespace lodforge;

namespace {
std::string error_of(const std::string& text) {
    try {
        parse_preset(text, "p.json");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(Preset, EmptyObjectGivesTheDefaults) {
    EXPECT_EQ(parse_preset("{}"), Preset{});
    const Preset p;
    ASSERT_EQ(p.levels.size(), 4u);
    EXPECT_EQ(p.levels[2].value, 0.1);
    EXPECT_EQ(p.method, LodMethod::collapse);
    EXPECT_EQ(p.placement, Placement::optimal);
}

TEST(Preset, EveryOptionSurvivesJsonRoundTrip) {
    Preset p;
    p.name = "mobile";
    p.method = LodMethod::lodstrips;
    p.levels = {LodTarget{.kind = LodTarget::Kind::ratio, .value = 0.4},
                LodTarget{.kind = LodTarget::Kind::triangles, .value = 5000},
                LodTarget{.kind = LodTarget::Kind::error, .value = 0.002}};
    p.weights.normal = 0.5f;
    p.weights.color = 0.25f;
    p.weights.texcoord = 2.f;
    p.weights.texcoord_sets = {1.f, 0.5f};
    p.lock_border = true;
    p.placement = Placement::half_edge;
    p.octree = OctreeOptions{.max_triangles_per_node = 4096, .max_depth = 5, .memory_mb = 16};
    p.mcoctree.resolution = 256;
    p.strips.primitive_restart = false;
    p.exports = ExportOptions{.glb = false, .ply = true, .obj = true, .lodstrips = true, .image_error = true};
    p.min_screen_pixels = 32.5;
    p.switching = SwitchParams{.pixels = 0.5, .width = 2560, .height = 1440, .fov_deg = 70, .hysteresis = 0.25};
    const std::string text = preset_to_json(p);
    const Preset back = parse_preset(text);
    EXPECT_EQ(back, p) << text;
    EXPECT_EQ(preset_to_json(back), text) << "saving must be deterministic";
}

TEST(Preset, SaveAndLoadThroughAFile) {
    test::ScratchDir dir("preset-file");
    Preset p;
    p.method = LodMethod::octree;
    p.octree.max_depth = 12;
    save_preset(dir.file("a.json"), p);
    EXPECT_EQ(load_preset(dir.file("a.json")), p);
}

TEST(Preset, PartialPresetChangesOnlyWhatItNames) {
    const Preset p = parse_preset(R"({"method": "cluster", "octree": {"max_depth": 3}})");
    EXPECT_EQ(p.method, LodMethod::cluster);
    EXPECT_EQ(p.octree.max_depth, 3u);
    EXPECT_EQ(p.placement, Placement::optimal);
    EXPECT_EQ(parse_preset(R"({"placement": "half-edge"})").placement, Placement::half_edge);
    EXPECT_EQ(p.octree.max_triangles_per_node, OctreeOptions{}.max_triangles_per_node);
    EXPECT_EQ(p.levels, Preset{}.levels);
}

TEST(Preset, BadInputNamesTheFileAndTheKey) {
    EXPECT_NE(error_of("{").find("p.json: not valid JSON"), std::string::npos);
    EXPECT_NE(error_of("[]").find("must be a JSON object"), std::string::npos);
    EXPECT_NE(error_of(R"({"methd": "collapse"})").find("'methd' is not a known preset option"), std::string::npos);
    EXPECT_NE(error_of(R"({"method": "magic"})").find("accepted: collapse, cluster"), std::string::npos);
    EXPECT_NE(error_of(R"({"levels": []})").find("'levels' must be a non-empty array"), std::string::npos);
    EXPECT_NE(error_of(R"({"levels": [{"ratio": 1.5}]})").find("'levels[0].ratio' must be between"), std::string::npos);
    // A ratio of 1 would copy level 0 (build_lod_chain and `lod --levels` refuse it too).
    EXPECT_NE(error_of(R"({"levels": [{"ratio": 1}]})").find("'levels[0].ratio' must be between"), std::string::npos);
    EXPECT_NE(error_of(R"({"levels": [{"ratio": 0.5, "triangles": 10}]})").find("exactly one"), std::string::npos);
    EXPECT_NE(error_of(R"({"levels": [{"triangles": 2.5}]})").find("must be an integer"), std::string::npos);
    EXPECT_NE(error_of(R"({"octree": {"max_depth": 0}})").find("'octree.max_depth'"), std::string::npos);
    EXPECT_NE(error_of(R"({"octree": {"depth": 4}})").find("'octree.depth' is not a known"), std::string::npos);
    EXPECT_NE(error_of(R"({"weights": {"normal": -1}})").find("'weights.normal'"), std::string::npos);
    EXPECT_NE(error_of(R"({"lock_border": 1})").find("must be true or false"), std::string::npos);
    EXPECT_NE(error_of(R"({"placement": "middle"})").find("accepted: optimal, half-edge"), std::string::npos);
    EXPECT_NE(error_of(R"({"placement": true})").find("'placement' must be a string"), std::string::npos);
    EXPECT_NE(error_of(R"({"version": 99})").find("reads presets up to version 1"), std::string::npos);
    EXPECT_NE(error_of(R"({"export": {"lodstrips": true}})").find("needs \"method\": \"lodstrips\""), std::string::npos);
}

TEST(Preset, AutoLevelsAndSwitchBlock) {
    const Preset p = parse_preset(R"({"levels": "auto", "min_screen_pixels": 24,
        "switch": {"pixels": 2, "screen": [1280, 720], "fov_deg": 45, "hysteresis": 0.2}})");
    EXPECT_TRUE(p.auto_levels);
    EXPECT_EQ(p.levels, Preset{}.levels);  // kept for when auto is switched off
    EXPECT_EQ(p.min_screen_pixels, 24);
    EXPECT_EQ(p.switching.pixels, 2);
    EXPECT_EQ(p.switching.width, 1280u);
    EXPECT_EQ(p.switching.height, 720u);
    EXPECT_EQ(p.switching.fov_deg, 45);
    EXPECT_EQ(p.switching.hysteresis, 0.2);
    const std::string text = preset_to_json(p);
    EXPECT_NE(text.find("\"levels\": \"auto\""), std::string::npos) << text;
    EXPECT_EQ(parse_preset(text), p);
    // The defaults: one pixel on 1920 x 1080, 60 degrees, 10 % margins, 16 pixels.
    const Preset d = parse_preset("{}");
    EXPECT_FALSE(d.auto_levels);
    EXPECT_EQ(d.switching, SwitchParams{});
    EXPECT_EQ(d.min_screen_pixels, 16);

    EXPECT_NE(error_of(R"({"levels": "some"})").find("'levels' must be a non-empty array or \"auto\""), std::string::npos);
    EXPECT_NE(error_of(R"({"switch": {"screen": [1920]}})").find("'switch.screen' must be [width, height]"), std::string::npos);
    EXPECT_NE(error_of(R"({"switch": {"screen": [0, 10]}})").find("'switch.screen'"), std::string::npos);
    EXPECT_NE(error_of(R"({"switch": {"fov_deg": 180}})").find("'switch.fov_deg' must be between"), std::string::npos);
    EXPECT_NE(error_of(R"({"switch": {"hysteresis": 1}})").find("'switch.hysteresis'"), std::string::npos);
    EXPECT_NE(error_of(R"({"switch": {"pixel": 1}})").find("'switch.pixel' is not a known"), std::string::npos);
    EXPECT_NE(error_of(R"({"min_screen_pixels": 0})").find("'min_screen_pixels'"), std::string::npos);
}

TEST(Preset, MissingFileIsAnIoError) {
    try {
        load_preset("/nonexistent/preset.json");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::io);
        EXPECT_NE(std::string(e.what()).find("/nonexistent/preset.json"), std::string::npos);
    }
}
