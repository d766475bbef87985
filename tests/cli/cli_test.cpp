// Runs the real `lodforge` executable the way users and scripts do and checks output and exit codes.
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;

TEST(Cli, HelpListsTheCommands) {
    const CliRun r = run_cli("--help");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("info"), std::string::npos);
    EXPECT_NE(r.out.find("convert"), std::string::npos);
    EXPECT_EQ(run_cli("info --help").exit_code, 0);
}

TEST(Cli, NoCommandOrUnknownOptionIsAUsageError) {
    EXPECT_NE(run_cli("").exit_code, 0);
    EXPECT_NE(run_cli("info --bogus x.ply").exit_code, 0);
}

TEST(Cli, InfoJsonOnTheDragonHasTheReadmeCounts) {
    const CliRun r = run_cli("info --json " + quoted(lodforge::test::shared_data("scan-dragon/dragon_vrip_res2.ply")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["vertices"], 100250);
    EXPECT_EQ(j["triangles"], 202520);
    EXPECT_EQ(j["attributes"][0], "position");
    EXPECT_EQ(j["bounds"]["min"].size(), 3u);
}

TEST(Cli, InfoOnColouredScanListsNormalsAndColours) {
    const CliRun r = run_cli("info --json " + quoted(lodforge::test::shared_data("color-open3d-frag115/frag_115.ply")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["vertices"], 64365);
    EXPECT_EQ(j["triangles"], 127229);
    const auto attrs = j["attributes"].get<std::vector<std::string>>();
    EXPECT_NE(std::find(attrs.begin(), attrs.end(), "normal"), attrs.end());
    EXPECT_NE(std::find(attrs.begin(), attrs.end(), "color"), attrs.end());
}

TEST(Cli, InfoTextReportsValidationFindings) {
    lodforge::test::ScratchDir dir("cli-findings");
    {
        std::ofstream out(dir.file("dup.ply"));
        out << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
               "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 2 1 0\n3 0 0 3\n";
    }
    const CliRun r = run_cli("info " + quoted(dir.file("dup.ply")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("duplicate triangles"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("degenerate triangles"), std::string::npos) << r.out;
}

TEST(Cli, ErrorsExitNonZeroAndNameTheFile) {
    lodforge::test::ScratchDir dir("cli-errors");
    {
        std::ofstream out(dir.file("truncated.ply"));
        out << "ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\n"
               "end_header\n0 0 0\n1 1 1\n";
    }
    CliRun r = run_cli("info " + quoted(dir.file("truncated.ply")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("truncated.ply"), std::string::npos) << r.out;
    r = run_cli("info " + quoted(dir.file("missing.obj")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.out.find("missing.obj: no such file"), std::string::npos) << r.out;
}

TEST(Cli, ConvertObjToPlyAndBackKeepsCounts) {
    lodforge::test::ScratchDir dir("cli-convert");
    const std::string spot = lodforge::test::sample("spot/spot_triangulated.obj");
    for (const char* enc : {"ascii", "binary", "binary-be"}) {
        const std::string out = dir.file(std::string("spot-") + enc + ".ply");
        CliRun r = run_cli("convert --encoding " + std::string(enc) + " " + quoted(spot) + " " + quoted(out));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        r = run_cli("info --json " + quoted(out));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["triangles"], 5856) << enc;
        const auto attrs = j["attributes"].get<std::vector<std::string>>();
        EXPECT_NE(std::find(attrs.begin(), attrs.end(), "texcoord0"), attrs.end()) << enc;
    }
    const std::string obj = dir.file("again.obj");
    ASSERT_EQ(run_cli("convert " + quoted(dir.file("spot-binary.ply")) + " " + quoted(obj)).exit_code, 0);
    const auto j = nlohmann::json::parse(run_cli("info --json " + quoted(obj)).out);
    EXPECT_EQ(j["triangles"], 5856);
}

TEST(Cli, ConvertToAnUnwritablePlaceFailsWithoutPartialOutput) {
    lodforge::test::ScratchDir dir("cli-unwritable");
    const std::string spot = lodforge::test::sample("spot/spot_triangulated.obj");
    const CliRun r = run_cli("convert " + quoted(spot) + " " + quoted(dir.file("no/such/dir/out.ply")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.out.find("out.ply"), std::string::npos) << r.out;
    const CliRun bad = run_cli("convert " + quoted(spot) + " " + quoted(dir.file("out.stl")));
    EXPECT_NE(bad.exit_code, 0);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}
