// `lodforge mcoctree build|extract|info` run as users run them.
#include "lodforge/io/mesh_io.h"
#include "mc_test_support.h"
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

using lodforge::test::quoted;
using lodforge::test::run_cli;

namespace {
using lodforge::test::contains;
}  // namespace

TEST(CliMcOctree, BuildInfoExtractRoundTrip) {
    lodforge::test::ScratchDir dir("cli-mco");
    const std::string bunny = lodforge::test::shared_data("scan-bunny/bun_zipper.ply");
    const std::string mco = dir.file("bunny.mco");
    auto r = run_cli("mcoctree build " + quoted(bunny) + " -o " + quoted(mco) + " --resolution 32");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "leaf cubes")) << r.out;
    r = run_cli("mcoctree info " + quoted(mco) + " --json", false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    const std::size_t max_priority = j["max_priority"];
    EXPECT_GT(max_priority, 100u);
    EXPECT_EQ(j["triangle_table"].size(), 11u);
    const std::uint64_t full = j["triangle_table"].back()["triangles"];
    r = run_cli("mcoctree extract " + quoted(mco) + " --triangles " + std::to_string(full / 3) + " -o " + quoted(dir.file("a.ply")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const lodforge::Mesh m = lodforge::read_mesh(dir.file("a.ply"));
    EXPECT_LE(m.triangle_count(), full / 3);
    EXPECT_GT(m.triangle_count(), full / 4);
    EXPECT_EQ(lodforge::test::check_watertight(m).border_edges, 0u);
    r = run_cli("mcoctree extract " + quoted(mco) + " --priority " + std::to_string(max_priority) + " -o " + quoted(dir.file("b.ply")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(lodforge::read_mesh(dir.file("b.ply")).triangle_count(), full);
    r = run_cli("mcoctree info " + quoted(mco));
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_TRUE(contains(r.out, "nodes on")) << r.out;
    // Given to a mesh command, the tree is named for what it is, with the way to a mesh.
    r = run_cli("info " + quoted(mco));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "not a mesh: a LodForge marching-cube octree")) << r.out;
    EXPECT_TRUE(contains(r.out, "mcoctree extract")) << r.out;
}

TEST(CliMcOctree, ErrorsNameTheFileAndUseTheExitCodes) {
    lodforge::test::ScratchDir dir("cli-mco-err");
    // a point cloud without normals
    const std::string pts = dir.file("pts.ply");
    {
        std::ofstream f(pts);
        f << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n";
    }
    auto r = run_cli("mcoctree build " + quoted(pts) + " -o " + quoted(dir.file("x.mco")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "lodforge: error: " + pts + ": the points have no normals")) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.mco")));
    const std::string junk = dir.file("junk.mco");
    {
        std::ofstream f(junk);
        f << "not an octree";
    }
    r = run_cli("mcoctree info " + quoted(junk));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, junk) && contains(r.out, "bad magic")) << r.out;
    r = run_cli("mcoctree extract " + quoted(junk) + " -o " + quoted(dir.file("o.ply")));
    EXPECT_GE(r.exit_code, 1);
    r = run_cli("mcoctree build " + quoted(dir.file("missing.ply")) + " -o " + quoted(dir.file("y.mco")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_GE(run_cli("mcoctree").exit_code, 2);
    EXPECT_EQ(run_cli("mcoctree build --help").exit_code, 0);
}
