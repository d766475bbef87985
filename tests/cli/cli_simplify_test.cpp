// `lodforge simplify`, `lod` and `compare` run as users run them: the real executable through popen.
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/ply.h"
#include "lodforge/simplify/simplify.h"

#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <tuple>

namespace {

using lodforge::test::CliRun;
using lodforge::test::contains;
using lodforge::test::quoted;
using lodforge::test::run_cli;

CliRun run(const std::string& args, bool merge_stderr = true) { return run_cli(args, merge_stderr); }
std::string q(const std::string& s) { return quoted(s); }

std::string bunny() { return lodforge::test::shared_data("scan-bunny/bun_zipper.ply"); }

}  // namespace

TEST(CliSimplify, HelpListsTheNewCommands) {
    const CliRun r = run("--help");
    EXPECT_EQ(r.exit_code, 0);
    for (const char* cmd : {"simplify", "lod", "compare"}) EXPECT_TRUE(contains(r.out, cmd)) << cmd;
    EXPECT_EQ(run("simplify --help").exit_code, 0);
    EXPECT_EQ(run("lod --help").exit_code, 0);
    EXPECT_EQ(run("compare --help").exit_code, 0);
}

TEST(CliSimplify, RatioTargetIsReachedAndReported) {
    lodforge::test::ScratchDir dir("cli-simplify");
    const std::string out = dir.file("bunny10.ply");
    const CliRun r = run("simplify " + q(bunny()) + " -o " + q(out) + " --ratio 0.1 --weights normal=0.1,color=0.2");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "-> 6944 triangles") || contains(r.out, "-> 6945 triangles")) << r.out;
    EXPECT_TRUE(contains(r.out, "stop: target reached")) << r.out;
    EXPECT_TRUE(contains(r.out, "of the diagonal")) << r.out;
    const lodforge::Mesh m = lodforge::read_mesh(out);
    EXPECT_NEAR(double(m.triangle_count()), 6945.0, 1.0);
}

TEST(CliSimplify, TriangleCountAndErrorTargetsAndBorderLock) {
    lodforge::test::ScratchDir dir("cli-simplify-targets");
    const std::string spot = lodforge::test::sample("spot/spot_triangulated.obj");
    CliRun r = run("simplify " + q(spot) + " -o " + q(dir.file("spot.obj")) + " --triangles 1000 --lock-border");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(lodforge::read_mesh(dir.file("spot.obj")).triangle_count(), 1000u);
    r = run("simplify " + q(bunny()) + " -o " + q(dir.file("err.ply")) + " --max-error 0.002");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "stop: error limit")) << r.out;
    EXPECT_LT(lodforge::read_mesh(dir.file("err.ply")).triangle_count(), 69451u);
}

TEST(CliSimplify, AreaAndHeightWeightsReachTheLibrary) {
    // --area-weight sqrt --height-weight 0.3 (half-edge placement) give what simplify() gives with those
    // parameters, and not the default result.
    lodforge::test::ScratchDir dir("cli-simplify-order");
    const std::string opt = dir.file("opt.ply"), plain = dir.file("plain.ply");
    CliRun r = run("simplify " + q(bunny()) + " -o " + q(opt) + " --ratio 0.02 --area-weight sqrt --height-weight 0.3 --placement half-edge");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    r = run("simplify " + q(bunny()) + " -o " + q(plain) + " --ratio 0.02");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    lodforge::SimplifyParams p;
    p.target_ratio = 0.02f;
    p.area_weight = lodforge::SimplifyParams::AreaWeight::sqrt_area;
    p.height_weight = 0.3f;
    const lodforge::SimplifyResult lib = lodforge::simplify(lodforge::read_mesh(bunny()), p);
    const lodforge::Mesh a = lodforge::read_mesh(opt), b = lodforge::read_mesh(plain);
    EXPECT_EQ(a.positions, lib.mesh.positions);
    EXPECT_EQ(a.indices, lib.mesh.indices);
    EXPECT_NE(a.positions, b.positions);
}
TEST(CliSimplify, PlacementReachesTheLibrary) {
    // --placement optimal (the default) gives what simplify() gives with Placement::optimal: vertices
    // that are not input vertices; half-edge keeps input positions.
    lodforge::test::ScratchDir dir("cli-simplify-placement");
    const std::string opt = dir.file("opt.ply"), half = dir.file("half.ply");
    CliRun r = run("simplify " + q(bunny()) + " -o " + q(opt) + " --ratio 0.05");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "placement: optimal")) << r.out;
    r = run("simplify " + q(bunny()) + " -o " + q(half) + " --ratio 0.05 --placement half-edge");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    lodforge::SimplifyParams p;
    p.target_ratio = 0.05f;
    p.placement = lodforge::Placement::optimal;
    const lodforge::Mesh in = lodforge::read_mesh(bunny());
    const lodforge::SimplifyResult lib = lodforge::simplify(in, p);
    const lodforge::Mesh a = lodforge::read_mesh(opt), b = lodforge::read_mesh(half);
    EXPECT_EQ(a.positions, lib.mesh.positions);
    EXPECT_EQ(a.indices, lib.mesh.indices);
    const std::set<std::tuple<float, float, float>> input = [&] {
        std::set<std::tuple<float, float, float>> s;
        for (const lodforge::Vec3f& x : in.positions) s.emplace(x.x, x.y, x.z);
        return s;
    }();
    auto moved = [&](const lodforge::Mesh& m) {
        std::size_t n = 0;
        for (const lodforge::Vec3f& x : m.positions) n += !input.count({x.x, x.y, x.z});
        return n;
    };
    EXPECT_GT(moved(a), a.positions.size() / 2);
    EXPECT_EQ(moved(b), 0u);
}

TEST(CliSimplify, PerSetUvWeightsReachTheLibrary) {
    // Spot with a second texcoord set (the first one mirrored and tiled): --weights uv1=W weighs set 1
    // alone; set 0 keeps the plain uv weight.
    lodforge::test::ScratchDir dir("cli-simplify-uvsets");
    lodforge::Mesh m = lodforge::read_mesh(lodforge::test::sample("spot/spot_triangulated.obj"));
    ASSERT_EQ(m.texcoords.size(), 1u);
    std::vector<lodforge::Vec2f> second = m.texcoords[0];
    for (lodforge::Vec2f& t : second) t = {3.f * (1.f - t.x), 3.f * t.y};
    m.texcoords.push_back(second);
    const std::string two = dir.file("two-sets.glb");
    lodforge::write_mesh(m, two);
    const lodforge::Mesh in = lodforge::read_mesh(two);
    ASSERT_EQ(in.texcoords.size(), 2u);

    const std::string heavy = dir.file("heavy.glb"), plain = dir.file("plain.glb"), lib_out = dir.file("lib.glb");
    CliRun r = run("simplify " + q(two) + " -o " + q(heavy) + " --ratio 0.2 --weights uv1=3,uv=0.2");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    r = run("simplify " + q(two) + " -o " + q(plain) + " --ratio 0.2 --weights uv=0.2");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    lodforge::SimplifyParams p;
    p.target_ratio = 0.2f;
    p.weights.texcoord = 0.2f;
    p.weights.texcoord_sets = {0.2f, 3.f};
    p.placement = lodforge::Placement::optimal;  // the command's default
    lodforge::write_mesh(lodforge::simplify(in, p).mesh, lib_out);
    const lodforge::Mesh a = lodforge::read_mesh(heavy), b = lodforge::read_mesh(plain), lib = lodforge::read_mesh(lib_out);
    EXPECT_EQ(a.positions, lib.positions);
    EXPECT_EQ(a.indices, lib.indices);
    EXPECT_NE(a.positions, b.positions);

    r = run("simplify " + q(two) + " -o " + q(dir.file("bad.glb")) + " --ratio 0.2 --weights uvx=1");
    EXPECT_EQ(r.exit_code, 2);  // an option value the command refuses: a usage error
    EXPECT_TRUE(contains(r.out, "unknown attribute 'uvx'")) << r.out;
}

TEST(CliSimplify, ClusterModeOnTheColouredScanKeepsColours) {
    lodforge::test::ScratchDir dir("cli-cluster");
    const std::string frag = lodforge::test::shared_data("color-open3d-frag115/frag_115.ply");
    const std::string out = dir.file("frag.ply");
    CliRun r = run("simplify " + q(frag) + " -o " + q(out) + " --ratio 0.1 --mode cluster");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "mode: cluster")) << r.out;
    const lodforge::Mesh m = lodforge::read_mesh(out);
    EXPECT_TRUE(m.has_colors());
    EXPECT_NEAR(double(m.triangle_count()), 12723.0, 0.05 * 12723.0);
    r = run("compare --json " + q(frag) + " " + q(out), false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("color_rms"));
    EXPECT_LT(j["color_rms"].get<double>(), 10.0);
}

TEST(CliSimplify, BadTargetsExitNonZeroWithAMessage) {
    lodforge::test::ScratchDir dir("cli-simplify-bad");
    const std::string in = q(bunny()) + " -o " + q(dir.file("x.ply"));
    struct Case {
        std::string args, message;
    };
    const Case cases[] = {
        {"", "exactly one of --ratio, --triangles and --max-error"},
        {" --ratio 0.5 --triangles 100", "exactly one of"},
        {" --ratio 1.5", "--ratio must be in (0, 1]"},
        {" --ratio 0", "--ratio must be in (0, 1]"},
        {" --triangles 0", "--triangles must be at least 1"},
        {" --max-error -1", "--max-error must be > 0"},
        {" --max-error 0.01 --mode cluster", "--max-error needs --mode collapse"},
        {" --ratio 0.5 --mode cluster --lock-border", "--lock-border needs --mode collapse"},
        {" --ratio 0.5 --mode cluster --height-weight 0.1", "--placement need --mode collapse"},
        {" --ratio 0.5 --mode cluster --placement optimal", "--placement need --mode collapse"},
        {" --ratio 0.5 --placement midpoint", "midpoint"},
        {" --ratio 0.5 --height-weight -1 --placement half-edge", "--height-weight must be finite and >= 0"},
        {" --ratio 0.5 --height-weight 0.3", "--height-weight needs --placement half-edge"},
        {" --ratio 0.5 --weights normal", "expected name=value"},
        {" --ratio 0.5 --weights shininess=1", "unknown attribute 'shininess'"},
        {" --ratio 0.5 --weights color=-1", "must be >= 0"},
        {" --ratio 0.5 --mode voxel", "voxel"},
    };
    const CliRun stl = run("simplify " + q(bunny()) + " -o " + q(dir.file("x.stl")) + " --ratio 0.5");
    EXPECT_EQ(stl.exit_code, 1);
    EXPECT_TRUE(contains(stl.out, "the output must be .ply, .obj or .glb")) << stl.out;
    for (const Case& c : cases) {
        const CliRun r = run("simplify " + in + c.args);
        EXPECT_NE(r.exit_code, 0) << c.args;
        EXPECT_TRUE(contains(r.out, c.message)) << c.args << ": " << r.out;
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(CliLod, LodsJsonMatchesTheFilesWritten) {
    lodforge::test::ScratchDir dir("cli-lod");
    const std::string out = dir.file("bunny-lods");
    const CliRun r = run("lod " + q(bunny()) + " -o " + q(out) + " --levels 0.5,0.25,0.1,0.03 --samples 100000");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::ifstream in(out + "/lods.json");
    ASSERT_TRUE(in.good());
    const auto j = nlohmann::json::parse(in);
    ASSERT_EQ(j["levels"].size(), 5u);
    double last_mean = -1;
    std::size_t last_triangles = 69452;
    for (std::size_t i = 0; i < 5; ++i) {
        const auto& level = j["levels"][i];
        EXPECT_EQ(level["level"], i);
        const std::string file = level["file"];
        EXPECT_EQ(file, "lod" + std::to_string(i) + ".ply");
        const lodforge::Mesh m = lodforge::read_mesh(out + "/" + file);
        EXPECT_EQ(level["triangles"].get<std::size_t>(), m.triangle_count()) << i;
        EXPECT_EQ(level["wedges"].get<std::size_t>(), m.vertex_count()) << i;
        EXPECT_LT(m.triangle_count(), last_triangles);
        last_triangles = m.triangle_count();
        const auto& e = level["error"];
        for (const char* key : {"hausdorff", "hausdorff_relative", "mean", "mean_relative", "rms", "rms_relative",
                                "step", "accumulated_relative"})
            EXPECT_TRUE(e.contains(key)) << key;
        if (i > 0) {
            EXPECT_GT(e["mean"].get<double>(), last_mean) << i;
            EXPECT_EQ(level["stop_reason"], "target_reached");
            const double target = level["target_triangles"].get<double>();
            EXPECT_NEAR(double(m.triangle_count()), target, 0.01 * target + 1);
        }
        last_mean = e["mean"].get<double>();
        // Optimal placement (the default): every level has its own vertices, no shared-buffer ranges.
        EXPECT_FALSE(level.contains("shared")) << i;
    }
    EXPECT_EQ(j["placement"], "optimal");
    EXPECT_FALSE(j.contains("shared_vertices"));
    EXPECT_EQ(j["levels"][0]["triangles"], 69451);
}

TEST(CliLod, ObjLevelsByTriangleCount) {
    lodforge::test::ScratchDir dir("cli-lod-obj");
    const std::string spot = lodforge::test::sample("spot/spot_triangulated.obj");
    const CliRun r = run("lod " + q(spot) + " -o " + q(dir.path().string()) +
                         " --level-triangles 3000,1000,300 --format obj --no-measure");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::ifstream in(dir.file("lods.json"));
    const auto j = nlohmann::json::parse(in);
    ASSERT_EQ(j["levels"].size(), 4u);
    EXPECT_EQ(j["measured"], false);
    for (std::size_t i = 1; i < 4; ++i) {
        const lodforge::Mesh m = lodforge::read_mesh(dir.file(j["levels"][i]["file"].get<std::string>()));
        EXPECT_EQ(m.triangle_count(), j["levels"][i]["triangles"].get<std::size_t>());
        EXPECT_EQ(m.point_count(), j["levels"][i]["vertices"].get<std::size_t>());
        EXPECT_TRUE(m.has_texcoords());
        EXPECT_FALSE(j["levels"][i]["error"].contains("hausdorff"));
    }
    EXPECT_EQ(j["levels"][3]["triangles"], 300);
}

TEST(CliLod, BadLevelsExitNonZeroWithAMessage) {
    lodforge::test::ScratchDir dir("cli-lod-bad");
    const std::string in = q(bunny()) + " -o " + q(dir.file("out"));
    struct Case {
        std::string args, message;
    };
    const Case cases[] = {
        {"", "give one of --levels, --level-triangles and --level-errors"},
        {" --levels 0.5,0.7", "not fewer than the previous level"},
        {" --levels 0.5,abc", "'abc' is not a number"},
        {" --levels 0.5,1.5", "outside (0, 1)"},
        {" --levels 1,0.5", "outside (0, 1)"},
        {" --levels 0.5 --level-triangles 100", "at most one of"},
        {" --level-triangles 100.5", "not a positive integer"},
        {" --level-errors 0.01,0.001", "larger than the previous level"},
        {" --levels 0.5 --format stl", "stl"},
    };
    for (const Case& c : cases) {
        const CliRun r = run("lod " + in + c.args);
        EXPECT_NE(r.exit_code, 0) << c.args;
        EXPECT_TRUE(contains(r.out, c.message)) << c.args << ": " << r.out;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("out/lods.json")));
}

TEST(CliCompare, JsonHasTheMetricsAndTheHeatmapHasColours) {
    lodforge::test::ScratchDir dir("cli-compare");
    const std::string simplified = dir.file("bunny-cluster.ply");
    ASSERT_EQ(run("simplify " + q(bunny()) + " -o " + q(simplified) + " --ratio 0.05 --mode cluster").exit_code, 0);
    const std::string heat = dir.file("heat.ply");
    const CliRun r = run("compare --json --samples 50000 --heatmap " + q(heat) + " " + q(bunny()) + " " + q(simplified), false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key : {"hausdorff", "mean", "rms", "hausdorff_relative", "mean_relative", "rms_relative", "diagonal"}) {
        ASSERT_TRUE(j.contains(key)) << key;
        EXPECT_GT(j[key].get<double>(), 0.0) << key;
    }
    EXPECT_NEAR(j["hausdorff_relative"].get<double>(), j["hausdorff"].get<double>() / j["diagonal"].get<double>(), 1e-9);
    EXPECT_GE(j["hausdorff"].get<double>(), j["rms"].get<double>());
    EXPECT_EQ(j["test_to_reference"]["samples"].get<std::size_t>() > 0, true);
    EXPECT_FALSE(j.contains("color_rms"));  // the bunny has no colours
    EXPECT_EQ(j["heatmap"]["file"], heat);

    const lodforge::Mesh m = lodforge::read_ply(heat);
    ASSERT_TRUE(m.has_colors());
    std::set<std::tuple<int, int, int>> distinct;
    for (const auto& c : m.colors) distinct.insert({int(std::lround(c.x * 255)), int(std::lround(c.y * 255)), int(std::lround(c.z * 255))});
    EXPECT_GT(distinct.size(), 2u);
    lodforge::PlyReader reader(heat);
    EXPECT_GE(reader.header().find_element("vertex")->find_property("quality"), 0);

    // On the reference: the field of a half-edge simplification (whose vertices lie on the input).
    const std::string collapsed = dir.file("bunny-collapse.ply");
    ASSERT_EQ(run("simplify " + q(bunny()) + " -o " + q(collapsed) + " --ratio 0.05 --placement half-edge").exit_code, 0);
    // On the test: a collapse's vertices lie on REF, but the field around them still shows the error.
    const std::string heat_test = dir.file("heat-test.ply");
    const CliRun c = run("compare --json --samples 50000 --heatmap " + q(heat_test) + " " + q(bunny()) + " " + q(collapsed), false);
    ASSERT_EQ(c.exit_code, 0) << c.out;
    const auto jc = nlohmann::json::parse(c.out);
    EXPECT_NEAR(jc["heatmap"]["max"].get<double>(), jc["hausdorff"].get<double>(), 1e-6 * jc["hausdorff"].get<double>());
    const lodforge::Mesh hm = lodforge::read_ply(heat_test);
    std::set<std::tuple<int, int, int>> shades;
    for (const auto& col : hm.colors) shades.insert({int(std::lround(col.x * 255)), int(std::lround(col.y * 255)), int(std::lround(col.z * 255))});
    EXPECT_GT(shades.size(), 20u);
    const std::string heat_ref = dir.file("heat-ref.ply");
    const CliRun t = run("compare --samples 50000 --heatmap-on reference --heatmap " + q(heat_ref) + " " + q(bunny()) + " " + q(collapsed));
    ASSERT_EQ(t.exit_code, 0) << t.out;
    EXPECT_TRUE(contains(t.out, "hausdorff:")) << t.out;
    EXPECT_EQ(lodforge::read_ply(heat_ref).triangle_count(), 69451u);
}

TEST(CliCompare, BadArgumentsExitNonZero) {
    lodforge::test::ScratchDir dir("cli-compare-bad");
    CliRun r = run("compare " + q(bunny()));
    EXPECT_NE(r.exit_code, 0);
    r = run("compare " + q(bunny()) + " " + q(dir.file("missing.ply")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "missing.ply")) << r.out;
    r = run("compare --heatmap " + q(dir.file("h.obj")) + " " + q(bunny()) + " " + q(bunny()));
    EXPECT_EQ(r.exit_code, 2);  // an option value the command refuses: a usage error
    EXPECT_TRUE(contains(r.out, "--heatmap writes PLY")) << r.out;
    r = run("compare --samples -5 " + q(bunny()) + " " + q(bunny()));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// A level that cannot be written (here: a directory in the way of lod2.ply) fails the whole run and
// leaves the target as it was: no earlier levels, no lods.json (all are staged and moved at the end).
TEST(CliLod, AFailedWriteLeavesNoPartialChain) {
    lodforge::test::ScratchDir dir("cli-lod-partial");
    const std::string out = dir.file("out");
    std::filesystem::create_directories(out + "/lod2.ply");
    const CliRun r = run("lod " + q(bunny()) + " -o " + q(out) + " --levels 0.5,0.25,0.1 --no-measure");
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_TRUE(contains(r.out, "lod2.ply")) << r.out;
    std::set<std::string> left;
    for (const auto& e : std::filesystem::directory_iterator(dir.path())) left.insert(e.path().filename().string());
    EXPECT_EQ(left, std::set<std::string>{"out"});  // no staging directory left beside it
    left.clear();
    for (const auto& e : std::filesystem::directory_iterator(out)) left.insert(e.path().filename().string());
    EXPECT_EQ(left, std::set<std::string>{"lod2.ply"});
    // Without the obstacle the same run writes the chain into the existing directory.
    std::filesystem::remove(out + "/lod2.ply");
    ASSERT_EQ(run("lod " + q(bunny()) + " -o " + q(out) + " --levels 0.5,0.25,0.1 --no-measure").exit_code, 0);
    for (const char* f : {"lod0.ply", "lod1.ply", "lod2.ply", "lod3.ply", "lods.json"})
        EXPECT_TRUE(std::filesystem::is_regular_file(out + "/" + f)) << f;
}

// A ratio that rounds to no triangle keeps one (the sweep found a single triangle written as an empty
// file, "target reached"), and dropped input faces are reported.
TEST(CliSimplify, TinyRatiosKeepATriangleAndDroppedFacesAreReported) {
    lodforge::test::ScratchDir dir("cli-simplify-tiny");
    {
        std::ofstream f(dir.file("tri.ply"));
        f << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n";
    }
    const CliRun r = run("simplify " + q(dir.file("tri.ply")) + " -o " + q(dir.file("out.ply")) + " --ratio 0.1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "2 -> 1 triangles (target 1)")) << r.out;
    EXPECT_TRUE(contains(r.out, "dropped: 1 input faces")) << r.out;
    EXPECT_EQ(lodforge::read_mesh(dir.file("out.ply")).triangle_count(), 1u);
}
