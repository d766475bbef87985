// `lodforge compare --render` and `pack --image-error`: the image-space error, rendered offscreen by the
// real executable (a private Xvfb when DISPLAY is not set). docs/image-compare.md.
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;
using lodforge::test::run_command;

namespace {

std::string spot_sample() { return lodforge::test::sample("spot/spot_triangulated.obj"); }

// Spot moved by `dx` along X, beside its texture (found by the OBJ reader from the file name).
std::string shiftedSpot(const lodforge::test::ScratchDir& dir, const std::string& name, double dx) {
    std::ifstream in(spot_sample());
    std::ofstream out(dir.file(name));
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("v ", 0) == 0) {
            std::istringstream s(line.substr(2));
            double x = 0, y = 0, z = 0;
            s >> x >> y >> z;
            out << "v " << x + dx << ' ' << y << ' ' << z << '\n';
        } else {
            out << line << '\n';
        }
    }
    std::filesystem::copy_file(lodforge::test::sample("spot/spot_texture.png"), dir.file("spot_texture.png"),
                               std::filesystem::copy_options::overwrite_existing);
    return dir.file(name);
}

nlohmann::json renderJson(const std::string& reference, const std::string& test, const std::string& extra = {}) {
    const CliRun r = run_cli("compare --json --samples 20000 --render " + quoted(reference) + " " + quoted(test) +
                             " " + extra, false);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    if (r.exit_code != 0) return {};
    return nlohmann::json::parse(r.out)["image"];
}

// Width and height from a PNG's IHDR chunk.
std::pair<std::uint32_t, std::uint32_t> pngSize(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char h[24] = {};
    in.read(reinterpret_cast<char*>(h), sizeof h);
    auto be = [&](int o) {
        return std::uint32_t(h[o]) << 24 | std::uint32_t(h[o + 1]) << 16 | std::uint32_t(h[o + 2]) << 8 | h[o + 3];
    };
    if (!in || h[1] != 'P' || h[2] != 'N' || h[3] != 'G') return {0, 0};
    return {be(16), be(20)};
}

}  // namespace

TEST(CliRender, IdenticalMeshesGiveZeroInEveryView) {
    const nlohmann::json image = renderJson(spot_sample(), spot_sample(), "--render-size 96");
    ASSERT_FALSE(image.is_null());
    EXPECT_EQ(image["size"], 96);
    ASSERT_EQ(image["views"].size(), 14u);
    for (const auto& v : image["views"]) {
        EXPECT_GT(v["covered"].get<int>(), 96 * 96 / 20) << v["name"];  // the cow fills a good part of each view
        EXPECT_EQ(v["mean_abs"].get<double>(), 0.0) << v["name"];
        EXPECT_EQ(v["over_threshold"].get<double>(), 0.0) << v["name"];
        EXPECT_EQ(v["silhouette"].get<double>(), 0.0) << v["name"];
    }
    EXPECT_EQ(image["views"][0]["name"], "+x");
    EXPECT_EQ(image["views"][13]["name"], "-x-y-z");
}

TEST(CliRender, SimplifiedLevelDiffersAndCoarserDiffersMore) {
    lodforge::test::ScratchDir dir("cli-render-simplified");
    for (const char* ratio : {"0.2", "0.02"}) {
        const CliRun r = run_cli("simplify " + quoted(spot_sample()) + " -o " + quoted(dir.file(std::string("spot_") + ratio + ".glb")) +
                                 " --ratio " + ratio);
        ASSERT_EQ(r.exit_code, 0) << r.out;
    }
    const nlohmann::json fine = renderJson(spot_sample(), dir.file("spot_0.2.glb"), "--render-size 128");
    const nlohmann::json coarse = renderJson(spot_sample(), dir.file("spot_0.02.glb"), "--render-size 128");
    ASSERT_FALSE(fine.is_null());
    ASSERT_FALSE(coarse.is_null());
    std::printf("spot 20 %%: mean %.3f over %.4f silhouette %.4f; 2 %%: mean %.3f over %.4f silhouette %.4f\n",
                fine["mean_abs"].get<double>(), fine["over_threshold"].get<double>(), fine["silhouette"].get<double>(),
                coarse["mean_abs"].get<double>(), coarse["over_threshold"].get<double>(),
                coarse["silhouette"].get<double>());
    EXPECT_GT(fine["mean_abs"].get<double>(), 0.0);
    EXPECT_GT(coarse["mean_abs"].get<double>(), fine["mean_abs"].get<double>());
    EXPECT_GT(coarse["over_threshold"].get<double>(), fine["over_threshold"].get<double>());
    EXPECT_GT(coarse["silhouette"].get<double>(), fine["silhouette"].get<double>());
    // Still the same cow in the same place: most pixels agree.
    EXPECT_LT(coarse["silhouette"].get<double>(), 0.2);
}

TEST(CliRender, ShiftedMeshShowsInTheSilhouetteInProportionToTheShift) {
    lodforge::test::ScratchDir dir("cli-render-shift");
    const std::string a = shiftedSpot(dir, "spot_a.obj", 0.0);  // the same cow through the same reader
    const std::string near = shiftedSpot(dir, "spot_near.obj", 0.02);
    const std::string far = shiftedSpot(dir, "spot_far.obj", 0.08);
    const nlohmann::json same = renderJson(spot_sample(), a, "--render-size 96");
    const nlohmann::json n = renderJson(spot_sample(), near, "--render-size 96");
    const nlohmann::json f = renderJson(spot_sample(), far, "--render-size 96");
    ASSERT_FALSE(same.is_null() || n.is_null() || f.is_null());
    EXPECT_EQ(same["silhouette"].get<double>(), 0.0);
    EXPECT_GT(n["silhouette"].get<double>(), 0.01);
    EXPECT_GT(f["silhouette"].get<double>(), 2 * n["silhouette"].get<double>());
    // Looking along X the shift moves nothing sideways: the +x view's silhouette barely changes, the +z
    // view's does.
    const auto& views = f["views"];
    ASSERT_EQ(views[0]["name"], "+x");
    ASSERT_EQ(views[4]["name"], "+z");
    EXPECT_LT(views[0]["silhouette"].get<double>(), views[4]["silhouette"].get<double>());
    EXPECT_GT(f["mean_abs"].get<double>(), n["mean_abs"].get<double>());
}

TEST(CliRender, SameInputSameNumbers) {
    lodforge::test::ScratchDir dir("cli-render-determinism");
    ASSERT_EQ(run_cli("simplify " + quoted(spot_sample()) + " -o " + quoted(dir.file("s.glb")) + " --ratio 0.1").exit_code, 0);
    const nlohmann::json first = renderJson(spot_sample(), dir.file("s.glb"), "--render-size 64");
    const nlohmann::json second = renderJson(spot_sample(), dir.file("s.glb"), "--render-size 64");
    ASSERT_FALSE(first.is_null());
    EXPECT_EQ(first.dump(), second.dump());
}

TEST(CliRender, WritesSideBySideAndDifferencePngs) {
    lodforge::test::ScratchDir dir("cli-render-out");
    const std::string moved = shiftedSpot(dir, "spot_moved.obj", 0.05);
    const std::string out = dir.file("images");
    const nlohmann::json image = renderJson(spot_sample(), moved, "--render-size 80 --render-out " + quoted(out));
    ASSERT_FALSE(image.is_null());
    ASSERT_EQ(image["files"].size(), 28u);
    EXPECT_EQ(pngSize(out + "/00_+x_side.png"), std::make_pair(160u, 80u));
    EXPECT_EQ(pngSize(out + "/00_+x_diff.png"), std::make_pair(80u, 80u));
    EXPECT_EQ(pngSize(out + "/13_-x-y-z_diff.png"), std::make_pair(80u, 80u));
    for (const auto& f : image["files"]) EXPECT_TRUE(std::filesystem::is_regular_file(f.get<std::string>())) << f;
    // The text output says where they went.
    const CliRun text = run_cli("compare --samples 20000 --render --render-size 32 --render-out " + quoted(out) + " " +
                                quoted(spot_sample()) + " " + quoted(moved));
    ASSERT_EQ(text.exit_code, 0) << text.out;
    EXPECT_NE(text.out.find("silhouette mismatch"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("28 PNGs"), std::string::npos) << text.out;
}

TEST(CliRender, HeadlessStartsItsOwnXvfbAndABadDisplayIsAClearError) {
    const CliRun headless = run_command("env -u DISPLAY " + std::string(LODFORGE_BIN_DIR) +
                                        "/lodforge --quiet compare --json --samples 20000 --render --render-size 48 " +
                                        quoted(spot_sample()) + " " + quoted(spot_sample()) + " 2>&1");
    ASSERT_EQ(headless.exit_code, 0) << headless.out;
    EXPECT_EQ(nlohmann::json::parse(headless.out)["image"]["mean_abs"].get<double>(), 0.0);
    const CliRun bad = run_command("DISPLAY=:4711 " + std::string(LODFORGE_BIN_DIR) +
                                   "/lodforge --quiet compare --render " + quoted(spot_sample()) + " " + quoted(spot_sample()) + " 2>&1");
    EXPECT_EQ(bad.exit_code, 1) << bad.out;
    EXPECT_NE(bad.out.find("cannot open DISPLAY=:4711"), std::string::npos) << bad.out;
}

TEST(CliRender, RenderOptionsAreChecked) {
    CliRun r = run_cli("compare --render-size 64 " + quoted(spot_sample()) + " " + quoted(spot_sample()));
    EXPECT_EQ(r.exit_code, 2) << r.out;  // a usage error
    EXPECT_NE(r.out.find("need --render"), std::string::npos) << r.out;
    r = run_cli("compare --render --render-size 8 " + quoted(spot_sample()) + " " + quoted(spot_sample()));
    EXPECT_EQ(r.exit_code, 2) << r.out;  // a usage error
    EXPECT_NE(r.out.find("16..4096"), std::string::npos) << r.out;
    r = run_cli("compare --render --render-threshold 300 " + quoted(spot_sample()) + " " + quoted(spot_sample()));
    EXPECT_EQ(r.exit_code, 2) << r.out;  // a usage error
    EXPECT_NE(r.out.find("0..255"), std::string::npos) << r.out;
}

TEST(CliRender, PackWritesEachLevelsImageErrorIntoPackJson) {
    lodforge::test::ScratchDir dir("cli-render-pack");
    {
        std::ofstream preset(dir.file("p.json"));
        preset << R"({"version": 1, "name": "two", "levels": [{"ratio": 0.3}, {"ratio": 0.05}],
                     "export": {"glb": false}})";
    }
    const CliRun r = run_cli("pack " + quoted(spot_sample()) + " --preset " + quoted(dir.file("p.json")) + " -o " +
                             quoted(dir.file("pack")) + " --image-error");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("image error"), std::string::npos) << r.out;
    std::ifstream in(dir.file("pack/pack.json"));
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_EQ(j["levels"].size(), 3u);
    EXPECT_FALSE(j["levels"][0].contains("image_error"));
    const auto& a = j["levels"][1]["image_error"];
    const auto& b = j["levels"][2]["image_error"];
    ASSERT_TRUE(a.is_object() && b.is_object()) << j.dump(1);
    EXPECT_EQ(a["views"].size(), 14u);
    EXPECT_EQ(a["size"], 256);
    EXPECT_GT(a["mean_abs"].get<double>(), 0.0);
    EXPECT_GT(b["mean_abs"].get<double>(), a["mean_abs"].get<double>());
    EXPECT_TRUE(j["preset"]["export"]["image_error"].get<bool>());
    // Without the flag nothing is rendered and nothing is written.
    const CliRun plain = run_cli("pack " + quoted(spot_sample()) + " --preset " + quoted(dir.file("p.json")) + " -o " +
                                 quoted(dir.file("plain")));
    ASSERT_EQ(plain.exit_code, 0) << plain.out;
    std::ifstream in2(dir.file("plain/pack.json"));
    const nlohmann::json k = nlohmann::json::parse(in2);
    EXPECT_FALSE(k["levels"][1].contains("image_error"));
}

// Vertex colours with alpha below 1 are drawn opaque (glTF's default), so their pixels are measured: two
// quads that differ only in colour must differ in the image, not read 0 because nothing was covered.
TEST(CliRender, TranslucentVertexColoursAreMeasured) {
    lodforge::test::ScratchDir dir("cli-render-rgba");
    auto quad = [&](const std::string& name, int red) {
        std::ofstream out(dir.file(name));
        out << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
               "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
               "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
        for (const char* xyz : {"0 0 0", "1 0 0", "1 1 0", "0 1 0"}) out << xyz << ' ' << red << " 40 40 100\n";
        out << "3 0 1 2\n3 0 2 3\n";
        return dir.file(name);
    };
    const std::string dark = quad("dark.ply", 40), bright = quad("bright.ply", 240);
    const nlohmann::json same = renderJson(dark, dark, "--render-size 64");
    const nlohmann::json differ = renderJson(dark, bright, "--render-size 64");
    ASSERT_FALSE(same.is_null());
    ASSERT_FALSE(differ.is_null());
    EXPECT_EQ(same["mean_abs"].get<double>(), 0.0);
    EXPECT_GT(differ["mean_abs"].get<double>(), 10.0);
    EXPECT_GT(differ["over_threshold"].get<double>(), 0.5);
}
