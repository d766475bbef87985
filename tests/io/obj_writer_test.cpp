// OBJ writer: OBJ → Mesh → OBJ → Mesh round trips (counts, positions bit-exact, UVs, normals, colours,
// materials), texture copying and extraction, and failure behaviour.
#include "io_test_util.h"

#include "lodforge/io/gltf_reader.h"
#include "lodforge/io/image_decode.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/obj.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace lodforge {
namespace {
namespace fs = std::filesystem;
using test::expect_error;
using test::expect_well_formed;
using test::shared_data;
using test::write_text;

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void expect_same_geometry(const Mesh& a, const Mesh& b) {
    EXPECT_EQ(a.point_count(), b.point_count());
    EXPECT_EQ(a.vertex_count(), b.vertex_count());
    EXPECT_EQ(a.triangle_count(), b.triangle_count());
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.position_ids, b.position_ids);
    EXPECT_EQ(a.indices, b.indices);
    EXPECT_EQ(a.normals, b.normals);
    EXPECT_EQ(a.colors, b.colors);
    ASSERT_EQ(a.texcoords.size(), b.texcoords.size());
    if (!a.texcoords.empty()) {
        EXPECT_EQ(a.texcoords[0], b.texcoords[0]);
    }
    EXPECT_EQ(a.face_materials, b.face_materials);
}

TEST(ObjWriter, SpotRoundTripIsExactAndCopiesTheTexture) {
    const Mesh original = read_obj(shared_data("tex-spot/spot_triangulated.obj"));
    test::ScratchDir dir("objw-spot");
    write_obj(original, dir.file("out.obj"));
    const Mesh again = read_obj(dir.file("out.obj"));
    expect_well_formed(again);
    expect_same_geometry(original, again);
    EXPECT_EQ(again.point_count(), 2930u);
    EXPECT_EQ(test::distinct_point_uv_pairs(again), 3225u);
    ASSERT_EQ(again.materials.size(), 1u);
    EXPECT_EQ(again.materials[0].name, "default");
    EXPECT_EQ(again.materials[0].base_color_texture.path, "spot_texture.png");
    EXPECT_TRUE(fs::is_regular_file(dir.file("spot_texture.png")));
    EXPECT_TRUE(fs::is_regular_file(dir.file("out.mtl")));
    EXPECT_EQ(decode_texture(again, again.materials[0].base_color_texture).width, 1024);
}

TEST(ObjWriter, HorseRoundTripWithoutMaterials) {
    const Mesh original = read_obj(shared_data("seq-horse-gallop/0001.obj"));
    test::ScratchDir dir("objw-horse");
    write_obj(original, dir.file("h.obj"));
    EXPECT_FALSE(fs::exists(dir.file("h.mtl")));
    EXPECT_EQ(read_text(dir.file("h.obj")).find("mtllib"), std::string::npos);
    expect_same_geometry(original, read_obj(dir.file("h.obj")));
}

TEST(ObjWriter, NormalsColoursAndMaterialsSurvive) {
    test::ScratchDir dir("objw-attrs");
    write_text(dir.file("a.png"), "not really a png");
    write_text(dir.file("m.mtl"),
               "newmtl first\nKd 0.25 0.5 0.75\nd 0.5\nmap_Kd a.png\nnorm a.png\n"
               "newmtl second\nKd 1 0 0\nKe 0.5 0.5 0\nPr 0.25\nPm 0.75\n");
    write_text(dir.file("in.obj"),
               "mtllib m.mtl\n"
               "v 0.1 0.2 0.3 1 0 0\nv 1e-7 -2.5 3.25 0 1 0\nv 123456.789 0 -0.000001 0 0 1\nv 1 1 1 0.5 0.5 0.5\n"
               "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.3333333 0.6666667\n"
               "vn 0 0 1\nvn 0.57735026 0.57735026 0.57735026\n"
               "usemtl first\nf 1/1/1 2/2/1 3/3/2\nusemtl second\nf 1/4/2 3/3/2 4/2/1\nf 2/1/1 4/2/2 3/3/2 1/4/1\n");
    const Mesh original = read_obj(dir.file("in.obj"));
    ASSERT_TRUE(original.has_colors());
    ASSERT_TRUE(original.has_normals());
    fs::create_directories(dir.path() / "out");
    const std::string out = (dir.path() / "out" / "copy.obj").string();
    write_obj(original, out);
    const Mesh again = read_obj(out);
    expect_same_geometry(original, again);
    ASSERT_EQ(again.materials.size(), original.materials.size());
    for (std::size_t i = 0; i < original.materials.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_EQ(again.materials[i].base_color, original.materials[i].base_color);
        EXPECT_EQ(again.materials[i].emissive, original.materials[i].emissive);
        EXPECT_EQ(again.materials[i].metallic, original.materials[i].metallic);
        EXPECT_EQ(again.materials[i].roughness, original.materials[i].roughness);
        EXPECT_EQ(again.materials[i].base_color_texture.empty(), original.materials[i].base_color_texture.empty());
        EXPECT_EQ(again.materials[i].normal_texture.empty(), original.materials[i].normal_texture.empty());
    }
    EXPECT_EQ(again.materials[1].name, "second");
    EXPECT_EQ(again.materials[1].roughness, 0.25f);
    EXPECT_EQ(again.materials[1].metallic, 0.75f);
    // One copy of a.png serves both maps.
    EXPECT_EQ(again.materials[0].base_color_texture.path, "a.png");
    EXPECT_EQ(again.materials[0].normal_texture.path, "a.png");
    EXPECT_EQ(read_text((dir.path() / "out" / "a.png").string()), "not really a png");
}

TEST(ObjWriter, WithoutCopyingTexturesReferencesTheOriginals) {
    const Mesh original = read_obj(shared_data("tex-spot/spot_triangulated.obj"));
    test::ScratchDir dir("objw-nocopy");
    WriteOptions options;
    options.copy_textures = false;
    write_obj(original, dir.file("s.obj"), options);
    EXPECT_FALSE(fs::exists(dir.file("spot_texture.png")));
    const Mesh again = read_obj(dir.file("s.obj"));
    ASSERT_EQ(again.materials.size(), 1u);
    const std::string resolved = again.resolve_texture_path(again.materials[0].base_color_texture);
    EXPECT_TRUE(fs::equivalent(resolved, shared_data("tex-spot/spot_texture.png"))) << resolved;
}

TEST(ObjWriter, EmbeddedGlbTextureIsExtracted) {
    const Mesh duck = read_gltf(shared_data("tex-duck/glTF_Binary/Duck.glb"));
    ASSERT_FALSE(duck.materials.at(0).base_color_texture.bytes.empty());
    test::ScratchDir dir("objw-duck");
    write_obj(duck, dir.file("duck.obj"));
    const Mesh again = read_obj(dir.file("duck.obj"));
    expect_well_formed(again);
    EXPECT_EQ(again.point_count(), 2399u);
    EXPECT_EQ(again.triangle_count(), 4212u);
    EXPECT_EQ(again.positions, duck.positions);
    EXPECT_EQ(again.normals, duck.normals);
    EXPECT_EQ(again.texcoords, duck.texcoords);
    ASSERT_EQ(again.materials.size(), 1u);
    const TextureRef& tex = again.materials[0].base_color_texture;
    EXPECT_EQ(fs::path(tex.path).extension(), ".png");
    const Image image = decode_texture(again, tex);
    EXPECT_EQ(image.width, 512);
    EXPECT_EQ(image.height, 512);
}

TEST(ObjWriter, WedgesThatDisagreeOnPositionAreNotWelded) {
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5f, 0, 0}};
    mesh.position_ids = {0, 1, 2, 1};  // vertex 3 claims point 1 but sits elsewhere
    mesh.indices = {0, 1, 2, 0, 3, 2};
    test::ScratchDir dir("objw-fallback");
    write_obj(mesh, dir.file("f.obj"));
    const Mesh again = read_obj(dir.file("f.obj"));
    EXPECT_EQ(again.vertex_count(), 4u);
    EXPECT_EQ(again.positions, mesh.positions);
    EXPECT_EQ(again.indices, mesh.indices);
}

TEST(ObjWriter, PointCloudAndOptionsDropAttributesOnRequest) {
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 2, 3}};
    mesh.normals = {{0, 0, 1}, {0, 1, 0}};
    mesh.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}};
    test::ScratchDir dir("objw-points");
    WriteOptions options;
    options.write_normals = false;
    options.write_colors = false;
    write_obj(mesh, dir.file("p.obj"), options);
    const Mesh again = read_obj(dir.file("p.obj"));
    EXPECT_EQ(again.positions, mesh.positions);
    EXPECT_FALSE(again.has_normals());
    EXPECT_FALSE(again.has_colors());
    EXPECT_EQ(again.triangle_count(), 0u);
}

TEST(ObjWriter, FailuresLeaveNoFileBehind) {
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2};
    expect_error([&] { write_obj(mesh, "/nonexistent-dir/x/out.obj"); }, Error::Kind::io, {"out.obj"});
    test::ScratchDir dir("objw-bad");
    mesh.indices = {0, 1, 7};
    expect_error([&] { write_obj(mesh, dir.file("bad.obj")); }, Error::Kind::invalid, {"bad.obj"});
    EXPECT_FALSE(fs::exists(dir.file("bad.obj")));
    EXPECT_TRUE(fs::is_empty(dir.path()));
}


// Found by the format-variant matrix (tests/formats/).
TEST(ObjWriter, EmptyMeshIsRefusedInsteadOfWritingAnUnreadableObj) {
    test::ScratchDir dir("objw-empty");
    // An OBJ without `v` lines is one our reader (rightly) refuses; `convert empty.ply x.obj` wrote one.
    expect_error([&] { write_mesh(Mesh{}, dir.file("e.obj")); }, Error::Kind::invalid, {"e.obj", "no vertices"});
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(ObjWriter, OneSetFormatsKeepTheSetTheTextureSamples) {
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.position_ids = {0, 1, 2};
    mesh.indices = {0, 1, 2};
    mesh.texcoords = {{{0, 0}, {0, 0}, {0, 0}}, {{0.25f, 0.5f}, {0.75f, 0.5f}, {0.25f, 1}}};
    Material m;
    m.name = "m";
    m.base_color_texture.path = "tex.png";
    m.base_color_texture.texcoord_set = 1;  // glTF baseColorTexture.texCoord = 1
    mesh.materials = {m};
    mesh.face_materials = {0};
    test::ScratchDir dir("objw-set1");
    WriteOptions options;
    options.copy_textures = false;
    for (const char* name : {"t.obj", "t.ply"}) {
        SCOPED_TRACE(name);
        write_mesh(mesh, dir.file(name), options);  // wrote set 0, so the texture was sampled at (0, 0)
        const Mesh again = read_mesh(dir.file(name));
        ASSERT_TRUE(again.has_texcoords());
        EXPECT_EQ(again.texcoords[0][1], (Vec2f{0.75f, 0.5f}));
        EXPECT_EQ(again.texcoords[0][2], (Vec2f{0.25f, 1}));
    }
}

}  // namespace
}  // namespace lodforge
