// `lodforge octree` as users run it, with the peak resident memory of the child process measured
// (wait4 → ru_maxrss), not assumed.
#include "lodforge/io/mesh_io.h"
#include "lodforge/octree/octree_store.h"

#include "octree_test_util.h"
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace lodforge {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;
using test::ScratchDir;
using test::shared_data;

using Measured = test::Waited;
pid_t spawn(const std::vector<std::string>& args) { return test::spawn_cli(args); }
Measured wait_measured(pid_t pid) { return test::wait_cli(pid); }

TEST(OctreeCli, PeakMemoryHonoursTheBudgetOnTheDragon) {
    ScratchDir dir("octree-cli-memory");
    const std::string input = shared_data("scan-dragon/dragon_vrip.ply");  // 871K triangles, ASCII
    // 4 MB forces the external 3-pass soup sort (the dragon's vertex table is 5 MB).
    for (int budget_mb : {4, 16, 64}) {
        SCOPED_TRACE(budget_mb);
        const std::string out = dir.file("dragon" + std::to_string(budget_mb) + ".lfo");
        const Measured m = wait_measured(spawn({"octree", "build", input, "-o", out, "--max-triangles", "4000",
                                                "--memory", std::to_string(budget_mb)}));
        ASSERT_EQ(m.exit_code, 0);
        EXPECT_GT(m.peak_kb, 0);
        EXPECT_LE(m.peak_kb, (budget_mb + 64) * 1024L) << "peak " << m.peak_kb / 1024 << " MB";
        OctreeStore store(out);
        EXPECT_EQ(store.header().input_triangles, 871414u);
    }
    // The budget changes how the work is done, not the result.
    auto bytes = [&](const std::string& name) {
        std::ifstream f(dir.file(name), std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(f)), {});
    };
    const std::string a16 = bytes("dragon16.lfo");
    EXPECT_GT(a16.size(), 1000u);
    EXPECT_TRUE(a16 == bytes("dragon64.lfo"));
    EXPECT_TRUE(a16 == bytes("dragon4.lfo"));
    // Cluster mode under the same budget.
    const Measured c = wait_measured(spawn({"octree", "build", input, "-o", dir.file("oocs.ply"), "--mode", "cluster",
                                            "--grid", "200", "--memory", "16"}));
    ASSERT_EQ(c.exit_code, 0);
    EXPECT_LE(c.peak_kb, (16 + 64) * 1024L);
    const Mesh oocs = read_mesh(dir.file("oocs.ply"));
    EXPECT_GT(oocs.triangle_count(), 50000u);
    EXPECT_LT(oocs.triangle_count(), 871414u / 3);
}

TEST(OctreeCli, BuildInfoAndExtract) {
    ScratchDir dir("octree-cli");
    const std::string input = shared_data("scan-dragon/dragon_vrip_res3.ply");
    const std::string asset = dir.file("d.lfo");
    const auto b = run_cli("octree build " + quoted(input) + " -o " + quoted(asset) + " --max-triangles 400 --max-depth 6");
    ASSERT_EQ(b.exit_code, 0) << b.out;
    EXPECT_NE(b.out.find("triangles per level: 47794"), std::string::npos) << b.out;

    const auto info = run_cli("octree info " + quoted(asset) + " --json", false);
    ASSERT_EQ(info.exit_code, 0) << info.out;
    const nlohmann::json j = nlohmann::json::parse(info.out);
    EXPECT_EQ(j["input_triangles"], 47794);
    EXPECT_LE(j["depth_reached"].get<int>(), 6);
    EXPECT_GT(j["leaves"].get<int>(), 47794 / 400);
    const auto levels = j["triangles_per_level"].get<std::vector<std::uint64_t>>();
    ASSERT_EQ(levels.size(), j["levels"].get<std::size_t>());
    EXPECT_EQ(levels[0], 47794u);
    const auto text = run_cli("octree info " + quoted(asset));
    EXPECT_EQ(text.exit_code, 0);
    EXPECT_NE(text.out.find("depth reached"), std::string::npos);
    // Each level's size against the level below, as the JSON counts give it.
    char ratio[64];
    std::snprintf(ratio, sizeof ratio, "level 2: %llu triangles (%.0f %% of level 1)", static_cast<unsigned long long>(levels[2]),
                  100.0 * static_cast<double>(levels[2]) / static_cast<double>(levels[1]));
    EXPECT_NE(text.out.find(ratio), std::string::npos) << text.out;

    const std::string l2 = dir.file("l2.ply");
    const auto e = run_cli("octree extract " + quoted(asset) + " --level 2 -o " + quoted(l2));
    ASSERT_EQ(e.exit_code, 0) << e.out;
    const Mesh m2 = read_mesh(l2);
    EXPECT_EQ(m2.triangle_count(), levels[2]);
    EXPECT_EQ(test::edge_counts(m2).border, 0u);

    // A view from the +Z side, close to the model: near nodes fine, far ones coarse, some culled.
    const std::string v = dir.file("view.ply");
    const auto ve = run_cli("octree extract " + quoted(asset) + " --screen-error 1 --camera -0.02,0.13,0.12,-0.02,0.13,0,40 -o " + quoted(v));
    ASSERT_EQ(ve.exit_code, 0) << ve.out;
    EXPECT_NE(ve.out.find("culled"), std::string::npos);
    const Mesh mv = read_mesh(v);
    EXPECT_GT(mv.triangle_count(), levels.back());
    EXPECT_LT(mv.triangle_count(), 47794u);

    // Usage and input errors.
    // An option value out of range is a usage error (2), like CLI11's own range checks.
    EXPECT_EQ(run_cli("octree extract " + quoted(asset) + " --level 99 -o " + quoted(dir.file("x.ply"))).exit_code, 2);
    EXPECT_NE(run_cli("octree extract " + quoted(asset) + " --screen-error 1 -o " + quoted(dir.file("x.ply"))).exit_code, 0);
    const auto bad_cam = run_cli("octree extract " + quoted(asset) + " --screen-error 1 --camera 1,2,3 -o " + quoted(dir.file("x.ply")));
    EXPECT_NE(bad_cam.exit_code, 0);
    EXPECT_NE(bad_cam.out.find("7 comma-separated"), std::string::npos) << bad_cam.out;
    EXPECT_FALSE(fs::exists(dir.file("x.ply")));
    const auto missing = run_cli("octree info " + quoted(dir.file("none.lfo")));
    EXPECT_EQ(missing.exit_code, 1);
    EXPECT_NE(missing.out.find("lodforge: error: "), std::string::npos);
    EXPECT_NE(run_cli("octree build " + quoted(input) + " -o " + quoted(dir.file("y.lfo")) + " --memory 2").exit_code, 0);
    const auto bad_ratio = run_cli("octree build " + quoted(input) + " -o " + quoted(dir.file("y.lfo")) + " --level-ratio 1.5");
    EXPECT_EQ(bad_ratio.exit_code, 2);
    EXPECT_NE(bad_ratio.out.find("--level-ratio"), std::string::npos) << bad_ratio.out;
    EXPECT_FALSE(fs::exists(dir.file("y.lfo")));
}

TEST(OctreeCli, TruncatedInputFailsCleanly) {
    ScratchDir dir("octree-cli-bad");
    const std::string cut = dir.file("cut.ply");
    {
        std::ifstream in(shared_data("color-open3d-frag115/frag_115.ply"), std::ios::binary);
        std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
        bytes.resize(bytes.size() - 5000);
        std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    const auto r = run_cli("octree build " + quoted(cut) + " -o " + quoted(dir.file("o.lfo")) + " --memory 4");
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("lodforge: error: " + cut), std::string::npos) << r.out;
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir.path())) files += e.path() != cut;
    EXPECT_EQ(files, 0u);
}

// SIGTERM (kill, CI timeouts) and SIGHUP (a closed terminal) clean up like Ctrl+C; they left up to
// 1.1 GB of temporary files before. The exit code is 128 + the signal, as a shell reports it.
TEST(OctreeCli, SignalMidBuildLeavesNoFiles) {
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
        SCOPED_TRACE(signal_number);
        ScratchDir dir("octree-cli-cancel");
        const pid_t pid = spawn({"octree", "build", shared_data("scan-dragon/dragon_vrip.ply"), "-o", dir.file("d.lfo"),
                                 "--max-triangles", "300", "--memory", "16"});
        // Interrupt once the build has started writing (its temporary directory exists).
        bool started = false;
        for (int i = 0; i < 2000 && !started; ++i) {
            for (const auto& e : fs::directory_iterator(dir.path())) started = started || e.is_directory();
            if (!started) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        ASSERT_TRUE(started);
        ::kill(pid, signal_number);
        const Measured m = wait_measured(pid);
        EXPECT_EQ(m.exit_code, 128 + signal_number);
        EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 0);
    }
}

// The streaming path read NaN normals, UVs and colours and 1e38 coordinates into an asset (exit 0)
// that `info` and `convert` refuse; it now makes the same checks.
TEST(OctreeCli, NonFiniteOrHugeValuesFailLikeInfoDoes) {
    ScratchDir dir("octree-cli-nan");
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string face = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    struct Case {
        const char* name;
        std::string text;
        const char* needle;
    };
    const Case cases[] = {
        {"normal.ply", header + "property float nx\nproperty float ny\nproperty float nz\n" + face +
                           "0 0 0 0 0 1\n1 0 0 nan 0 1\n0 1 0 0 0 1\n3 0 1 2\n", "vertex 1"},
        {"uv.ply", header + "property float u\nproperty float v\n" + face + "0 0 0 0 0\n1 0 0 0 0\n0 1 0 inf 0\n3 0 1 2\n",
         "vertex 2"},
        {"color.ply", header + "property float red\nproperty float green\nproperty float blue\n" + face +
                          "0 0 0 -inf 0 0\n1 0 0 0 0 0\n0 1 0 0 0 0\n3 0 1 2\n", "vertex 0"},
        {"huge.ply", header + face + "0 0 0\n1e38 0 0\n0 1e38 0\n3 0 1 2\n", "coordinates too large"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string in = dir.file(c.name);
        std::ofstream(in) << c.text;
        const auto info = run_cli("info " + quoted(in));
        ASSERT_EQ(info.exit_code, 0) << info.out;
        EXPECT_NE(info.out.find("error"), std::string::npos) << info.out;  // info lists the finding
        for (const char* mode : {"octree", "cluster"}) {
            const std::string out = dir.file(std::string(c.name) + (std::string(mode) == "octree" ? ".lfo" : ".out.ply"));
            const auto r = run_cli("octree build " + quoted(in) + " -o " + quoted(out) + " --mode " + mode);
            EXPECT_EQ(r.exit_code, 1) << mode << ": " << r.out;
            EXPECT_NE(r.out.find(in), std::string::npos) << r.out;
            EXPECT_NE(r.out.find(c.needle), std::string::npos) << r.out;
            EXPECT_FALSE(fs::exists(out));
        }
    }
    std::size_t left = 0;
    for (const auto& e : fs::directory_iterator(dir.path())) left += e.path().extension() != ".ply";
    EXPECT_EQ(left, 0u);  // no temporary directory or partial output remains
}

// Issue #27: levels an artist would ship. Every level of the bunny (the untuned case: level 2
// had star fans, broken ears and dark slits, Hausdorff 31 times and image error 4.4 times an edge
// collapse of its size) and of Lucy, at the settings a new user tries, stays within a small factor of
// `lodforge simplify` to the same triangle count, in surface distance and in the rendered image.
// Measured with the level ratio 0.35 (bunny levels 1-4, Lucy 1-5): Hausdorff 1.3-4.4 times, 6.4 at the
// bunny's level 1 (24 674 triangles: 0.35 % of the diagonal, the old 12 676-triangle level 1 had 0.58 %,
// against a collapse at 0.054 %) and at Lucy's level 4 (4 736 triangles, most of them the depth-1 cells' cut
// lines at full resolution); image error 1.1-1.7 times. The bounds (8 and 2.5) leave about 20 % margin
// for the sampling; before the fix the bunny's level 2 was at 31 and 4.4.
TEST(OctreeCli, EveryLevelStaysCloseToAnEdgeCollapseOfItsSize) {
    ScratchDir dir("octree-cli-quality");
    auto measure = [&](const std::string& reference, const std::string& test) {
        const auto r = run_cli("compare --json --samples 100000 --render --render-size 128 " + quoted(reference) + " " +
                                   quoted(test),
                               false);
        EXPECT_EQ(r.exit_code, 0) << r.out;
        const nlohmann::json j = nlohmann::json::parse(r.out);
        return std::pair<double, double>{j["hausdorff_relative"].get<double>(), j["image"]["mean_abs"].get<double>()};
    };
    for (const std::string name : {"scan-bunny/bun_zipper.ply", "scan-lucy100k/Lucy100k.ply"}) {
        SCOPED_TRACE(name);
        const std::string input = shared_data(name), asset = dir.file("a.lfo");
        ASSERT_EQ(run_cli("octree build " + quoted(input) + " -o " + quoted(asset) + " --max-triangles 2000 --max-depth 8")
                      .exit_code,
                  0);
        OctreeStore store(asset);
        const auto& per_level = store.stats().triangles_per_level;
        for (int level = 1; level < store.level_count() && per_level[level] >= 1000; ++level) {
            const std::string lod = dir.file("level.ply"), collapse = dir.file("collapse.ply");
            ASSERT_EQ(run_cli("octree extract " + quoted(asset) + " -o " + quoted(lod) + " --level " + std::to_string(level))
                          .exit_code,
                      0);
            ASSERT_EQ(run_cli("simplify " + quoted(input) + " -o " + quoted(collapse) + " --triangles " +
                              std::to_string(per_level[level]))
                          .exit_code,
                      0);
            const auto [octree_h, octree_image] = measure(input, lod);
            const auto [collapse_h, collapse_image] = measure(input, collapse);
            std::printf("%s level %d: %llu triangles, Hausdorff %.3g %% (collapse %.3g %%), image %.2f (collapse %.2f)\n",
                        name.c_str(), level, static_cast<unsigned long long>(per_level[level]), 100 * octree_h,
                        100 * collapse_h, octree_image, collapse_image);
            EXPECT_LE(octree_h, 8 * collapse_h) << "level " << level;
            EXPECT_LE(octree_image, 2.5 * collapse_image) << "level " << level;
        }
    }
}

}  // namespace
}  // namespace lodforge
