// One options model: every command that makes levels takes `--preset NAME|FILE`, flags given on the
// command line override the preset's keys, and `pack IN -o DIR` works without a preset.
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;

namespace {

std::string spot() { return lodforge::test::shared_data("tex-spot/spot_triangulated.obj"); }  // 5856 triangles

nlohmann::json read_json(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

std::string write_preset(const lodforge::test::ScratchDir& dir, const std::string& name, const std::string& json) {
    const std::string path = dir.file(name);
    std::ofstream(path) << json;
    return path;
}

// The first number after `label` in `text` (-1 when absent).
long long number_after(const std::string& text, const std::string& label) {
    std::smatch m;
    if (!std::regex_search(text, m, std::regex(label + R"(\s*(\d+))"))) return -1;
    return std::stoll(m[1]);
}

}  // namespace

TEST(CliPreset, SimplifyTakesTheFirstLevelOfANamedOrFilePresetAndFlagsOverrideIt) {
    lodforge::test::ScratchDir dir("cli-preset-simplify");
    // mobile: first level ratio 0.25 of 5856 triangles.
    CliRun r = run_cli("simplify " + quoted(spot()) + " -o " + quoted(dir.file("a.ply")) + " --preset mobile");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(number_after(r.out, "target"), 1464) << r.out;
    const std::string file = write_preset(dir, "p.json", R"({"method": "cluster", "levels": [{"triangles": 1000}]})");
    r = run_cli("simplify " + quoted(spot()) + " -o " + quoted(dir.file("b.ply")) + " --preset " + quoted(file));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("mode: cluster"), std::string::npos) << r.out;
    EXPECT_EQ(number_after(r.out, "target"), 1000) << r.out;
    // --ratio and --mode override the preset's level and method.
    r = run_cli("simplify " + quoted(spot()) + " -o " + quoted(dir.file("c.ply")) + " --preset " + quoted(file) +
                " --ratio 0.5 --mode collapse");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("mode: collapse"), std::string::npos) << r.out;
    EXPECT_EQ(number_after(r.out, "target"), 2928) << r.out;
}

TEST(CliPreset, LodBuildsThePresetsLevelsWithAnyMethodAndFlagsOverrideThem) {
    lodforge::test::ScratchDir dir("cli-preset-lod");
    CliRun r = run_cli("lod " + quoted(spot()) + " -o " + quoted(dir.file("mobile")) + " --preset mobile --no-measure");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    nlohmann::json j = read_json(dir.file("mobile/lods.json"));
    ASSERT_EQ(j["levels"].size(), 4u);  // the input and mobile's three levels
    EXPECT_EQ(j["levels"][1]["target_triangles"], 1464);
    EXPECT_EQ(j["levels"][3]["target_triangles"], 117);
    EXPECT_EQ(j["placement"], "optimal");              // the collapse chain, each level its own vertices
    EXPECT_FALSE(j["levels"][1].contains("shared"));

    // --placement half-edge: the levels index one shared vertex buffer, and lods.json gives the ranges.
    r = run_cli("lod " + quoted(spot()) + " -o " + quoted(dir.file("half-edge")) +
                " --preset mobile --placement half-edge --no-measure");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    j = read_json(dir.file("half-edge/lods.json"));
    EXPECT_EQ(j["placement"], "half-edge");
    ASSERT_EQ(j["levels"].size(), 4u);
    EXPECT_EQ(j["levels"][3]["shared"]["index_count"].get<int>(), 3 * j["levels"][3]["triangles"].get<int>());
    EXPECT_GT(j["shared_vertices"].get<int>(), 0);
    EXPECT_EQ(run_cli("lod " + quoted(spot()) + " -o " + quoted(dir.file("bad")) + " --preset mobile --placement middle")
                  .exit_code,
              2);

    const std::string file =
        write_preset(dir, "p.json", R"({"method": "cluster", "levels": [{"ratio": 0.5}, {"ratio": 0.1}]})");
    r = run_cli("lod " + quoted(spot()) + " -o " + quoted(dir.file("cluster")) + " --preset " + quoted(file) +
                " --no-measure");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    j = read_json(dir.file("cluster/lods.json"));
    EXPECT_EQ(j["method"], "cluster");
    ASSERT_EQ(j["levels"].size(), 3u);
    EXPECT_FALSE(j["levels"][1].contains("shared"));
    EXPECT_LT(j["levels"][2]["triangles"].get<int>(), j["levels"][1]["triangles"].get<int>());

    r = run_cli("lod " + quoted(spot()) + " -o " + quoted(dir.file("override")) + " --preset mobile --levels 0.5 --no-measure");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    j = read_json(dir.file("override/lods.json"));
    ASSERT_EQ(j["levels"].size(), 2u);
    EXPECT_EQ(j["levels"][1]["target_triangles"], 2928);
}

TEST(CliPreset, StripsTakesJoinsAndCoarsestLevelFromThePreset) {
    lodforge::test::ScratchDir dir("cli-preset-strips");
    const auto info = [&](const std::string& file) {
        const CliRun r = run_cli("strips info --json " + quoted(file), false);
        EXPECT_EQ(r.exit_code, 0) << r.out;
        return nlohmann::json::parse(r.out);
    };
    CliRun r = run_cli("strips " + quoted(spot()) + " -o " + quoted(dir.file("m.lodstrips")) + " --preset mobile");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    // mobile's coarsest level: 2 % of the triangles (the default --coarsest is 1 %).
    nlohmann::json j = info(dir.file("m.lodstrips"));
    EXPECT_LE(j["triangles"]["coarsest"].get<int>(), 117);
    EXPECT_GT(j["triangles"]["coarsest"].get<int>(), 58);

    const std::string file = write_preset(
        dir, "p.json", R"({"method": "lodstrips", "levels": [{"triangles": 800}], "strips": {"primitive_restart": false}})");
    r = run_cli("strips " + quoted(spot()) + " -o " + quoted(dir.file("f.lodstrips")) + " --preset " + quoted(file));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    j = info(dir.file("f.lodstrips"));
    EXPECT_EQ(j["join"], "degenerate");
    EXPECT_LE(j["triangles"]["coarsest"].get<int>(), 800);
    EXPECT_GT(j["triangles"]["coarsest"].get<int>(), 400);

    r = run_cli("strips " + quoted(spot()) + " -o " + quoted(dir.file("o.lodstrips")) + " --preset " + quoted(file) +
                " --restart --coarsest 0.5");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    j = info(dir.file("o.lodstrips"));
    EXPECT_EQ(j["join"], "restart");
    EXPECT_GT(j["triangles"]["coarsest"].get<int>(), 2000);
}

TEST(CliPreset, OctreeBuildTakesTheOctreeKeysAndFlagsOverrideThem) {
    lodforge::test::ScratchDir dir("cli-preset-octree");
    const std::string ply = dir.file("spot.ply");
    ASSERT_EQ(run_cli("convert " + quoted(spot()) + " " + quoted(ply)).exit_code, 0);
    const std::string file = write_preset(
        dir, "p.json", R"({"method": "octree", "octree": {"max_triangles_per_node": 300, "max_depth": 2}})");
    CliRun r = run_cli("octree build " + quoted(ply) + " -o " + quoted(dir.file("a.lfo")) + " --preset " + quoted(file));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(number_after(r.out, "depth reached"), 2) << r.out;
    r = run_cli("octree build " + quoted(ply) + " -o " + quoted(dir.file("b.lfo")) + " --preset " + quoted(file) +
                " --max-depth 1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(number_after(r.out, "depth reached"), 1) << r.out;
    // The shipped presets keep the octree's defaults (20000 triangles per node): one node for Spot.
    r = run_cli("octree build " + quoted(ply) + " -o " + quoted(dir.file("c.lfo")) + " --preset console");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(number_after(r.out, "depth reached"), 0) << r.out;
}

TEST(CliPreset, McoctreeBuildTakesTheResolutionAndTheFlagOverridesIt) {
    lodforge::test::ScratchDir dir("cli-preset-mco");
    const std::string file = write_preset(dir, "p.json", R"({"method": "mcoctree", "mcoctree": {"resolution": 12}})");
    CliRun r = run_cli("mcoctree build " + quoted(spot()) + " -o " + quoted(dir.file("a.mco")) + " --preset " + quoted(file));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const long long coarse = number_after(r.out, "points ->");
    r = run_cli("mcoctree build " + quoted(spot()) + " -o " + quoted(dir.file("b.mco")) + " --preset " + quoted(file) +
                " --resolution 24");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const long long fine = number_after(r.out, "points ->");
    EXPECT_GT(coarse, 0) << r.out;
    EXPECT_GT(fine, 2 * coarse) << r.out;  // leaf cubes grow with the resolution
    r = run_cli("mcoctree build " + quoted(spot()) + " -o " + quoted(dir.file("c.mco")) + " --preset web --resolution 12");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(number_after(r.out, "points ->"), coarse) << r.out;
}

TEST(CliPreset, PackWorksWithoutAPresetWithANamedOneAndWithOverrides) {
    lodforge::test::ScratchDir dir("cli-preset-pack");
    CliRun r = run_cli("pack " + quoted(spot()) + " -o " + quoted(dir.file("default")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    nlohmann::json j = read_json(dir.file("default/pack.json"));
    EXPECT_EQ(j["preset"]["name"], "default");
    EXPECT_EQ(j["levels"].size(), 5u);  // the studio's default: four levels

    r = run_cli("pack " + quoted(spot()) + " -o " + quoted(dir.file("web")) + " --preset web");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    j = read_json(dir.file("web/pack.json"));
    EXPECT_EQ(j["preset"]["name"], "web");
    EXPECT_EQ(j["levels"].size(), 3u);

    r = run_cli("pack " + quoted(spot()) + " -o " + quoted(dir.file("over")) +
                " --preset web --method cluster --levels 0.5 --weights normal=0.5");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    j = read_json(dir.file("over/pack.json"));
    EXPECT_EQ(j["method"], "cluster");
    EXPECT_EQ(j["levels"].size(), 2u);
    EXPECT_FLOAT_EQ(j["preset"]["weights"]["normal"].get<float>(), 0.5f);
    EXPECT_FLOAT_EQ(j["preset"]["weights"]["uv"].get<float>(), 0.2f);  // web's key, not overridden
}

TEST(CliPreset, UnknownNamesAndMissingFilesAreClearErrors) {
    lodforge::test::ScratchDir dir("cli-preset-bad");
    CliRun r = run_cli("pack " + quoted(spot()) + " -o " + quoted(dir.file("x")) + " --preset mobil");
    EXPECT_EQ(r.exit_code, 2) << r.out;  // a usage error
    EXPECT_NE(r.out.find("'mobil' is not a shipped preset"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("console, mobile, scan-archive, web"), std::string::npos) << r.out;
    r = run_cli("lod " + quoted(spot()) + " -o " + quoted(dir.file("y")) + " --preset " + quoted(dir.file("none.json")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("none.json"), std::string::npos) << r.out;
    // A preset whose method makes no single mesh is refused by simplify unless --mode says which.
    const std::string file = write_preset(dir, "o.json", R"({"method": "octree"})");
    r = run_cli("simplify " + quoted(spot()) + " -o " + quoted(dir.file("z.ply")) + " --preset " + quoted(file));
    EXPECT_EQ(r.exit_code, 2) << r.out;  // a usage error
    EXPECT_NE(r.out.find("makes no single mesh"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("x")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("y")));
}
