// Artist paint from the command line (issue 31, docs/artist-control.md): `simplify`, `lod` and `pack`
// read --importance FILE|color:CHANNEL and --lock FILE, and the preset keys of the same names; bad paint
// is a clear error with exit status 1.
#include "lodforge/io/file_hash.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/vertex_paint.h"
#include "lodforge/simplify/seams.h"

#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using lodforge::Mesh;
using lodforge::Vec3f;
using lodforge::VertexPaint;
using lodforge::test::CliRun;
using lodforge::test::contains;
using lodforge::test::quoted;
using lodforge::test::run_cli;

std::string spot_path() { return lodforge::test::sample("spot/spot_triangulated.obj"); }
const Mesh& spot() {
    static const Mesh m = lodforge::read_mesh(spot_path());
    return m;
}

// Spot's head painted (within 0.4 of (0, 0.65, -0.3)) and its left flank locked (x > 0.3).
VertexPaint spot_paint() {
    VertexPaint p;
    p.importance.assign(spot().vertex_count(), 0.f);
    p.lock.assign(spot().vertex_count(), 0);
    for (std::size_t v = 0; v < spot().vertex_count(); ++v) {
        const Vec3f x = spot().positions[v];
        const Vec3f d = x - Vec3f{0.f, 0.65f, -0.3f};
        if (lodforge::dot(d, d) < 0.16f) p.importance[v] = 1.f;
        if (x.x > 0.3f) p.lock[v] = 1;
    }
    return p;
}

// Every locked position of Spot is a position of `out`, bit for bit.
void expect_locked_positions(const std::vector<std::uint8_t>& lock, const Mesh& out) {
    std::size_t locked = 0;
    for (std::size_t v = 0; v < spot().vertex_count(); ++v) {
        if (!lock[v]) continue;
        ++locked;
        bool found = false;
        for (const Vec3f& p : out.positions) found = found || std::memcmp(&p, &spot().positions[v], sizeof p) == 0;
        EXPECT_TRUE(found) << "locked vertex " << v;
    }
    EXPECT_GT(locked, 50u);
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
std::string nlohmann_quote(const std::string& s) { return nlohmann::json(s).dump(); }

}  // namespace

TEST(CliPaint, SimplifyHonoursPaintFiles) {
    lodforge::test::ScratchDir dir("cli-paint-simplify");
    const VertexPaint paint = spot_paint();
    const std::string file = dir.file("spot.paint.json");
    lodforge::write_vertex_paint(file, paint, lodforge::sha256_file(spot_path()), spot().vertex_count());
    for (const char* placement : {"half-edge", "optimal"}) {
        SCOPED_TRACE(placement);
        const std::string out = dir.file(std::string("spot-") + placement + ".ply");
        const CliRun r = run_cli("simplify " + quoted(spot_path()) + " -o " + quoted(out) + " --ratio 0.1 --placement " +
                                 placement + " --importance " + quoted(file) + " --lock " + quoted(file));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        const Mesh m = lodforge::read_mesh(out);
        EXPECT_LT(m.triangle_count(), spot().triangle_count() / 2);
        expect_locked_positions(paint.lock, m);
    }
}

TEST(CliPaint, LodAndPackHonourFlagsAndPresetKeys) {
    lodforge::test::ScratchDir dir("cli-paint-lod");
    const VertexPaint paint = spot_paint();
    const std::string file = dir.file("spot.paint.json");
    lodforge::write_vertex_paint(file, paint, lodforge::sha256_file(spot_path()), spot().vertex_count());
    CliRun r = run_cli("lod " + quoted(spot_path()) + " -o " + quoted(dir.file("lods")) +
                       " --levels 0.5,0.2,0.05 --no-measure --lock " + quoted(file) + " --importance " + quoted(file));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    for (int l = 1; l <= 3; ++l) {
        SCOPED_TRACE("lod" + std::to_string(l));
        expect_locked_positions(paint.lock, lodforge::read_mesh(dir.file("lods/lod" + std::to_string(l) + ".ply")));
    }
    // The same paint as preset keys, through `pack`.
    const std::string preset = dir.file("painted.json");
    write_text(preset, "{\"version\": 1, \"levels\": [{\"ratio\": 0.2}, {\"ratio\": 0.05}], \"export\": {\"ply\": true},"
                       " \"importance\": " + nlohmann_quote(file) + ", \"lock\": " + nlohmann_quote(file) + "}");
    r = run_cli("pack " + quoted(spot_path()) + " --preset " + quoted(preset) + " -o " + quoted(dir.file("pack")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::size_t levels = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.file("pack")))
        if (e.path().extension() == ".ply" && e.path().stem().string().find("lod0") == std::string::npos) {
            expect_locked_positions(paint.lock, lodforge::read_mesh(e.path().string()));
            ++levels;
        }
    EXPECT_EQ(levels, 2u);
}

TEST(CliPaint, ColourChannelAsImportance) {
    lodforge::test::ScratchDir dir("cli-paint-colour");
    const std::string colour = lodforge::test::shared_data("color-open3d-small/color.ply");
    CliRun r = run_cli("simplify " + quoted(colour) + " -o " + quoted(dir.file("c.ply")) + " --ratio 0.2 --importance color:g");
    EXPECT_EQ(r.exit_code, 0) << r.out;
    r = run_cli("simplify " + quoted(colour) + " -o " + quoted(dir.file("c.ply")) + " --ratio 0.2 --importance color:x");
    EXPECT_EQ(r.exit_code, 2) << r.out;  // a usage error
    EXPECT_TRUE(contains(r.out, "r, g, b or a")) << r.out;
    // Spot has no vertex colours.
    r = run_cli("simplify " + quoted(spot_path()) + " -o " + quoted(dir.file("s.ply")) + " --ratio 0.2 --importance color:r");
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_TRUE(contains(r.out, "no vertex colours")) << r.out;
}

TEST(CliPaint, BadPaintIsAClearError) {
    lodforge::test::ScratchDir dir("cli-paint-bad");
    const std::string hash = lodforge::sha256_file(spot_path());
    const std::string n = std::to_string(spot().vertex_count());
    auto attempt = [&](const std::string& name, const std::string& text, const std::string& expected) {
        SCOPED_TRACE(name);
        const std::string file = dir.file(name + ".json");
        write_text(file, text);
        const CliRun r = run_cli("simplify " + quoted(spot_path()) + " -o " + quoted(dir.file("out.ply")) +
                                 " --ratio 0.5 --importance " + quoted(file));
        EXPECT_EQ(r.exit_code, 1) << r.out;
        EXPECT_TRUE(contains(r.out, file)) << r.out;
        EXPECT_TRUE(contains(r.out, expected)) << r.out;
    };
    const std::string head = "{\"format\": \"lodforge-paint\", \"version\": 1, ";
    std::string ones;
    for (std::size_t v = 0; v + 1 < spot().vertex_count(); ++v) ones += "0.5,";
    attempt("other-mesh", head + "\"mesh_sha256\": \"" + std::string(64, '0') + "\", \"vertex_count\": " + n +
                              ", \"importance\": [" + ones + "1]}",
            "another mesh");
    attempt("wrong-count", head + "\"mesh_sha256\": \"" + hash + "\", \"vertex_count\": 12, \"importance\": [1]}",
            "the mesh has " + n);
    attempt("not-a-number", head + "\"mesh_sha256\": \"" + hash + "\", \"vertex_count\": " + n + ", \"importance\": [" +
                                ones + "null]}",
            "not a number in [0, 1]");
    attempt("out-of-range", head + "\"mesh_sha256\": \"" + hash + "\", \"vertex_count\": " + n + ", \"importance\": [" +
                                ones + "1.5]}",
            "not a number in [0, 1]");
    attempt("no-importance", head + "\"mesh_sha256\": \"" + hash + "\", \"vertex_count\": " + n + ", \"lock\": [0]}",
            "holds no importance");
    attempt("not-paint", "{\"levels\": []}", "not a paint file");
    const CliRun r = run_cli("simplify " + quoted(spot_path()) + " -o " + quoted(dir.file("out.ply")) +
                             " --ratio 0.5 --importance " + quoted(dir.file("missing.json")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
}

TEST(CliSeams, InfoPrintsTheCountsPerClass) {
    const CliRun r = run_cli("info --seams --json " + quoted(spot_path()), false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    const lodforge::SeamReport expected = lodforge::classify_seams(spot());
    EXPECT_EQ(j["edges"].get<std::size_t>(), expected.edge_count);
    for (int c = 0; c < lodforge::kSeamClasses; ++c) {
        const std::string name(lodforge::to_string(static_cast<lodforge::SeamClass>(c)));
        EXPECT_EQ(j[name].get<std::size_t>(), expected.edges[c].size()) << name;
    }
    EXPECT_GT(j["uv"].get<std::size_t>(), 0u);
    const CliRun text = run_cli("info --seams " + quoted(spot_path()));
    EXPECT_TRUE(contains(text.out, "uv: " + std::to_string(expected.edges[0].size()))) << text.out;
}

TEST(CliSeams, SeamWeightsReachTheSimplifier) {
    lodforge::test::ScratchDir dir("cli-seams");
    const std::string bunny = lodforge::test::shared_data("scan-bunny/bun_zipper.ply");
    CliRun r = run_cli("simplify " + quoted(bunny) + " -o " + quoted(dir.file("plain.ply")) + " --ratio 0.05");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    r = run_cli("simplify " + quoted(bunny) + " -o " + quoted(dir.file("weighted.ply")) +
                " --ratio 0.05 --seams weight=border:20");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    auto borders = [&](const std::string& file) {
        return lodforge::classify_seams(lodforge::read_mesh(file)).edges[static_cast<int>(lodforge::SeamClass::border)].size();
    };
    EXPECT_GT(borders(dir.file("weighted.ply")), borders(dir.file("plain.ply")));
    // The same through a preset and `lod`.
    const std::string preset = dir.file("seams.json");
    write_text(preset, "{\"version\": 1, \"levels\": [{\"ratio\": 0.05}], \"seams\": \"weight=border:20\"}");
    r = run_cli("lod " + quoted(bunny) + " --preset " + quoted(preset) + " --no-measure -o " + quoted(dir.file("lods")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_GT(borders(dir.file("lods/lod1.ply")), borders(dir.file("plain.ply")));
    r = run_cli("simplify " + quoted(bunny) + " -o " + quoted(dir.file("x.ply")) + " --ratio 0.5 --seams protect=uv");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_TRUE(contains(r.out, "protect=uv")) << r.out;
}
