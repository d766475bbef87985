// `lodforge pack` as users run it: the pack it writes is byte-identical to write_lod_pack's (which the
// studio's export button calls) for the same preset file, and bad presets, inputs and outputs fail with
// exit status 1, a message naming the file, and no partial pack.
#include "pack_test_util.h"
#include "support/cli_run.h"
#include "support/test_paths.h"

#include "lodforge/pack/lod_pack.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/pack/preset.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

using namespace lodforge;
using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;
using lodforge::test::ScratchDir;
using lodforge::test::sample;
using lodforge::test::shared_data;
namespace fs = std::filesystem;

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

const char* kPreset = R"({
  "name": "game",
  "levels": [ {"ratio": 0.5}, {"triangles": 400} ],
  "weights": { "uv": 0.2 },
  "export": { "glb": true, "ply": true, "obj": false }
})";

TEST(CliPack, SamePackAsTheLibraryForTheSamePreset) {
    ScratchDir dir("cli-pack");
    write_text(dir.file("game.json"), kPreset);
    const std::string input = shared_data("tex-duck/glTF/Duck.gltf");
    const CliRun r = run_cli("pack " + quoted(input) + " --preset " + quoted(dir.file("game.json")) + " -o " +
                             quoted(dir.file("cli")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("lod2: "), std::string::npos) << r.out;

    // What the studio does: load the same preset file, read the same mesh, call the library.
    PackParams p;
    p.preset = load_preset(dir.file("game.json"));
    p.source_path = input;
    p.output_dir = dir.file("studio");
    const PackResult lib = write_lod_pack(read_mesh(input), p);
    ASSERT_EQ(lib.files.size(), 5u);  // glb, 3 PLY, pack.json
    for (const std::string& f : lib.files) {
        ASSERT_TRUE(fs::exists(dir.file("cli/" + f))) << f;
        EXPECT_EQ(test::read_bytes(dir.file("cli/" + f)), test::read_bytes(dir.file("studio/" + f))) << f;
    }
    const auto v = test::validate_gltf(dir.file("cli/Duck.glb"));
    EXPECT_EQ(v.exit_code, 0) << v.raw;
    const auto manifest = nlohmann::json::parse(test::read_bytes(dir.file("cli/pack.json")));
    EXPECT_EQ(manifest["preset"]["name"], "game");
    EXPECT_EQ(manifest["levels"][2]["triangles"].get<std::size_t>(), lib.levels[2].triangles);
    EXPECT_LE(lib.levels[2].triangles, 400u);
}

TEST(CliPack, JsonListsLevelsAndFiles) {
    ScratchDir dir("cli-pack-json");
    write_text(dir.file("p.json"), R"({"levels": [{"ratio": 0.25}]})");
    const CliRun r = run_cli("pack --json " + quoted(sample("spot/spot_triangulated.obj")) + " --preset " +
                                 quoted(dir.file("p.json")) + " -o " + quoted(dir.file("out")),
                             false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["levels"].size(), 2u);
    EXPECT_EQ(j["levels"][0]["triangles"], 5856);
    EXPECT_GT(j["levels"][1]["error_relative"].get<double>(), 0.0);
    EXPECT_EQ(j["glb"], "spot_triangulated.glb");
    EXPECT_EQ(j["files"], nlohmann::json::array({"spot_triangulated.glb", "pack.json"}));
    EXPECT_EQ(j["source_sha256"].get<std::string>().size(), 64u);
    const test::Glb g = test::split_glb(test::read_bytes(dir.file("out/spot_triangulated.glb")));
    EXPECT_EQ(test::node_triangles(g, 1), j["levels"][1]["triangles"].get<std::size_t>());
    EXPECT_EQ(g.json["images"].size(), 1u);
}

// CesiumMilkTruck's "Wheels" mesh is placed by two nodes (front and rear axle): the pack holds both,
// at their nodes' transforms, as the studio shows the truck (3,624 triangles, not the 2,856 of one
// placement per mesh).
TEST(CliPack, EveryPlacementOfAnInstancedMeshIsInThePack) {
    ScratchDir dir("cli-pack-instances");
    const CliRun r = run_cli("pack --json " + quoted(shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf")) +
                                 " --levels 0.5 -o " + quoted(dir.file("out")),
                             false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["levels"][0]["triangles"], 3624);
    const test::Glb g = test::split_glb(test::read_bytes(dir.file("out/CesiumMilkTruck.glb")));
    EXPECT_EQ(test::node_triangles(g, 0), 3624u);
    // The reader's default (each mesh once, at its first placement) is what packs held before.
    const Mesh one = read_mesh(shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"));
    ReadOptions every;
    every.place_every_instance = true;
    const Mesh all = read_mesh(shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"), every);
    EXPECT_EQ(all.triangle_count(), 3624u);
    EXPECT_EQ(one.triangle_count(), 2856u);
}

TEST(CliPack, BadPresetMissingInputAndUnwritableOutputFailCleanly) {
    ScratchDir dir("cli-pack-bad");
    const std::string input = quoted(sample("spot/spot_triangulated.obj"));
    write_text(dir.file("typo.json"), R"({"levels": [{"ratio": 0.5}], "max_dept": 3})");
    write_text(dir.file("good.json"), R"({"levels": [{"ratio": 0.5}]})");
    write_text(dir.file("octree.json"), R"({"method": "octree", "levels": [{"ratio": 0.5}, {"error": 0.01}]})");
    write_text(dir.file("a_file"), "x");
    const fs::path out = dir.path() / "out";

    CliRun r = run_cli("pack " + input + " --preset " + quoted(dir.file("typo.json")) + " -o " + quoted(out.string()));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("lodforge: error: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("typo.json"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("max_dept"), std::string::npos) << r.out;

    r = run_cli("pack " + input + " --preset " + quoted(dir.file("nothere.json")) + " -o " + quoted(out.string()));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("nothere.json"), std::string::npos) << r.out;

    r = run_cli("pack " + quoted(dir.file("missing.obj")) + " --preset " + quoted(dir.file("good.json")) + " -o " +
                quoted(out.string()));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("missing.obj"), std::string::npos) << r.out;

    r = run_cli("pack " + input + " --preset " + quoted(dir.file("good.json")) + " -o " + quoted(dir.file("a_file/pack")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("a_file"), std::string::npos) << r.out;

    r = run_cli("pack " + input + " --preset " + quoted(dir.file("octree.json")) + " -o " + quoted(out.string()));
    EXPECT_EQ(r.exit_code, 1) << r.out;  // the octree's levels are chosen by triangle count
    EXPECT_NE(r.out.find("octree"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("levels[1]"), std::string::npos) << r.out;

    r = run_cli("pack " + input + " -o " + quoted(out.string()) + " --method bogus");  // a usage error
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.exit_code, 1);

    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir.path())) left.push_back(e.path().filename().string());
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"a_file", "good.json", "octree.json", "typo.json"}));
}

}  // namespace

namespace {

// `pack --levels auto` with the switch flags: the flags reach pack.json's switch block, every level's
// switch points are printed and written, the chosen levels halve, and `lod --levels auto` picks the same.
TEST(CliPack, AutoLevelsAndSwitchFlags) {
    ScratchDir dir("cli-pack-auto");
    const std::string input = quoted(shared_data("tex-duck/glTF_Binary/Duck.glb"));
    CliRun r = run_cli("pack " + input + " -o " + quoted(dir.file("duck")) +
                       " --levels auto --switch-pixels 2 --switch-screen 1280x720 --switch-fov 45"
                       " --switch-hysteresis 0.2 --min-screen-pixels 24");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("automatic levels"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("takes over at distance"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(test::read_bytes(dir.file("duck/pack.json")));
    EXPECT_EQ(j["switch"]["pixels"], 2.0);
    EXPECT_EQ(j["switch"]["screen"], nlohmann::json::array({1280, 720}));
    EXPECT_EQ(j["switch"]["fov_deg"], 45.0);
    EXPECT_EQ(j["switch"]["hysteresis"], 0.2);
    EXPECT_EQ(j["screen_reference"]["width"], 1280);
    EXPECT_EQ(j["preset"]["levels"], "auto");
    EXPECT_EQ(j["preset"]["min_screen_pixels"], 24.0);
    const auto& levels = j["levels"];
    ASSERT_GE(levels.size(), 2u);
    for (std::size_t k = 1; k < levels.size(); ++k) {
        EXPECT_LE(2 * levels[k]["triangles"].get<std::size_t>(), levels[k - 1]["triangles"].get<std::size_t>());
        const auto& s = levels[k]["switch"];
        const auto& before = levels[k - 1]["switch"];
        EXPECT_EQ(s["godot"]["visibility_range_begin"], before["godot"]["visibility_range_end"]);
        EXPECT_NEAR(s["godot"]["visibility_range_begin_margin"].get<double>(),
                    0.2 * s["godot"]["visibility_range_begin"].get<double>(), 1e-12);
        EXPECT_EQ(s["unreal_screen_size"], before["screen_size"]);
        // Level k takes over where its error is 2 px: a sphere of 2 / error pixels across, >= 24.
        EXPECT_NEAR(before["screen_size"].get<double>() * 720,
                    2 / levels[k]["error"]["hausdorff_relative"].get<double>(), 1e-6);
    }
    EXPECT_GE(levels[levels.size() - 2]["switch"]["screen_size"].get<double>() * 720, 24 * (1 - 1e-9));
    EXPECT_EQ(levels.back()["switch"]["godot"]["visibility_range_end"], 0.0);

    // `lod` chooses the same levels from the same preset.
    std::ofstream(dir.file("auto.json")) << R"({"levels": "auto", "min_screen_pixels": 24,
        "switch": {"pixels": 2, "screen": [1280, 720]}})";
    r = run_cli("lod " + input + " --preset " + quoted(dir.file("auto.json")) + " -o " + quoted(dir.file("lods")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto lods = nlohmann::json::parse(test::read_bytes(dir.file("lods/lods.json")));
    ASSERT_EQ(lods["levels"].size(), levels.size());
    for (std::size_t k = 0; k < levels.size(); ++k) EXPECT_EQ(lods["levels"][k]["triangles"], levels[k]["triangles"]);

    r = run_cli("pack " + input + " -o " + quoted(dir.file("bad")) + " --switch-screen 1280by720");
    EXPECT_EQ(r.exit_code, 2) << r.out;  // a usage error
    EXPECT_NE(r.out.find("--switch-screen"), std::string::npos) << r.out;
    r = run_cli("pack " + input + " -o " + quoted(dir.file("bad")) + " --levels auto --level-triangles 100");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    r = run_cli("pack " + input + " -o " + quoted(dir.file("bad")) + " --levels auto --method cluster");
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("collapse"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir.file("bad")));
}

}  // namespace
