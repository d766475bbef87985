// `lodforge morph build | extract | info` run as users run them.
#include "lodforge/io/mesh_io.h"

#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace {

using lodforge::test::quoted;
using lodforge::test::run_cli;

using lodforge::test::contains;

std::string horse() { return lodforge::test::shared_data("seq-horse-gallop"); }
std::string sphere() { return lodforge::test::shared_data("morph-animated-morph-sphere/AnimatedMorphSphere.gltf"); }

}  // namespace

TEST(CliMorph, BuildInfoExtractRoundTrip) {
    lodforge::test::ScratchDir dir("cli-morph");
    const std::string out = dir.file("h.lfmorph");
    auto r = run_cli("morph build " + quoted(horse()) + " -o " + quoted(out) + " --frames 4 --levels 0.5,0.1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "4 frames")) << r.out;
    r = run_cli("morph info " + quoted(out) + " --json", false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["frames"], 4);
    EXPECT_EQ(j["vertices"], 8431);
    EXPECT_EQ(j["order"], "single");
    EXPECT_EQ(j["normals"], "computed");
    ASSERT_EQ(j["levels"].size(), 2u);
    const std::size_t coarse = j["levels"][1]["triangles"];
    EXPECT_LE(coarse, 1685u);
    r = run_cli("morph extract " + quoted(out) + " --t 0.5 --lod 0 -o " + quoted(dir.file("p.ply")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const lodforge::Mesh m = lodforge::read_mesh(dir.file("p.ply"));
    EXPECT_EQ(m.triangle_count(), coarse);
    EXPECT_TRUE(m.has_normals());
    r = run_cli("morph extract " + quoted(out) + " --t 1 --lod 1 -o " + quoted(dir.file("full.ply")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(lodforge::read_mesh(dir.file("full.ply")).triangle_count(), 16843u);
    r = run_cli("morph info " + quoted(out));
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_TRUE(contains(r.out, "order: single")) << r.out;
}

TEST(CliMorph, GltfPerFrameOrderAndFloatEncoding) {
    lodforge::test::ScratchDir dir("cli-morph-gltf");
    const std::string out = dir.file("s.lfmorph");
    auto r = run_cli("morph build " + quoted(sphere()) + " -o " + quoted(out) +
                     " --frames 5 --order per-frame --encoding float --close-seams --levels 0.5");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    r = run_cli("morph info " + quoted(out) + " --json", false);
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["order"], "per-frame");
    EXPECT_EQ(j["sequences"], 5);
    EXPECT_EQ(j["encoding"], "float");
    EXPECT_EQ(j["normals"], "stored");
}

TEST(CliMorph, ErrorsNameTheFileAndExitOne) {
    lodforge::test::ScratchDir dir("cli-morph-err");
    // Case (b) with a missing landmark file names it (the rest of case (b): tests/morph/supermesh_test.cpp).
    auto r = run_cli("morph build " + quoted(sphere()) + " " + quoted(sphere()) + " --landmarks l.json -o " +
                     quoted(dir.file("x.lfmorph")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "lodforge: error: l.json")) << r.out;
    r = run_cli("morph build " + quoted(dir.file("none")) + " -o " + quoted(dir.file("x.lfmorph")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "lodforge: error: " + dir.file("none"))) << r.out;
    r = run_cli("morph build " + quoted(horse()) + " -o " + quoted(dir.file("x.lfmorph")) + " --order best");
    EXPECT_EQ(r.exit_code, 2);  // an option value out of range: a usage error
    EXPECT_TRUE(contains(r.out, "--order")) << r.out;
    r = run_cli("morph build " + quoted(horse()) + " -o " + quoted(dir.file("x.lfmorph")) + " --levels 0.1,0.5");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.lfmorph")));
    r = run_cli("morph info " + quoted(horse() + "/0001.obj"));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "magic")) << r.out;
    r = run_cli("morph extract " + quoted(dir.file("none.lfmorph")) + " --t 0.5 --lod 0.5 -o " + quoted(dir.file("p.ply")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(run_cli("morph extract x --t 2 --lod 0.5 -o y.ply").exit_code, 0);
    EXPECT_EQ(run_cli("morph --help").exit_code, 0);
    EXPECT_EQ(run_cli("morph build --help").exit_code, 0);
}

TEST(CliMorph, BuildWithGltfWritesTheGlbAndTheMorphStripsNextToIt) {
    lodforge::test::ScratchDir dir("cli-morph-export");
    const std::string glb = dir.file("sphere.glb");
    auto r = run_cli("morph build " + quoted(sphere()) + " -o " + quoted(dir.file("s.lfmorph")) +
                     " --frames 4 --close-seams --levels 0.5,0.1 --gltf " + quoted(glb));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "3 levels, 3 morph targets each, animated")) << r.out;
    EXPECT_TRUE(std::filesystem::exists(dir.file("sphere.lfmstrips")));
    const auto v = lodforge::test::run_command(std::string(LODFORGE_GLTF_VALIDATE) + " " + quoted(glb) + " 2>&1");
    EXPECT_EQ(v.exit_code, 0) << v.out;
    // quantised targets (KHR_mesh_quantization, required) by default; float32 with --gltf-float
    auto file_text = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    EXPECT_TRUE(contains(file_text(glb), "\"extensionsRequired\":[\"KHR_mesh_quantization\"]"));
    const std::string float_glb = dir.file("sphere-float.glb");
    r = run_cli("morph build " + quoted(sphere()) + " -o " + quoted(dir.file("sf.lfmorph")) +
                " --frames 4 --close-seams --levels 0.5,0.1 --gltf-float --gltf " + quoted(float_glb));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_FALSE(contains(file_text(float_glb), "KHR_mesh_quantization"));
    EXPECT_GT(std::filesystem::file_size(float_glb), std::filesystem::file_size(glb));
    // --strips alone, and the per-frame order refused before anything is written
    r = run_cli("morph build " + quoted(horse()) + " -o " + quoted(dir.file("h.lfmorph")) + " --frames 3 --levels 0.5 --strips " +
                quoted(dir.file("h.lfmstrips")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(std::filesystem::exists(dir.file("h.lfmstrips")));
    r = run_cli("morph build " + quoted(sphere()) + " -o " + quoted(dir.file("p.lfmorph")) +
                " --frames 3 --close-seams --levels 0.5 --order per-frame --gltf " + quoted(dir.file("p.glb")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "one collapse order")) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("p.lfmorph")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("p.glb")));
    // a glb that cannot be written: exit 1 naming it, and neither the .lfmorph nor the strips are left
    const std::string nowhere = dir.file("missing-dir/x.glb");
    r = run_cli("morph build " + quoted(sphere()) + " -o " + quoted(dir.file("q.lfmorph")) + " --frames 3 --close-seams " +
                "--levels 0.5 --gltf " + quoted(nowhere) + " --strips " + quoted(dir.file("q.lfmstrips")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, nowhere)) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("q.lfmorph")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("q.lfmstrips")));
}

// `morph extract` from the strips file (the runtime's set_frame + go_to_lod) writes the same triangles as
// from the .lfmorph file (extract_morph), at several times and LOD factors.
namespace {

// Triangles as position triples, rotated so the smallest corner comes first (winding kept), sorted.
std::vector<std::array<float, 9>> position_triangles(const lodforge::Mesh& m) {
    std::vector<std::array<float, 9>> out;
    for (std::size_t f = 0; f < m.triangle_count(); ++f) {
        std::array<std::array<float, 3>, 3> c;
        for (int k = 0; k < 3; ++k) {
            const lodforge::Vec3f p = m.positions[m.indices[3 * f + std::size_t(k)]];
            c[std::size_t(k)] = {p.x, p.y, p.z};
        }
        std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
        out.push_back({c[0][0], c[0][1], c[0][2], c[1][0], c[1][1], c[1][2], c[2][0], c[2][1], c[2][2]});
    }
    std::sort(out.begin(), out.end());
    return out;
}

// Builds the horse (3 frames) with `order` and --strips, then checks `morph extract` of the .lfmstrips
// against `morph extract` of the .lfmorph, triangle for triangle in space, at each of `cases`. Returns
// the build's output.
std::string build_and_compare_extracts(const lodforge::test::ScratchDir& dir, const std::string& order,
                                       std::initializer_list<const char*> cases) {
    const std::string lfm = dir.file("h.lfmorph"), strips = dir.file("h.lfmstrips");
    const auto built = run_cli("morph build " + quoted(horse()) + " -o " + quoted(lfm) +
                               " --frames 3 --levels 0.5,0.1 --encoding float --order " + order + " --strips " + quoted(strips));
    EXPECT_EQ(built.exit_code, 0) << built.out;
    for (const char* args : cases) {
        auto r = run_cli("morph extract " + quoted(lfm) + " " + args + " -o " + quoted(dir.file("a.ply")));
        EXPECT_EQ(r.exit_code, 0) << r.out;
        r = run_cli("morph extract " + quoted(strips) + " " + args + " -o " + quoted(dir.file("b.ply")));
        EXPECT_EQ(r.exit_code, 0) << r.out;
        const auto a = position_triangles(lodforge::read_mesh(dir.file("a.ply")));
        EXPECT_GT(a.size(), 100u);
        EXPECT_EQ(a, position_triangles(lodforge::read_mesh(dir.file("b.ply")))) << args;
    }
    return built.out;
}

}  // namespace

TEST(CliMorph, PerFrameStripsExtractEqualsTheMorphFilesPerFrameExtract) {
    lodforge::test::ScratchDir dir("cli-morph-strips-pf");
    const std::string out =
        build_and_compare_extracts(dir, "per-frame", {"--t 0 --lod 1", "--t 0.4 --lod 0.3", "--t 0.8 --lod 0.6", "--t 1 --lod 0"});
    EXPECT_TRUE(contains(out, "3 change set(s)")) << out;
    const auto r = run_cli("morph info " + quoted(dir.file("h.lfmstrips")) + " --json", false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["version"], 2);
    ASSERT_EQ(j["change_sets"].size(), 3u);
    EXPECT_EQ(j["change_sets"][2]["frame"], 2);
    EXPECT_GT(j["change_sets"][2]["collapses"].get<int>(), 1000);
}

TEST(CliMorph, ExtractFromTheStripsFileEqualsExtractFromTheMorphFile) {
    lodforge::test::ScratchDir dir("cli-morph-strips");
    const std::string strips = dir.file("h.lfmstrips");
    build_and_compare_extracts(dir, "single", {"--t 0 --lod 1", "--t 0.4 --lod 0.3", "--t 1 --lod 0"});
    auto r = run_cli("morph info " + quoted(strips) + " --json", false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["format"], "lfmstrips");
    EXPECT_EQ(j["frames"], 3);
    EXPECT_EQ(j["encoding"], "float");
    EXPECT_EQ(j["triangles"], 16843);
    EXPECT_LE(j["coarsest_triangles"].get<int>(), 1685);
    // a damaged strips file: exit 1 naming it
    std::filesystem::resize_file(strips, std::filesystem::file_size(strips) - 5);
    r = run_cli("morph extract " + quoted(strips) + " --t 0.5 --lod 0.5 -o " + quoted(dir.file("c.ply")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "lodforge: error: " + strips)) << r.out;
}
