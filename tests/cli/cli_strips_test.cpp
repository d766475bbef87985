// `lodforge strips`, `strips info`, `strips extract` run as users run them.
#include "lodforge/io/mesh_io.h"

#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace {

using lodforge::test::CliRun;
using lodforge::test::contains;
using lodforge::test::quoted;
using lodforge::test::run_cli;

TEST(CliStrips, BuildInfoExtractInBothJoinModes) {
    lodforge::test::ScratchDir dir("cli-strips");
    const std::string in = lodforge::test::shared_data("scan-dragon/dragon_vrip_res4.ply");
    for (const char* mode : {"--restart", "--degenerate"}) {
        SCOPED_TRACE(mode);
        const std::string out = dir.file(std::string("res4") + mode + ".lodstrips");
        CliRun r = run_cli("strips " + quoted(in) + " -o " + quoted(out) + " " + mode + " --weights normal=0.1");
        ASSERT_EQ(r.exit_code, 0) << r.out;
        EXPECT_TRUE(contains(r.out, "ratio")) << r.out;
        r = run_cli("strips info " + quoted(out) + " --json", false);
        ASSERT_EQ(r.exit_code, 0) << r.out;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["join"], std::string(mode).substr(2));
        EXPECT_GT(j["strips"].get<int>(), 10);
        EXPECT_EQ(j["lods"].get<int>(), j["collapses"].get<int>() + 1);
        // res4 has 11,102 faces; the simplifier drops the ones degenerate on welded points up front.
        const std::size_t full_tris = j["triangles"]["full"].get<std::size_t>();
        EXPECT_LE(full_tris, 11102u);
        EXPECT_GT(full_tris, 10000u);
        EXPECT_EQ(j["bytes"]["file"].get<std::uintmax_t>(), std::filesystem::file_size(out));
        EXPECT_LT(j["ratio_to_indexed_mesh"].get<double>(), 2.0);
        EXPECT_GT(j["ratio_to_indexed_mesh"].get<double>(), 1.0);
        r = run_cli("strips info " + quoted(out));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        EXPECT_TRUE(contains(r.out, "LODs")) << r.out;

        const std::string coarse = dir.file("coarse.ply"), full = dir.file("full.ply"), half = dir.file("half.ply");
        ASSERT_EQ(run_cli("strips extract " + quoted(out) + " --lod 0 -o " + quoted(coarse)).exit_code, 0);
        ASSERT_EQ(run_cli("strips extract " + quoted(out) + " --lod 1 -o " + quoted(full)).exit_code, 0);
        ASSERT_EQ(run_cli("strips extract " + quoted(out) + " --triangles 5000 -o " + quoted(half)).exit_code, 0);
        EXPECT_EQ(lodforge::read_mesh(coarse).triangle_count(), j["triangles"]["coarsest"].get<std::size_t>());
        EXPECT_EQ(lodforge::read_mesh(full).triangle_count(), full_tris);
        const std::size_t h = lodforge::read_mesh(half).triangle_count();
        EXPECT_LE(h, 5000u);
        EXPECT_GE(h, 4990u);
    }
}

TEST(CliStrips, StripOrderCacheKeepsTheTrianglesAndMakesMoreStrips) {
    lodforge::test::ScratchDir dir("cli-strips-order");
    const std::string in = lodforge::test::shared_data("scan-dragon/dragon_vrip_res4.ply");
    nlohmann::json info[2];
    const char* orders[2] = {"run-off", "cache"};
    for (int i = 0; i < 2; ++i) {
        const std::string out = dir.file(std::string(orders[i]) + ".lodstrips");
        CliRun r = run_cli("strips " + quoted(in) + " -o " + quoted(out) + " --strip-order " + orders[i] + " --json", false);
        ASSERT_EQ(r.exit_code, 0) << r.out;
        info[i] = nlohmann::json::parse(r.out);
    }
    // Same collapse sequence, so the same triangles per level; meshoptimizer's order cuts more strips.
    EXPECT_EQ(info[0]["triangles"], info[1]["triangles"]);
    EXPECT_EQ(info[0]["collapses"], info[1]["collapses"]);
    EXPECT_GT(info[1]["strips"].get<int>(), info[0]["strips"].get<int>());
    CliRun r = run_cli("strips " + quoted(in) + " -o " + quoted(dir.file("x.lodstrips")) + " --strip-order fifo");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_TRUE(contains(r.out, "--strip-order")) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.lodstrips")));
}

TEST(CliStrips, BadInputSaysWhatAndWhere) {
    lodforge::test::ScratchDir dir("cli-strips-bad");
    CliRun r = run_cli("strips info " + quoted(dir.file("missing.lodstrips")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "lodforge: error: ") && contains(r.out, "missing.lodstrips")) << r.out;

    const std::string spot = lodforge::test::shared_data("tex-spot/spot_triangulated.obj");
    const std::string good = dir.file("spot.lodstrips");
    ASSERT_EQ(run_cli("strips " + quoted(spot) + " -o " + quoted(good)).exit_code, 0);
    const std::string cut = dir.file("cut.lodstrips");
    {
        std::ifstream in(good, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }
    r = run_cli("strips extract " + quoted(cut) + " --lod 0.5 -o " + quoted(dir.file("x.ply")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "cut.lodstrips") && contains(r.out, "truncated")) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.ply")));

    r = run_cli("strips extract " + quoted(good) + " --lod 1.5 -o " + quoted(dir.file("x.ply")));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.exit_code, 1) << "a usage error";
    r = run_cli("strips " + quoted(good) + " -o " + quoted(dir.file("y.lodstrips")));
    EXPECT_EQ(r.exit_code, 1) << "a .lodstrips is not a mesh input: " << r.out;
    r = run_cli("strips " + quoted(spot) + " -o " + quoted(dir.file("no/dir/y.lodstrips")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    r = run_cli("strips");
    EXPECT_EQ(r.exit_code, 2);  // a usage error
    EXPECT_TRUE(contains(r.out, "strips")) << r.out;
    EXPECT_EQ(run_cli("strips --help").exit_code, 0);
}

}  // namespace
