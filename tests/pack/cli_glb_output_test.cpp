// `.glb` as the output of the single-mesh commands (simplify, convert, lod --format glb, the extract
// subcommands): the file passes the Khronos validator, reads back with the triangles the command
// reported and keeps texture coordinates, colours and the embedded texture; what cannot be written
// (.gltf, an unknown extension) fails at once with exit status 1 and no file; an unreadable texture
// leaves a warning and a valid, untextured .glb.
#include "pack_test_util.h"
#include "support/cli_run.h"
#include "support/test_paths.h"

#include "lodforge/io/mesh_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

using namespace lodforge;
using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;
namespace fs = std::filesystem;

// "a.glb: 4212 -> 420 triangles ..." -> 420
std::size_t reported_triangles(const std::string& out) {
    const auto arrow = out.find("-> ");
    if (arrow == std::string::npos) return 0;
    return std::stoul(out.substr(arrow + 3));
}

TEST(CliGlbOutput, SimplifiedDuckIsValidTexturedGlb) {
    ScratchDir dir("cli-glb-simplify");
    const std::string out = dir.file("duck10.glb");
    const CliRun r = run_cli("-q simplify " + quoted(shared_data("tex-duck/glTF_Binary/Duck.glb")) + " -o " +
                             quoted(out) + " --ratio 0.1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto v = test::validate_gltf(out);
    EXPECT_EQ(v.exit_code, 0) << v.raw;
    ASSERT_TRUE(v.report.is_object()) << v.raw;
    EXPECT_EQ(v.report["errors"], 0) << v.raw;

    const Mesh m = read_mesh(out);
    EXPECT_EQ(m.triangle_count(), reported_triangles(r.out)) << r.out;
    EXPECT_NEAR(double(m.triangle_count()), 421.0, 5.0);
    ASSERT_TRUE(m.has_texcoords());
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_FALSE(m.materials[0].base_color_texture.bytes.empty()) << "the texture is embedded";
    // The simplified duck still sits where the input does (node transforms applied once, not twice).
    const Mesh in = read_mesh(shared_data("tex-duck/glTF_Binary/Duck.glb"));
    EXPECT_NEAR(m.bounds().diagonal(), in.bounds().diagonal(), 0.05 * in.bounds().diagonal());
}

TEST(CliGlbOutput, ConvertKeepsSpotsUvsAndColoursOfAScan) {
    ScratchDir dir("cli-glb-convert");
    {
        const std::string out = dir.file("spot.glb");
        const CliRun r = run_cli("-q convert " + quoted(shared_data("tex-spot/spot_triangulated.obj")) + " " + quoted(out));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        EXPECT_EQ(test::validate_gltf(out).exit_code, 0);
        const Mesh in = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
        const Mesh m = read_mesh(out);
        EXPECT_EQ(m.triangle_count(), in.triangle_count());
        ASSERT_TRUE(m.has_texcoords());
        ASSERT_FALSE(m.materials.empty());
        EXPECT_FALSE(m.materials[0].base_color_texture.bytes.empty());
        // Same UVs at the same corners (the writer flips v for glTF, the reader flips it back).
        ASSERT_EQ(m.indices.size(), in.indices.size());
        double worst = 0;
        for (std::size_t c = 0; c < in.indices.size(); ++c) {
            const Vec2f a = in.texcoords[0][in.indices[c]], b = m.texcoords[0][m.indices[c]];
            worst = std::max({worst, double(std::abs(a.x - b.x)), double(std::abs(a.y - b.y))});
        }
        EXPECT_LT(worst, 1e-6);
    }
    {
        const std::string out = dir.file("frag.glb");
        const CliRun r = run_cli("-q convert " + quoted(shared_data("color-open3d-small/color.ply")) + " " + quoted(out));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        EXPECT_EQ(test::validate_gltf(out).exit_code, 0);
        const Mesh m = read_mesh(out);
        ASSERT_TRUE(m.has_colors());
        const Mesh in = read_mesh(shared_data("color-open3d-small/color.ply"));
        EXPECT_EQ(m.triangle_count(), in.triangle_count());
    }
}

TEST(CliGlbOutput, LodChainAsGlbLevels) {
    ScratchDir dir("cli-glb-lod");
    const CliRun r = run_cli("-q lod " + quoted(shared_data("scan-bunny/bun_zipper.ply")) + " -o " +
                             quoted(dir.file("lods")) + " --levels 0.5,0.1 --format glb --no-measure");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::size_t previous = 0;
    for (int i = 0; i < 3; ++i) {
        const std::string f = dir.file("lods/lod" + std::to_string(i) + ".glb");
        ASSERT_TRUE(fs::exists(f)) << f;
        EXPECT_EQ(test::validate_gltf(f).exit_code, 0) << f;
        const std::size_t t = read_mesh(f).triangle_count();
        if (i > 0) {
            EXPECT_LT(t, previous);
        }
        previous = t;
    }
}

TEST(CliGlbOutput, GltfAndUnknownOutputsFailBeforeTheWork) {
    ScratchDir dir("cli-glb-bad");
    for (const char* name : {"out.gltf", "out.stl"}) {
        const std::string out = dir.file(name);
        const CliRun r = run_cli("-q simplify " + quoted(shared_data("scan-bunny/bun_zipper.ply")) + " -o " +
                                 quoted(out) + " --ratio 0.5");
        EXPECT_EQ(r.exit_code, 1) << r.out;
        EXPECT_NE(r.out.find(out), std::string::npos) << r.out;
        EXPECT_NE(r.out.find(".glb"), std::string::npos) << r.out;
        EXPECT_FALSE(fs::exists(out));
    }
    const CliRun c = run_cli("-q convert " + quoted(shared_data("scan-bunny/bun_zipper.ply")) + " " +
                             quoted(dir.file("x.gltf")));
    EXPECT_EQ(c.exit_code, 1) << c.out;
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(CliGlbOutput, MissingTextureGivesAWarningAndAnUntexturedGlb) {
    ScratchDir dir("cli-glb-missing-texture");
    // Spot's OBJ and MTL copied without the PNG.
    const fs::path src = shared_data("tex-spot");
    fs::copy_file(src / "spot_triangulated.obj", dir.path() / "spot.obj");
    std::ofstream(dir.file("spot.mtl")) << "newmtl spot\nKd 0.8 0.7 0.6\nmap_Kd spot_texture.png\n";
    std::string obj;
    {
        std::ifstream in(dir.file("spot.obj"));
        obj.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    std::ofstream(dir.file("spot.obj")) << "mtllib spot.mtl\nusemtl spot\n" << obj;
    const std::string out = dir.file("spot.glb");
    const CliRun r = run_cli("-q convert " + quoted(dir.file("spot.obj")) + " " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("warning"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("spot_texture.png"), std::string::npos) << r.out;
    EXPECT_EQ(test::validate_gltf(out).exit_code, 0);
    const Mesh m = read_mesh(out);
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_TRUE(m.materials[0].base_color_texture.empty());
    EXPECT_NEAR(m.materials[0].base_color.x, 0.8f, 1e-6f);
}

}  // namespace
