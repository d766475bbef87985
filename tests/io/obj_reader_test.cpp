// OBJ (+MTL) import: the real meshes of ../shared/data with their README counts, the wedge rules,
// materials and texture discovery, and malformed inputs generated at test time.
#include "io_test_util.h"

#include "lodforge/io/image_decode.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/progress.h"
#include "lodforge/io/obj.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string_view>

namespace lodforge {
namespace {
namespace fs = std::filesystem;
using test::expect_error;
using test::expect_well_formed;
using test::shared_data;
using test::write_text;

// Counts straight from the text, independent of tinyobjloader: `v` lines and n-2 triangles per face.
struct ObjCounts {
    std::size_t v = 0, vt = 0, vn = 0, triangles = 0;
};
ObjCounts count_obj(const std::string& path) {
    ObjCounts c;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::string key;
        s >> key;
        if (key == "v") ++c.v;
        else if (key == "vt") ++c.vt;
        else if (key == "vn") ++c.vn;
        else if (key == "f") {
            std::size_t corners = 0;
            for (std::string corner; s >> corner;) ++corners;
            c.triangles += corners - 2;
        }
    }
    return c;
}

bool has_uv_seams(const Mesh& mesh) {
    std::vector<int> wedges(mesh.point_count(), 0);
    for (std::uint32_t id : mesh.position_ids) ++wedges[id];
    return std::any_of(wedges.begin(), wedges.end(), [](int w) { return w > 1; });
}

TEST(ObjReader, SpotTriangulatedMatchesReadme) {
    const Mesh mesh = read_obj(shared_data("tex-spot/spot_triangulated.obj"));
    expect_well_formed(mesh);
    EXPECT_EQ(mesh.point_count(), 2930u);
    EXPECT_EQ(mesh.triangle_count(), 5856u);
    ASSERT_EQ(mesh.texcoords.size(), 1u);
    EXPECT_FALSE(mesh.has_normals());
    EXPECT_FALSE(mesh.has_colors());
    // No welding: every (point, vt) combination tinyobjloader reports survives as its own wedge.
    EXPECT_EQ(test::distinct_point_uv_pairs(mesh), 3225u);
    EXPECT_EQ(mesh.vertex_count(), 3225u);
    EXPECT_TRUE(has_uv_seams(mesh));
}

TEST(ObjReader, SpotTextureFoundByDiscoveryRuleAndDecodes) {
    const Mesh mesh = read_obj(shared_data("tex-spot/spot_triangulated.obj"));
    ASSERT_EQ(mesh.materials.size(), 1u);
    ASSERT_EQ(mesh.face_materials.size(), mesh.triangle_count());
    const TextureRef& tex = mesh.materials[0].base_color_texture;
    EXPECT_EQ(tex.path, "spot_texture.png");
    const std::string resolved = mesh.resolve_texture_path(tex);
    EXPECT_TRUE(fs::is_regular_file(resolved)) << resolved;
    const Image image = decode_texture(mesh, tex);
    EXPECT_EQ(image.width, 1024);
    EXPECT_EQ(image.height, 1024);
    ASSERT_EQ(image.rgba.size(), 1024u * 1024u * 4u);
    std::set<std::uint32_t> colours;
    for (std::size_t i = 0; i < image.rgba.size(); i += 4 * 97)
        colours.insert(image.rgba[i] | image.rgba[i + 1] << 8 | image.rgba[i + 2] << 16);
    EXPECT_GT(colours.size(), 10u) << "texture decodes to a flat image";
}

TEST(ObjReader, SpotQuadsTriangulateToTwoTrianglesEach) {
    const std::string path = shared_data("tex-spot/spot_quadrangulated.obj");
    const ObjCounts counts = count_obj(path);
    const Mesh mesh = read_obj(path);
    expect_well_formed(mesh);
    EXPECT_EQ(mesh.point_count(), 2930u);
    EXPECT_EQ(mesh.triangle_count(), 2u * 2928u);
    EXPECT_EQ(counts.triangles, mesh.triangle_count());
    EXPECT_EQ(test::distinct_point_uv_pairs(mesh), 3225u);
    EXPECT_EQ(mesh.materials.size(), 1u) << "spot_texture.png found through the <stem cut at '_'> rule";
}

TEST(ObjReader, HorseFrameMatchesReadme) {
    const Mesh mesh = read_obj(shared_data("seq-horse-gallop/0001.obj"));
    expect_well_formed(mesh);
    EXPECT_EQ(mesh.point_count(), 8431u);
    EXPECT_EQ(mesh.vertex_count(), 8431u);
    EXPECT_EQ(mesh.triangle_count(), 16843u);
    EXPECT_FALSE(mesh.has_texcoords());
    EXPECT_FALSE(mesh.has_normals());
    EXPECT_TRUE(mesh.materials.empty());
    EXPECT_TRUE(mesh.face_materials.empty());
}

TEST(ObjReader, EveryObjInSharedDataLoadsWithTextCounts) {
    std::size_t files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(LODFORGE_SHARED_DATA)) {
        if (entry.path().extension() != ".obj") continue;
        ++files;
        SCOPED_TRACE(entry.path().string());
        const ObjCounts counts = count_obj(entry.path().string());
        const Mesh mesh = read_mesh(entry.path().string());
        expect_well_formed(mesh);
        EXPECT_EQ(mesh.point_count(), counts.v);
        EXPECT_EQ(mesh.triangle_count(), counts.triangles);
        EXPECT_EQ(mesh.has_texcoords(), counts.vt > 0);
        if (mesh.has_texcoords()) {
            ASSERT_FALSE(mesh.materials.empty()) << "texture discovery found nothing";
            EXPECT_TRUE(fs::is_regular_file(mesh.resolve_texture_path(mesh.materials[0].base_color_texture)));
        }
    }
    EXPECT_GE(files, 51u);  // 48 horse frames + 3 Spot variants
}

TEST(ObjReader, HorseSequenceSharesConnectivity) {
    const Mesh first = read_obj(shared_data("seq-horse-gallop/0001.obj"));
    const Mesh last = read_obj(shared_data("seq-horse-gallop/0048.obj"));
    EXPECT_EQ(first.indices, last.indices);
    EXPECT_NE(first.positions, last.positions);
}

TEST(ObjReader, WedgesFollowFirstUseAndKeepStoredOrder) {
    test::ScratchDir dir("obj-wedges");
    write_text(dir.file("w.obj"),
               "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 5 5 5\n"
               "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvt 0.5 0.5\n"
               "vn 0 0 1\nvn 0 0 -1\n"
               "f 1/1/1 2/2/1 3/3/1\n"
               "f 2/2/1 4/4/1 3/5/1\n"   // vertex 3 with a second uv -> wedge
               "f 3/5/1 4/4/1 2/2/2\n"); // same wedge reused; vertex 2 with a second normal -> wedge
    const Mesh mesh = read_obj(dir.file("w.obj"));
    expect_well_formed(mesh);
    EXPECT_EQ(mesh.point_count(), 5u);  // the unreferenced `v 5 5 5` still counts
    ASSERT_EQ(mesh.vertex_count(), 7u);
    EXPECT_EQ(mesh.positions[4], (Vec3f{5, 5, 5}));
    EXPECT_EQ(mesh.texcoords[0][2], (Vec2f{0, 1}));
    EXPECT_EQ(mesh.position_ids[5], 2u);
    EXPECT_EQ(mesh.texcoords[0][5], (Vec2f{0.5f, 0.5f}));
    EXPECT_EQ(mesh.position_ids[6], 1u);
    EXPECT_EQ(mesh.normals[6], (Vec3f{0, 0, -1}));
    EXPECT_EQ(mesh.texcoords[0][6], (Vec2f{1, 0}));
    const std::vector<std::uint32_t> expected = {0, 1, 2, 1, 3, 5, 5, 3, 6};
    EXPECT_EQ(mesh.indices, expected);
}

TEST(ObjReader, PolygonsAreFanTriangulatedAndRelativeIndicesResolve) {
    test::ScratchDir dir("obj-fan");
    write_text(dir.file("p.obj"),
               "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n"
               "f -5 -4 -3 -2 -1\n");
    const Mesh mesh = read_obj(dir.file("p.obj"));
    const std::vector<std::uint32_t> expected = {0, 1, 2, 0, 2, 3, 0, 3, 4};
    EXPECT_EQ(mesh.indices, expected);
}

TEST(ObjReader, VertexColoursOnlyWhenEveryVertexHasThem) {
    test::ScratchDir dir("obj-colors");
    write_text(dir.file("c.obj"), "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n");
    write_text(dir.file("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Mesh c = read_obj(dir.file("c.obj"));
    ASSERT_TRUE(c.has_colors());
    EXPECT_EQ(c.colors[1], (Vec4f{0, 1, 0, 1}));
    EXPECT_FALSE(read_obj(dir.file("n.obj")).has_colors());
}

TEST(ObjReader, ByteOrderMarkAndCrLfAreAccepted) {
    test::ScratchDir dir("obj-bom");
    write_text(dir.file("b.obj"), "\xEF\xBB\xBFv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n");
    const Mesh mesh = read_obj(dir.file("b.obj"));
    EXPECT_EQ(mesh.point_count(), 3u);
    EXPECT_EQ(mesh.triangle_count(), 1u);
}

TEST(ObjReader, PointsWithoutFacesAreFine) {
    test::ScratchDir dir("obj-points");
    write_text(dir.file("pts.obj"), "# cloud\nv 0 0 0\nv 1 2 3\n");
    const Mesh mesh = read_obj(dir.file("pts.obj"));
    EXPECT_EQ(mesh.point_count(), 2u);
    EXPECT_EQ(mesh.triangle_count(), 0u);
}

TEST(ObjReader, MaterialsFromMtl) {
    test::ScratchDir dir("obj-mtl");
    write_text(dir.file("m.mtl"),
               "newmtl red\nKd 1 0 0\nd 0.5\nmap_Kd tex\\red.png\nbump red_bump.png\n"
               "newmtl blue\nKd 0 0 1\nnorm blue_n.png\nKe 0.1 0.2 0.3\n");
    write_text(dir.file("m.obj"),
               "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\n"
               "f 1/1 2/1 3/1\nusemtl blue\nf 2/1 4/1 3/1\nusemtl red\nf 1/1 3/1 4/1\n");
    const Mesh mesh = read_obj(dir.file("m.obj"));
    expect_well_formed(mesh);
    ASSERT_EQ(mesh.materials.size(), 3u);  // red, blue, and "default" for the face before any usemtl
    EXPECT_EQ(mesh.materials[0].name, "red");
    EXPECT_EQ(mesh.materials[0].base_color, (Vec4f{1, 0, 0, 0.5f}));
    EXPECT_EQ(mesh.materials[0].base_color_texture.path, "tex/red.png");
    EXPECT_EQ(mesh.materials[0].normal_texture.path, "red_bump.png");
    EXPECT_EQ(mesh.materials[1].normal_texture.path, "blue_n.png");
    EXPECT_EQ(mesh.materials[1].emissive, (Vec3f{0.1f, 0.2f, 0.3f}));
    EXPECT_EQ(mesh.materials[2].name, "default");
    const std::vector<std::uint32_t> expected = {2, 1, 0};
    EXPECT_EQ(mesh.face_materials, expected);
    // The textures do not exist: the mesh still opens and the paths stay listed (resolved, missing).
    const std::string resolved = mesh.resolve_texture_path(mesh.materials[0].base_color_texture);
    EXPECT_EQ(fs::path(resolved), (fs::absolute(dir.path()) / "tex/red.png").lexically_normal());
    EXPECT_FALSE(fs::exists(resolved));
    expect_error([&] { decode_texture(mesh, mesh.materials[0].base_color_texture); }, Error::Kind::io, {"red.png"});
}

TEST(ObjReader, MissingMtlIsNotFatal) {
    test::ScratchDir dir("obj-nomtl");
    write_text(dir.file("a.obj"), "mtllib gone.mtl\nusemtl skin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Mesh mesh = read_obj(dir.file("a.obj"));
    EXPECT_EQ(mesh.triangle_count(), 1u);
    EXPECT_TRUE(mesh.materials.empty());
}

TEST(ObjReader, TextureDiscoveryRule) {
    test::ScratchDir dir("obj-discover");
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    write_text(dir.file("rock_lod0.obj"), obj);
    write_text(dir.file("unrelated.png"), "x");
    write_text(dir.file("other.jpg"), "x");
    // Two unrelated images: no rule matches, nothing is guessed.
    EXPECT_TRUE(read_obj(dir.file("rock_lod0.obj")).materials.empty());
    write_text(dir.file("rock_Albedo.JPG"), "x");  // stem cut at '_', case-insensitive
    Mesh mesh = read_obj(dir.file("rock_lod0.obj"));
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_EQ(mesh.materials[0].base_color_texture.path, "rock_Albedo.JPG");
    write_text(dir.file("rock_lod0_texture.png"), "x");  // the full stem wins over the cut one
    mesh = read_obj(dir.file("rock_lod0.obj"));
    EXPECT_EQ(mesh.materials[0].base_color_texture.path, "rock_lod0_texture.png");

    test::ScratchDir single("obj-discover-single");
    write_text(single.file("mesh.obj"), obj);
    write_text(single.file("whatever.tga"), "x");
    mesh = read_obj(single.file("mesh.obj"));
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_EQ(mesh.materials[0].base_color_texture.path, "whatever.tga");
    // Without UVs a texture is useless: none is attached.
    write_text(single.file("flat.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_TRUE(read_obj(single.file("flat.obj")).materials.empty());
}

TEST(ObjReader, MissingFileIsIoError) {
    expect_error([] { read_obj("/nonexistent/dir/missing.obj"); }, Error::Kind::io, {"missing.obj"});
}

TEST(ObjReader, BinaryGarbageIsFormatError) {
    test::ScratchDir dir("obj-garbage");
    std::vector<std::uint8_t> junk(3000);
    for (std::size_t i = 0; i < junk.size(); ++i) junk[i] = static_cast<std::uint8_t>((i * 7919u) >> 3);
    test::write_bytes(dir.file("junk.obj"), junk);
    expect_error([&] { read_obj(dir.file("junk.obj")); }, Error::Kind::format, {"junk.obj"});
    write_text(dir.file("text.obj"), "this is not\nan OBJ file at all\n");
    expect_error([&] { read_obj(dir.file("text.obj")); }, Error::Kind::format, {"text.obj", "no vertices"});
    write_text(dir.file("empty.obj"), "");
    expect_error([&] { read_obj(dir.file("empty.obj")); }, Error::Kind::format, {"empty.obj"});
}

TEST(ObjReader, ZeroIndexIsFormatErrorWithLine) {
    test::ScratchDir dir("obj-zero");
    write_text(dir.file("z.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    expect_error([&] { read_obj(dir.file("z.obj")); }, Error::Kind::format, {"z.obj", "line 4"});
}

TEST(ObjReader, IndexOutOfRangeIsInvalid) {
    test::ScratchDir dir("obj-range");
    write_text(dir.file("r.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    expect_error([&] { read_obj(dir.file("r.obj")); }, Error::Kind::invalid, {"r.obj", "face 2", "vertex 9"});
    write_text(dir.file("neg.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -7\n");
    expect_error([&] { read_obj(dir.file("neg.obj")); }, Error::Kind::invalid, {"neg.obj", "face 1"});
    write_text(dir.file("uv.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n");
    expect_error([&] { read_obj(dir.file("uv.obj")); }, Error::Kind::invalid, {"uv.obj", "texcoord 2"});
    write_text(dir.file("vn.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n");
    expect_error([&] { read_obj(dir.file("vn.obj")); }, Error::Kind::invalid, {"vn.obj", "normal 1"});
}

TEST(ObjReader, DirectoryIsIoError) {
    test::ScratchDir dir("obj-dir");
    fs::create_directories(dir.path() / "x.obj");
    expect_error([&] { read_obj(dir.file("x.obj")); }, Error::Kind::io, {"x.obj"});
}

TEST(ObjReader, TruncatedPrefixesNeverCrash) {
    // Every prefix of a small valid OBJ either loads or throws lodforge::Error.
    test::ScratchDir dir("obj-prefix");
    const std::string text = "mtllib m.mtl\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 1 1 0 1 1 1\n"
                             "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/3/1 4/2/1\nf -1/-1/-1 -2/-2/-1 -3/-3/-1\n";
    write_text(dir.file("m.mtl"), "newmtl a\nKd 1 1 1\n");
    for (std::size_t n = 0; n <= text.size(); ++n) {
        write_text(dir.file("t.obj"), text.substr(0, n));
        try {
            const Mesh mesh = read_obj(dir.file("t.obj"));
            expect_well_formed(mesh);
        } catch (const Error&) {
        }
    }
}


// Found by the format-variant matrix (tests/formats/).
TEST(ObjReader, NanAndInfinityAreInvalidNamingTheLine) {
    test::ScratchDir dir("obj-nan");
    // tinyobjloader reads `nan` and `inf` as 0: the vertex moved silently and every command exited 0.
    write_text(dir.file("nan.obj"), "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    expect_error([&] { read_obj(dir.file("nan.obj")); }, Error::Kind::invalid, {"nan.obj", "line 3", "'nan'"});
    write_text(dir.file("inf.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 -INF 1\nf 1//1 2//1 3//1\n");
    expect_error([&] { read_obj(dir.file("inf.obj")); }, Error::Kind::invalid, {"inf.obj", "line 4", "'-INF'"});
    write_text(dir.file("big.obj"), "v 0 0 0\nv 1 0 0\nv 0 1e999 0\nf 1 2 3\n");
    expect_error([&] { read_obj(dir.file("big.obj")); }, Error::Kind::invalid, {"big.obj", "vertex ('v') 3", "not finite"});
}

TEST(ObjReader, IndicesBeyondTheIntRangeAreInvalidNotWrapped) {
    test::ScratchDir dir("obj-overflow");
    // tinyobjloader's atoi wrapped these: 4294967299 became vertex 3 and -4294967293 vertex 3 too, so a
    // corrupt face silently became a valid triangle on the wrong vertex.
    const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
    for (const char* face : {"f 1 2 4294967299", "f 1 2 -4294967293", "f 1/1 2/4294967297 3/1",
                             "f 1 2 99999999999999999999", "f 1//2147483648 2 3"}) {
        write_text(dir.file("o.obj"), head + face + "\n");
        expect_error([&] { read_obj(dir.file("o.obj")); }, Error::Kind::invalid, {"o.obj", "line 5", "out of range"});
    }
    // The largest int and leading zeros are not overflows (the first is then out of range as usual).
    write_text(dir.file("max.obj"), head + "f 1 2 2147483647\n");
    expect_error([&] { read_obj(dir.file("max.obj")); }, Error::Kind::invalid, {"max.obj", "refers to vertex"});
    write_text(dir.file("zeros.obj"), head + "f 000000000001/1 00000000000002/1 3\n");
    EXPECT_EQ(read_obj(dir.file("zeros.obj")).triangle_count(), 1u);
}

TEST(ObjReader, BackslashContinuesALine) {
    test::ScratchDir dir("obj-continuation");
    // Was "cannot parse OBJ: Failed parse `f' line": tinyobjloader does not join continued lines.
    write_text(dir.file("c.obj"), "v 0 0 \\\n 0\r\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                  "f 1/1 2/2 \\\r\n 3/3 \\\n 4/1\n");
    const Mesh mesh = read_obj(dir.file("c.obj"));
    expect_well_formed(mesh);
    EXPECT_EQ(mesh.point_count(), 4u);
    EXPECT_EQ(mesh.triangle_count(), 2u);
    EXPECT_EQ(mesh.positions[0], (Vec3f{0, 0, 0}));
    ASSERT_TRUE(mesh.has_texcoords());
    EXPECT_EQ(mesh.texcoords[0][2], (Vec2f{1, 1}));
}

TEST(ObjReader, PointCloudNormalsPairWithVertices) {
    test::ScratchDir dir("obj-cloud-normals");
    // Our writer (and MeshLab) store a point cloud's normals as one `vn` per `v`; they were dropped.
    write_text(dir.file("pc.obj"), "v 0 0 0\nv 1 0 0\nvn 0 0 1\nvn 0 1 0\n");
    const Mesh mesh = read_obj(dir.file("pc.obj"));
    ASSERT_TRUE(mesh.has_normals());
    EXPECT_EQ(mesh.normals[1], (Vec3f{0, 1, 0}));
    write_text(dir.file("odd.obj"), "v 0 0 0\nv 1 0 0\nvn 0 0 1\n");  // counts differ: no pairing
    EXPECT_FALSE(read_obj(dir.file("odd.obj")).has_normals());
}

}  // namespace
}  // namespace lodforge

namespace lodforge {
namespace {


TEST(ObjReader, ReportsProgressAndHonoursCancel) {
    test::RecordingProgress progress;
    read_obj(test::shared_data("seq-horse-gallop/0001.obj"), &progress);
    ASSERT_GE(progress.fractions.size(), 2u);
    EXPECT_TRUE(std::is_sorted(progress.fractions.begin(), progress.fractions.end()));
    EXPECT_EQ(progress.fractions.back(), 1.0);
    CancelFlagProgress cancel;
    cancel.cancel();
    test::expect_error([&] { read_obj(test::shared_data("seq-horse-gallop/0001.obj"), &cancel); },
                       Error::Kind::cancelled, {});
}

}  // namespace
}  // namespace lodforge
