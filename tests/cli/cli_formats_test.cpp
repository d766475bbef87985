// Format variants derived from the real meshes of ../shared/data, through the real `lodforge`
// executable: the cases the format matrix (tests/formats/run_matrix.py) found failing. Each runs in a
// scratch directory that is removed afterwards.
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace {
namespace fs = std::filesystem;
using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    ASSERT_TRUE(out.good()) << path;
}

// The Stanford bunny's 35,947 scanned points with its faces removed: a real point cloud.
std::string bunny_point_cloud(const lodforge::test::ScratchDir& dir) {
    const std::string text = read_text(lodforge::test::shared_data("scan-bunny/bun_zipper.ply"));
    std::string header = text.substr(0, text.find("end_header\n"));
    const std::size_t face = header.find("element face 69451");
    EXPECT_NE(face, std::string::npos);
    header.replace(face, std::string("element face 69451").size(), "element face 0");
    std::size_t body = text.find("end_header\n") + 11, end = body;
    for (int i = 0; i < 35947; ++i) end = text.find('\n', end) + 1;
    const std::string path = dir.file("bunny points.ply");
    write_text(path, header + "end_header\n" + text.substr(body, end - body));
    return path;
}

nlohmann::json info_json(const std::string& path) {
    const CliRun r = run_cli("info --json " + quoted(path), false);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json{};
}

TEST(CliFormats, MeshCommandsRefuseAPointCloudNamingTheFileAndLeaveNothing) {
    lodforge::test::ScratchDir dir("cli-formats-cloud");
    const std::string cloud = bunny_point_cloud(dir);
    EXPECT_EQ(info_json(cloud)["vertices"], 35947);
    // Before: "lodforge: error: build_lod_chain: the mesh has no triangles" (no file), and lod left
    // an empty output directory.
    const struct {
        std::string args, output;
    } runs[] = {{"lod " + quoted(cloud) + " --levels 0.5 -o " + quoted(dir.file("lods")), dir.file("lods")},
                {"strips " + quoted(cloud) + " -o " + quoted(dir.file("s.lodstrips")), dir.file("s.lodstrips")},
                {"compare " + quoted(cloud) + " " + quoted(cloud), ""}};
    for (const auto& run : runs) {
        SCOPED_TRACE(run.args);
        const CliRun r = run_cli(run.args);
        EXPECT_EQ(r.exit_code, 1) << r.out;
        EXPECT_NE(r.out.find("lodforge: error: " + cloud + ": no triangles (35947 points)"), std::string::npos) << r.out;
        if (!run.output.empty()) {
            EXPECT_FALSE(fs::exists(run.output));
        }
    }
}

TEST(CliFormats, PointCloudKeepsItsNormalsThroughObj) {
    lodforge::test::ScratchDir dir("cli-formats-cloud-obj");
    // color.ply's points with normals and colours, faces dropped on the way: PLY → OBJ → PLY.
    ASSERT_EQ(run_cli("convert " + quoted(lodforge::test::shared_data("color-open3d-small/color.ply")) + " " +
                      quoted(dir.file("mesh.obj"))).exit_code, 0);
    std::istringstream lines(read_text(dir.file("mesh.obj")));
    std::string cloud, line;
    while (std::getline(lines, line))
        if (line.rfind("f ", 0) != 0) cloud += line + "\n";
    write_text(dir.file("cloud.obj"), cloud);
    const auto j = info_json(dir.file("cloud.obj"));
    EXPECT_EQ(j["vertices"], 3017);
    EXPECT_EQ(j["triangles"], 0);
    const auto attrs = j["attributes"].get<std::vector<std::string>>();
    EXPECT_NE(std::find(attrs.begin(), attrs.end(), "normal"), attrs.end()) << j.dump();  // dropped before
    EXPECT_NE(std::find(attrs.begin(), attrs.end(), "color"), attrs.end()) << j.dump();
}

TEST(CliFormats, EmptyMeshToObjIsRefusedNotWrittenUnreadable) {
    lodforge::test::ScratchDir dir("cli-formats-empty");
    write_text(dir.file("empty.ply"), "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                                      "property float z\nend_header\n");
    const CliRun r = run_cli("convert " + quoted(dir.file("empty.ply")) + " " + quoted(dir.file("out.obj")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("out.obj: no vertices"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir.file("out.obj")));
}

TEST(CliFormats, SpotWithLineContinuationsAndNanLines) {
    lodforge::test::ScratchDir dir("cli-formats-obj");
    std::istringstream lines(read_text(lodforge::test::sample("spot/spot_triangulated.obj")));
    std::string continued, with_nan, line;
    int v_lines = 0;
    while (std::getline(lines, line)) {
        // Every face split after its first corner, CRLF on the continued part.
        if (line.rfind("f ", 0) == 0) continued += line.substr(0, line.find(' ', 2)) + " \\\r\n " + line.substr(line.find(' ', 2)) + "\n";
        else continued += line + "\n";
        if (line.rfind("v ", 0) == 0 && ++v_lines == 100) with_nan += "v 0.1 NaN 0.2\n";
        else with_nan += line + "\n";
    }
    write_text(dir.file("continued.obj"), continued);
    const auto j = info_json(dir.file("continued.obj"));
    EXPECT_EQ(j["triangles"], 5856);  // was exit 1: "Failed parse `f' line"
    EXPECT_EQ(j["vertices"], 2930);
    write_text(dir.file("nan.obj"), with_nan);
    const CliRun r = run_cli("convert " + quoted(dir.file("nan.obj")) + " " + quoted(dir.file("out.ply")));
    EXPECT_EQ(r.exit_code, 1) << r.out;  // was exit 0 with the vertex silently at y = 0
    EXPECT_NE(r.out.find("nan.obj: line"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("'NaN' is not a finite number"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir.file("out.ply")));
}

}  // namespace
