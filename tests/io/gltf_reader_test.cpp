// glTF 2.0 import: the real samples of ../shared/data with their README counts and textures, node
// transforms, primitive modes, accessor variants, and malformed files generated at test time.
#include "io_test_util.h"

#include "lodforge/io/gltf_reader.h"
#include "lodforge/io/image_decode.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/progress.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <string_view>

namespace lodforge {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using test::expect_error;
using test::expect_well_formed;
using test::shared_data;

json load_json(const std::string& path) {
    std::ifstream in(path);
    return json::parse(in);
}

struct Sample {
    const char* path;
    std::size_t points, triangles;
};
const Sample kSamples[] = {
    {"tex-duck/glTF/Duck.gltf", 2399, 4212},
    {"tex-duck/glTF_Binary/Duck.glb", 2399, 4212},
    {"tex-water-bottle/WaterBottle.gltf", 2549, 4510},
    {"tex-cesium-milk-truck/CesiumMilkTruck.gltf", 2978, 2856},
    {"morph-animated-morph-cube/AnimatedMorphCube.gltf", 24, 12},
    {"morph-animated-morph-sphere/AnimatedMorphSphere.gltf", 1876, 960},
};

TEST(GltfReader, SamplesMatchReadmeCounts) {
    for (const Sample& s : kSamples) {
        SCOPED_TRACE(s.path);
        const Mesh mesh = read_mesh(shared_data(s.path));
        expect_well_formed(mesh);
        EXPECT_EQ(mesh.point_count(), s.points);
        EXPECT_EQ(mesh.triangle_count(), s.triangles);
        EXPECT_TRUE(mesh.has_normals());
        EXPECT_EQ(mesh.face_materials.size(), mesh.triangle_count());
        for (const Vec3f& n : mesh.normals) ASSERT_NEAR(length(n), 1.0f, 1e-3f);
    }
}

TEST(GltfReader, EveryGltfInSharedDataLoads) {
    std::size_t files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(LODFORGE_SHARED_DATA)) {
        const std::string ext = entry.path().extension().string();
        if (ext != ".gltf" && ext != ".glb") continue;
        ++files;
        SCOPED_TRACE(entry.path().string());
        const Mesh mesh = read_gltf(entry.path().string());
        expect_well_formed(mesh);
        EXPECT_GT(mesh.triangle_count(), 0u);
        for (const Material& m : mesh.materials)
            for (const TextureRef* t : {&m.base_color_texture, &m.normal_texture, &m.metallic_roughness_texture,
                                        &m.occlusion_texture, &m.emissive_texture})
                if (!t->empty() && t->bytes.empty()) {
                    EXPECT_TRUE(fs::is_regular_file(mesh.resolve_texture_path(*t))) << t->path;
                }
    }
    // Eight files today (the Duck twice, the truck, the bottle, two morph and two skinned models); more may be
    // added, but the walk must never silently find fewer.
    EXPECT_GE(files, 8u);
}

TEST(GltfReader, DuckTextureAndTransform) {
    const std::string path = shared_data("tex-duck/glTF/Duck.gltf");
    const Mesh mesh = read_gltf(path);
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_EQ(mesh.materials[0].name, "blinn3-fx");
    EXPECT_EQ(mesh.materials[0].metallic, 0.f);
    const TextureRef& tex = mesh.materials[0].base_color_texture;
    EXPECT_EQ(tex.path, "DuckCM.png");
    EXPECT_TRUE(fs::is_regular_file(mesh.resolve_texture_path(tex)));
    const Image image = decode_texture(mesh, tex);
    EXPECT_EQ(image.width, 512);
    EXPECT_EQ(image.height, 512);
    ASSERT_EQ(mesh.texcoords.size(), 1u);

    // The root node scales by 0.01: bounds are the POSITION accessor's min/max times 0.01.
    const json doc = load_json(path);
    const json& pos = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
    const Bounds b = mesh.bounds();
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(b.min[c], pos["min"][c].get<double>() * 0.01, 1e-4);
        EXPECT_NEAR(b.max[c], pos["max"][c].get<double>() * 0.01, 1e-4);
    }
    // V is flipped to the OpenGL convention (v' = 1 - v).
    const json& uv = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"].get<int>()];
    float vmin = 2, vmax = -2;
    for (const Vec2f& t : mesh.texcoords[0]) {
        vmin = std::min(vmin, t.y);
        vmax = std::max(vmax, t.y);
    }
    EXPECT_NEAR(vmin, 1.0 - uv["max"][1].get<double>(), 1e-6);
    EXPECT_NEAR(vmax, 1.0 - uv["min"][1].get<double>(), 1e-6);
}

TEST(GltfReader, DuckGlbEqualsGltfAndEmbeddedTextureDecodes) {
    const Mesh text = read_gltf(shared_data("tex-duck/glTF/Duck.gltf"));
    const Mesh binary = read_gltf(shared_data("tex-duck/glTF_Binary/Duck.glb"));
    EXPECT_EQ(text.positions, binary.positions);
    EXPECT_EQ(text.indices, binary.indices);
    EXPECT_EQ(text.texcoords, binary.texcoords);
    const TextureRef& tex = binary.materials.at(0).base_color_texture;
    ASSERT_FALSE(tex.bytes.empty());
    EXPECT_EQ(tex.mime_type, "image/png");
    EXPECT_TRUE(binary.resolve_texture_path(tex).empty());
    const Image embedded = decode_texture(binary, tex);
    const Image file = decode_texture(text, text.materials[0].base_color_texture);
    EXPECT_EQ(embedded.width, 512);
    EXPECT_EQ(embedded.height, 512);
    EXPECT_EQ(embedded.rgba, file.rgba);
}

TEST(GltfReader, WaterBottlePbrTextures) {
    const Mesh mesh = read_gltf(shared_data("tex-water-bottle/WaterBottle.gltf"));
    ASSERT_EQ(mesh.materials.size(), 1u);
    const Material& m = mesh.materials[0];
    EXPECT_EQ(m.name, "BottleMat");
    EXPECT_EQ(m.base_color_texture.path, "WaterBottle_baseColor.png");
    EXPECT_EQ(m.metallic_roughness_texture.path, "WaterBottle_roughnessMetallic.png");
    EXPECT_EQ(m.normal_texture.path, "WaterBottle_normal.png");
    EXPECT_EQ(m.occlusion_texture.path, "WaterBottle_occlusion.png");
    EXPECT_EQ(m.emissive_texture.path, "WaterBottle_emissive.png");
    for (const TextureRef* t : {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                                &m.occlusion_texture, &m.emissive_texture})
        EXPECT_TRUE(fs::is_regular_file(mesh.resolve_texture_path(*t))) << t->path;
    EXPECT_EQ(m.emissive, (Vec3f{1, 1, 1}));
    EXPECT_EQ(mesh.texcoords.size(), 1u);
}

TEST(GltfReader, MilkTruckMaterialsAndInstancing) {
    const std::string path = shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf");
    const Mesh mesh = read_gltf(path);
    ASSERT_EQ(mesh.materials.size(), 4u);  // every primitive has a material: no default added
    EXPECT_EQ(mesh.materials[0].name, "truck");
    EXPECT_EQ(mesh.materials[3].name, "wheels");
    EXPECT_EQ(mesh.materials[0].base_color_texture.path, "CesiumMilkTruck.png");
    EXPECT_TRUE(mesh.materials[1].base_color_texture.empty());
    // Triangles per material are the primitives' index counts / 3; the wheel mesh, instanced by two
    // nodes, is imported once.
    const json doc = load_json(path);
    std::map<int, std::size_t> expected;
    for (const json& gm : doc["meshes"])
        for (const json& p : gm["primitives"])
            expected[p["material"].get<int>()] += doc["accessors"][p["indices"].get<int>()]["count"].get<std::size_t>() / 3;
    std::map<int, std::size_t> actual;
    for (std::uint32_t m : mesh.face_materials) ++actual[static_cast<int>(m)];
    EXPECT_EQ(actual, expected);
}

TEST(GltfReader, MorphTargetsIgnoredBaseGeometryLoaded) {
    const Mesh mesh = read_gltf(shared_data("morph-animated-morph-cube/AnimatedMorphCube.gltf"));
    EXPECT_EQ(mesh.vertex_count(), 24u);
    EXPECT_EQ(mesh.point_count(), 24u);
    EXPECT_FALSE(mesh.has_texcoords());
}

// ---- generated files ------------------------------------------------------------------------------

// Builds a small glTF: raw little-endian data in one buffer, accessors appended on demand.
class GltfBuilder {
public:
    GltfBuilder() {
        doc_ = {{"asset", {{"version", "2.0"}}},
                {"scene", 0},
                {"scenes", json::array({{{"nodes", json::array({0})}}})},
                {"nodes", json::array({{{"mesh", 0}}})},
                {"meshes", json::array({{{"primitives", json::array()}}})},
                {"buffers", json::array()},
                {"bufferViews", json::array()},
                {"accessors", json::array()}};
    }

    template <typename T>
    int accessor(const std::vector<T>& values, int component_type, const char* type, std::size_t count,
                 bool normalized = false) {
        while (bin_.size() % 4) bin_.push_back(0);
        const std::size_t offset = bin_.size();
        bin_.resize(offset + values.size() * sizeof(T));
        std::memcpy(bin_.data() + offset, values.data(), values.size() * sizeof(T));
        doc_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
        json a = {{"bufferView", doc_["bufferViews"].size() - 1},
                  {"componentType", component_type},
                  {"count", count},
                  {"type", type}};
        if (normalized) a["normalized"] = true;
        doc_["accessors"].push_back(a);
        return static_cast<int>(doc_["accessors"].size() - 1);
    }
    int floats(const std::vector<float>& v, const char* type, std::size_t per) {
        return accessor(v, 5126, type, v.size() / per);
    }
    int indices(const std::vector<std::uint16_t>& v) { return accessor(v, 5123, "SCALAR", v.size()); }

    json& primitive(json attributes, int indices = -1, int mode = -1) {
        json p = {{"attributes", attributes}};
        if (indices >= 0) p["indices"] = indices;
        if (mode >= 0) p["mode"] = mode;
        doc_["meshes"][0]["primitives"].push_back(p);
        return doc_["meshes"][0]["primitives"].back();
    }

    json& doc() { return doc_; }

    // Writes <name>.gltf + <name>.bin into `dir`; returns the .gltf path.
    std::string write(const test::ScratchDir& dir, const std::string& name) {
        doc_["buffers"] = json::array({{{"uri", name + ".bin"}, {"byteLength", bin_.size()}}});
        test::write_bytes(dir.file(name + ".bin"), bin_);
        test::write_text(dir.file(name + ".gltf"), doc_.dump(1));
        return dir.file(name + ".gltf");
    }

private:
    json doc_;
    std::vector<std::uint8_t> bin_;
};

const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};

TEST(GltfReader, TrsTransformNegativeScaleFlipsWinding) {
    test::ScratchDir dir("gltf-trs");
    GltfBuilder b;
    const int pos = b.floats(kQuad, "VEC3", 3);
    const int nrm = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
    b.primitive({{"POSITION", pos}, {"NORMAL", nrm}}, b.indices({0, 1, 2, 0, 2, 3}));
    // Parent translates, child rotates 90° about Y and mirrors X.
    b.doc()["nodes"] = json::array({{{"translation", {10, 0, 0}}, {"children", {1}}},
                                    {{"mesh", 0}, {"rotation", {0, 0.70710678, 0, 0.70710678}}, {"scale", {-2, 1, 1}}}});
    const Mesh mesh = read_gltf(b.write(dir, "trs"));
    ASSERT_EQ(mesh.vertex_count(), 4u);
    // x' = R * (S * x) + T: (1,0,0) -> S (-2,0,0) -> R(90° about Y) (0,0,2) -> +T (10,0,2).
    EXPECT_NEAR(mesh.positions[1].x, 10.f, 1e-5f);
    EXPECT_NEAR(mesh.positions[1].y, 0.f, 1e-5f);
    EXPECT_NEAR(mesh.positions[1].z, 2.f, 1e-5f);
    // Normal (0,0,1): inverse transpose of R*S keeps it unit length; Rotating +Z by 90° about Y gives +X.
    EXPECT_NEAR(mesh.normals[0].x, 1.f, 1e-5f);
    EXPECT_NEAR(length(mesh.normals[0]), 1.f, 1e-5f);
    // det < 0: winding flipped so faces stay counter-clockwise.
    const std::vector<std::uint32_t> expected = {0, 2, 1, 0, 3, 2};
    EXPECT_EQ(mesh.indices, expected);
    // The flipped triangle's geometric normal agrees with the transformed vertex normal.
    const Vec3f n = cross(mesh.positions[2] - mesh.positions[0], mesh.positions[1] - mesh.positions[0]);
    EXPECT_GT(dot(n, mesh.normals[0]), 0.f);
}

TEST(GltfReader, StripsFansNonIndexedAndSkippedModes) {
    test::ScratchDir dir("gltf-modes");
    GltfBuilder b;
    const std::vector<float> five = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};
    b.primitive({{"POSITION", b.floats(five, "VEC3", 3)}}, -1, 5);                                      // strip: 3 tris
    b.primitive({{"POSITION", b.floats(five, "VEC3", 3)}}, b.indices({0, 1, 3, 4}), 6);                 // fan: 2 tris
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}}, -1, 1);                                     // lines: skipped
    b.primitive({{"POSITION", b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3)}});                       // triangles, no indices
    const Mesh mesh = read_gltf(b.write(dir, "modes"));
    expect_well_formed(mesh);
    EXPECT_EQ(mesh.point_count(), 5u + 5u + 3u);
    const std::vector<std::uint32_t> expected = {0, 1, 2, 1, 3, 2, 2, 3, 4,  // strip, odd triangle reordered
                                                 6, 8, 5, 8, 9, 5,           // fan around the first index
                                                 10, 11, 12};
    EXPECT_EQ(mesh.indices, expected);
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_EQ(mesh.materials[0].name, "default");
}

TEST(GltfReader, NormalizedColoursTexcoordSetsAndSparse) {
    test::ScratchDir dir("gltf-attrs");
    GltfBuilder b;
    const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int col = b.accessor(std::vector<std::uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0}, 5121, "VEC3", 3, true);
    const int uv0 = b.accessor(std::vector<std::uint16_t>{0, 0, 65535, 0, 0, 65535}, 5123, "VEC2", 3, true);
    const int uv1 = b.floats({0.25f, 0.25f, 0.5f, 0.5f, 0.75f, 0.75f}, "VEC2", 2);
    b.primitive({{"POSITION", pos}, {"COLOR_0", col}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}});
    // Second primitive: sparse positions on top of zeros (no bufferView), no colour, no uv.
    const int sparse_idx = b.accessor(std::vector<std::uint8_t>{1, 2, 0, 0}, 5121, "SCALAR", 2);
    const int sparse_val = b.floats({5, 5, 5, 6, 6, 6}, "VEC3", 3);
    json& doc = b.doc();
    const int view_idx = doc["accessors"][sparse_idx]["bufferView"];
    const int view_val = doc["accessors"][sparse_val]["bufferView"];
    doc["accessors"].push_back({{"componentType", 5126},
                                {"count", 3},
                                {"type", "VEC3"},
                                {"sparse",
                                 {{"count", 2},
                                  {"indices", {{"bufferView", view_idx}, {"componentType", 5121}}},
                                  {"values", {{"bufferView", view_val}}}}}});
    b.primitive({{"POSITION", static_cast<int>(doc["accessors"].size() - 1)}});
    const Mesh mesh = read_gltf(b.write(dir, "attrs"));
    expect_well_formed(mesh);
    ASSERT_EQ(mesh.vertex_count(), 6u);
    ASSERT_TRUE(mesh.has_colors());
    EXPECT_EQ(mesh.colors[0], (Vec4f{1, 0, 0, 1}));
    EXPECT_EQ(mesh.colors[2], (Vec4f{0, 0, 1, 1}));
    EXPECT_EQ(mesh.colors[4], (Vec4f{1, 1, 1, 1}));  // primitive without COLOR_0: white
    ASSERT_EQ(mesh.texcoords.size(), 2u);
    EXPECT_EQ(mesh.texcoords[0][1], (Vec2f{1, 1}));  // (1, 0) with v flipped
    EXPECT_EQ(mesh.texcoords[0][2], (Vec2f{0, 0}));
    EXPECT_EQ(mesh.texcoords[1][0], (Vec2f{0.25f, 0.75f}));
    EXPECT_EQ(mesh.texcoords[1][4], (Vec2f{0, 0}));  // absent set filled with zeros
    EXPECT_EQ(mesh.positions[3], (Vec3f{0, 0, 0}));
    EXPECT_EQ(mesh.positions[4], (Vec3f{5, 5, 5}));
    EXPECT_EQ(mesh.positions[5], (Vec3f{6, 6, 6}));
}

TEST(GltfReader, SharedPositionAccessorStoresPointsOnce) {
    test::ScratchDir dir("gltf-shared");
    GltfBuilder b;
    const int pos = b.floats(kQuad, "VEC3", 3);
    const int uv_a = b.floats({0, 0, 1, 0, 1, 1, 0, 1}, "VEC2", 2);
    const int uv_b = b.floats({0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f}, "VEC2", 2);
    b.primitive({{"POSITION", pos}, {"TEXCOORD_0", uv_a}}, b.indices({0, 1, 2}));
    b.primitive({{"POSITION", pos}, {"TEXCOORD_0", uv_a}}, b.indices({0, 2, 3}));  // same attributes: same vertices
    b.primitive({{"POSITION", pos}, {"TEXCOORD_0", uv_b}}, b.indices({0, 2, 3}));  // different uv: wedges
    // A second node instancing the same mesh adds nothing.
    b.doc()["nodes"] = json::array({{{"mesh", 0}}, {{"mesh", 0}, {"translation", {5, 0, 0}}}});
    b.doc()["scenes"][0]["nodes"] = {0, 1};
    const Mesh mesh = read_gltf(b.write(dir, "shared"));
    expect_well_formed(mesh);
    EXPECT_EQ(mesh.point_count(), 4u);
    EXPECT_EQ(mesh.vertex_count(), 7u);
    EXPECT_EQ(mesh.triangle_count(), 3u);
    const std::vector<std::uint32_t> expected = {0, 1, 2, 0, 2, 3, 4, 5, 6};
    EXPECT_EQ(mesh.indices, expected);
    EXPECT_EQ(mesh.position_ids[5], 2u);
    EXPECT_EQ(mesh.texcoords[0][5], (Vec2f{0.5f, 0.5f}));
}

TEST(GltfReader, MissingFileIsIoError) {
    expect_error([] { read_gltf("/nonexistent/model.gltf"); }, Error::Kind::io, {"model.gltf"});
}

TEST(GltfReader, MissingBinIsIoErrorNamingBoth) {
    test::ScratchDir dir("gltf-nobin");
    GltfBuilder b;
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}});
    const std::string path = b.write(dir, "nobin");
    fs::remove(dir.file("nobin.bin"));
    expect_error([&] { read_gltf(path); }, Error::Kind::io, {"nobin.gltf", "nobin.bin"});
}

TEST(GltfReader, MissingTextureStillOpensAndIsListed) {
    test::ScratchDir dir("gltf-notex");
    GltfBuilder b;
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}, {"TEXCOORD_0", b.floats({0, 0, 1, 0, 1, 1, 0, 1}, "VEC2", 2)}},
                b.indices({0, 1, 2, 0, 2, 3}))["material"] = 0;
    b.doc()["materials"] = json::array({{{"name", "painted"},
                                         {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    b.doc()["textures"] = json::array({{{"source", 0}}});
    b.doc()["images"] = json::array({{{"uri", "gone%20away.png"}}});
    const Mesh mesh = read_gltf(b.write(dir, "notex"));
    ASSERT_EQ(mesh.materials.size(), 1u);
    const TextureRef& tex = mesh.materials[0].base_color_texture;
    EXPECT_EQ(tex.path, "gone away.png");
    const std::string resolved = mesh.resolve_texture_path(tex);
    EXPECT_FALSE(resolved.empty());
    EXPECT_FALSE(fs::exists(resolved));
    expect_error([&] { decode_texture(mesh, tex); }, Error::Kind::io, {"gone away.png"});
}

TEST(GltfReader, InvalidJsonIsFormatError) {
    test::ScratchDir dir("gltf-json");
    test::write_text(dir.file("bad.gltf"), "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ ");
    expect_error([&] { read_gltf(dir.file("bad.gltf")); }, Error::Kind::format, {"bad.gltf"});
    test::write_text(dir.file("empty.gltf"), "");
    expect_error([&] { read_gltf(dir.file("empty.gltf")); }, Error::Kind::format, {"empty.gltf"});
}

TEST(GltfReader, IndexOutOfRangeIsInvalid) {
    test::ScratchDir dir("gltf-range");
    GltfBuilder b;
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}}, b.indices({0, 1, 9}));
    expect_error([&] { read_gltf(b.write(dir, "range")); }, Error::Kind::invalid, {"range.gltf", "index 9"});
}

TEST(GltfReader, AccessorBeyondBufferIsFormatError) {
    test::ScratchDir dir("gltf-overrun");
    GltfBuilder b;
    const int pos = b.floats(kQuad, "VEC3", 3);
    b.primitive({{"POSITION", pos}});
    b.doc()["accessors"][pos]["count"] = 400;
    expect_error([&] { read_gltf(b.write(dir, "overrun")); }, Error::Kind::format, {"overrun.gltf"});
}

TEST(GltfReader, RequiredDracoIsUnsupported) {
    test::ScratchDir dir("gltf-draco");
    GltfBuilder b;
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}});
    b.doc()["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    b.doc()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    expect_error([&] { read_gltf(b.write(dir, "draco")); }, Error::Kind::unsupported, {"draco.gltf", "KHR_draco"});
}

TEST(GltfReader, TruncatedGlbPrefixesThrowAndNeverCrash) {
    const std::vector<std::uint8_t> glb = test::read_bytes(shared_data("tex-duck/glTF_Binary/Duck.glb"));
    ASSERT_GT(glb.size(), 1000u);
    test::ScratchDir dir("gltf-trunc");
    const std::string path = dir.file("t.glb");
    std::size_t step = 1;
    for (std::size_t n = 0; n < glb.size(); n += step) {
        step = n < 64 ? 1 : 997;  // every byte of the header, then a sweep through the chunks
        test::write_bytes(path, std::vector<std::uint8_t>(glb.begin(), glb.begin() + static_cast<std::ptrdiff_t>(n)));
        SCOPED_TRACE(n);
        expect_error([&] { read_gltf(path); }, Error::Kind::format, {"t.glb"});
    }
    // Once the length field is there, the message says what is wrong.
    test::write_bytes(path, std::vector<std::uint8_t>(glb.begin(), glb.begin() + 3000));
    expect_error([&] { read_gltf(path); }, Error::Kind::format,
                 {"t.glb", "truncated GLB", std::to_string(glb.size()), "3000"});
}

TEST(GltfReader, CorruptedGlbBytesNeverCrash) {
    // Flipping bytes inside the JSON chunk must give either a mesh or a lodforge::Error.
    const std::vector<std::uint8_t> glb = test::read_bytes(shared_data("tex-duck/glTF_Binary/Duck.glb"));
    test::ScratchDir dir("gltf-corrupt");
    const std::string path = dir.file("c.glb");
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    for (std::size_t i = 20; i < 20 + json_length; i += 37) {
        std::vector<std::uint8_t> copy = glb;
        copy[i] = static_cast<std::uint8_t>(copy[i] ^ 0x5A);
        test::write_bytes(path, copy);
        try {
            expect_well_formed(read_gltf(path));
        } catch (const Error&) {
        }
    }
}


// Found by the format-variant matrix (tests/formats/): each was a crash, a silent empty import or a
// silently accepted defect before.
TEST(GltfReader, LyingAccessorCountIsFormatErrorNotAnAllocation) {
    test::ScratchDir dir("gltf-lying-count");
    GltfBuilder b;
    const int pos = b.floats(kQuad, "VEC3", 3);
    b.primitive({{"POSITION", pos}}, b.indices({0, 1, 2}));
    b.doc()["accessors"][pos]["count"] = 4000000000u;  // was std::bad_alloc (exit 3), 48 GB asked for
    const std::string path = b.write(dir, "lying");
    expect_error([&] { read_gltf(path); }, Error::Kind::format, {"lying.gltf", "POSITION", "4000000000", "exceed"});
}

TEST(GltfReader, SparseOnlyAccessorCannotOutgrowTheData) {
    test::ScratchDir dir("gltf-sparse-huge");
    GltfBuilder b;
    const int idx = b.accessor(std::vector<std::uint8_t>{0, 0, 0, 0}, 5121, "SCALAR", 1);
    const int val = b.floats({1, 2, 3}, "VEC3", 3);
    json& doc = b.doc();
    doc["accessors"].push_back({{"componentType", 5126}, {"count", 3000000000u}, {"type", "VEC3"},
                                {"sparse", {{"count", 1},
                                            {"indices", {{"bufferView", doc["accessors"][idx]["bufferView"]}, {"componentType", 5121}}},
                                            {"values", {{"bufferView", doc["accessors"][val]["bufferView"]}}}}}});
    b.primitive({{"POSITION", static_cast<int>(doc["accessors"].size() - 1)}});
    const std::string path = b.write(dir, "sparse");
    expect_error([&] { read_gltf(path); }, Error::Kind::format, {"sparse.gltf", "without a bufferView"});
}

TEST(GltfReader, NonFinitePositionIsInvalidNamingTheVertex) {
    test::ScratchDir dir("gltf-nan");
    GltfBuilder b;
    std::vector<float> quad = kQuad;
    quad[7] = std::numeric_limits<float>::quiet_NaN();  // vertex 2, y
    const int pos = b.floats(quad, "VEC3", 3);
    b.primitive({{"POSITION", pos}}, b.indices({0, 1, 2, 0, 2, 3}));
    const std::string path = b.write(dir, "nan");
    // read_gltf itself refuses it (before, only read_mesh's validation did, and `info` showed the mesh).
    expect_error([&] { read_gltf(path); }, Error::Kind::invalid, {"nan.gltf", "POSITION", "vertex 2", "not finite"});
}

// Hostile input (issue 32): each of these crashed, asked for gigabytes or read the wrong data before.
TEST(GltfReader, NodesNestedTenThousandDeepAreWalkedWithoutRecursion) {
    test::ScratchDir dir("gltf-deep-nodes");
    GltfBuilder b;
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}}, b.indices({0, 1, 2, 0, 2, 3}));
    json& doc = b.doc();
    constexpr int kDepth = 10000;
    doc["nodes"] = json::array();
    for (int i = 0; i + 1 < kDepth; ++i) doc["nodes"].push_back({{"children", json::array({i + 1})}, {"translation", {1, 0, 0}}});
    doc["nodes"].push_back({{"mesh", 0}});
    const Mesh mesh = read_gltf(b.write(dir, "deep"));  // was SIGSEGV in the recursive scene walk
    EXPECT_EQ(mesh.triangle_count(), 2u);
    // Every level's translation applies: the quad sits 9999 units along x.
    EXPECT_FLOAT_EQ(mesh.bounds().min.x, static_cast<float>(kDepth - 1));
}

TEST(GltfReader, NodeCycleDeepInTheHierarchyIsAFormatError) {
    test::ScratchDir dir("gltf-deep-cycle");
    GltfBuilder b;
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}});
    json& doc = b.doc();
    doc["nodes"] = json::array();
    for (int i = 0; i < 3000; ++i) doc["nodes"].push_back({{"children", json::array({(i + 1) % 3000})}});
    expect_error([&] { read_gltf(b.write(dir, "cycle")); }, Error::Kind::format, {"cycle.gltf", "cycle"});
}

TEST(GltfReader, JsonNestedFiftyThousandDeepIsRefusedBeforeParsing) {
    test::ScratchDir dir("gltf-deep-json");
    GltfBuilder b;
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}});
    b.write(dir, "deep");
    std::string text = b.doc().dump();
    text.pop_back();  // the closing brace
    text += ",\"extras\":" + std::string(50000, '[') + std::string(50000, ']') + "}";
    test::write_text(dir.file("deep.gltf"), text);  // was SIGSEGV inside tinygltf's JSON conversion
    expect_error([&] { read_gltf(dir.file("deep.gltf")); }, Error::Kind::format, {"deep.gltf", "nested deeper than 256"});
    // The same depth inside a GLB's JSON chunk.
    const std::string glb = dir.file("deep.glb");
    std::string chunk = text;
    while (chunk.size() % 4) chunk += ' ';
    std::vector<std::uint8_t> bytes = {'g', 'l', 'T', 'F', 2, 0, 0, 0};
    auto u32 = [&](std::uint32_t v) { for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i))); };
    u32(static_cast<std::uint32_t>(20 + chunk.size()));
    u32(static_cast<std::uint32_t>(chunk.size()));
    u32(0x4E4F534Au);
    bytes.insert(bytes.end(), chunk.begin(), chunk.end());
    test::write_bytes(glb, bytes);
    expect_error([&] { read_gltf(glb); }, Error::Kind::format, {"deep.glb", "nested deeper"});
}

TEST(GltfReader, HugeSparseCountIsRefusedBeforeAnyAllocation) {
    test::ScratchDir dir("gltf-sparse-2e9");
    GltfBuilder b;
    const int idx = b.accessor(std::vector<std::uint32_t>{0, 1, 2}, 5125, "SCALAR", 3);
    const int val = b.floats({1, 2, 3}, "VEC3", 3);
    json& doc = b.doc();
    // No bufferView, count and sparse count 2e9: read_floats asked for 24 GB before checking the views.
    doc["accessors"].push_back({{"componentType", 5126}, {"count", 2000000000u}, {"type", "VEC3"},
                                {"sparse", {{"count", 2000000000u},
                                            {"indices", {{"bufferView", doc["accessors"][idx]["bufferView"]}, {"componentType", 5125}}},
                                            {"values", {{"bufferView", doc["accessors"][val]["bufferView"]}}}}}});
    b.primitive({{"POSITION", static_cast<int>(doc["accessors"].size() - 1)}});
    expect_error([&] { read_gltf(b.write(dir, "huge")); }, Error::Kind::format, {"huge.gltf", "sparse", "exceed"});
}

TEST(GltfReader, SparseCountAboveTheAccessorCountIsAFormatError) {
    test::ScratchDir dir("gltf-sparse-over");
    GltfBuilder b;
    const int pos = b.floats(kQuad, "VEC3", 3);
    const int idx = b.accessor(std::vector<std::uint8_t>{0, 1, 2, 3, 0, 1, 2, 3}, 5121, "SCALAR", 8);
    const int val = b.floats(std::vector<float>(24, 0.5f), "VEC3", 3);
    json& doc = b.doc();
    doc["accessors"][pos]["sparse"] = {{"count", 8},
                                       {"indices", {{"bufferView", doc["accessors"][idx]["bufferView"]}, {"componentType", 5121}}},
                                       {"values", {{"bufferView", doc["accessors"][val]["bufferView"]}}}};
    b.primitive({{"POSITION", pos}}, b.indices({0, 1, 2}));
    expect_error([&] { read_gltf(b.write(dir, "over")); }, Error::Kind::format, {"over.gltf", "sparse count 8", "1..4"});
}

TEST(GltfReader, NegativeOrFractionalOffsetsAreFormatErrors) {
    test::ScratchDir dir("gltf-neg-offset");
    for (const auto& [member, value, needle] : {std::tuple<const char*, json, const char*>{"byteOffset", -12, "negative"},
                                                {"byteOffset", 1.5, "not an integer"},
                                                {"count", -3, "negative"}}) {
        GltfBuilder b;
        const int pos = b.floats(kQuad, "VEC3", 3);
        b.primitive({{"POSITION", pos}}, b.indices({0, 1, 2}));
        b.doc()["accessors"][pos][member] = value;  // tinygltf read a negative byteOffset as 0
        SCOPED_TRACE(member);
        expect_error([&] { read_gltf(b.write(dir, "neg")); }, Error::Kind::format, {"neg.gltf", member, needle});
    }
    // Author data in extras is not the schema's business.
    GltfBuilder b;
    b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}}, b.indices({0, 1, 2}));
    b.doc()["accessors"][0]["extras"] = {{"byteOffset", -1}, {"count", 0.5}};
    EXPECT_EQ(read_gltf(b.write(dir, "extras")).triangle_count(), 1u);
}

TEST(GltfReader, TransformOfTheWrongLengthIsAFormatError) {
    test::ScratchDir dir("gltf-matrix3");
    for (const char* member : {"matrix", "translation", "rotation", "scale"}) {
        GltfBuilder b;
        b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}}, b.indices({0, 1, 2}));
        b.doc()["nodes"][0][member] = {1, 2};  // a 3-number matrix was silently the identity
        SCOPED_TRACE(member);
        expect_error([&] { read_gltf(b.write(dir, "m")); }, Error::Kind::format, {"m.gltf", "node 0", member, "2 numbers"});
    }
}

TEST(GltfReader, GlbContainerVersionOtherThanTwoIsUnsupported) {
    const std::vector<std::uint8_t> glb = test::read_bytes(shared_data("tex-duck/glTF_Binary/Duck.glb"));
    ASSERT_GT(glb.size(), 20u);
    test::ScratchDir dir("gltf-glb-version");
    std::vector<std::uint8_t> v7 = glb;
    v7[4] = 7;
    test::write_bytes(dir.file("v7.glb"), v7);
    expect_error([&] { read_gltf(dir.file("v7.glb")); }, Error::Kind::unsupported, {"v7.glb", "version 7"});
}

TEST(GltfReader, NothingToImportIsAClearError) {
    test::ScratchDir dir("gltf-nothing");
    {
        GltfBuilder b;  // only POINTS and LINES: was an empty mesh that `convert` wrote as an unreadable OBJ
        b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}}, -1, 0);
        b.primitive({{"POSITION", b.floats(kQuad, "VEC3", 3)}}, -1, 1);
        const std::string path = b.write(dir, "points");
        expect_error([&] { read_gltf(path); }, Error::Kind::invalid, {"points.gltf", "no triangle primitives", "2 POINTS/LINES"});
    }
    test::write_text(dir.file("nomesh.gltf"), R"({"asset": {"version": "2.0"}})");
    expect_error([&] { read_gltf(dir.file("nomesh.gltf")); }, Error::Kind::invalid, {"nomesh.gltf", "no triangle geometry"});
    // glTF 1.0 parsed as an empty 2.0 model before.
    test::write_text(dir.file("v1.gltf"), R"({"asset": {"version": "1.0"}, "meshes": {}})");
    expect_error([&] { read_gltf(dir.file("v1.gltf")); }, Error::Kind::unsupported, {"v1.gltf", "'1.0'", "glTF 2.0"});
}


TEST(GltfReader, UndecodableDataUriErrorStaysShort) {
    test::ScratchDir dir("gltf-bad-uri");
    // A 30,000-character base64 payload broken at its end: tinygltf quotes all of it in its error.
    GltfBuilder b;
    const int pos = b.floats(std::vector<float>(7500, 0.f), "VEC3", 3);
    b.primitive({{"POSITION", pos}});
    json doc = load_json(b.write(dir, "uri"));
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + std::string(40000, 'A') + "*&^%";
    test::write_text(dir.file("uri.gltf"), doc.dump());
    try {
        read_gltf(dir.file("uri.gltf"));
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::format) << e.what();
        EXPECT_NE(std::string(e.what()).find("uri.gltf"), std::string::npos) << e.what();
        EXPECT_LT(std::string(e.what()).size(), 400u) << e.what();
    }
}

TEST(GltfReader, TextureTransformIsBakedIntoTheUvs) {
    test::ScratchDir dir("gltf-ktt");
    GltfBuilder b;
    const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int uv = b.floats({0, 0, 1, 0, 0.5f, 0.25f}, "VEC2", 2);
    b.primitive({{"POSITION", pos}, {"TEXCOORD_0", uv}})["material"] = 0;
    json& doc = b.doc();
    doc["images"] = json::array({{{"uri", "t.png"}}});
    doc["textures"] = json::array({{{"source", 0}}});
    // Rotation by 90°, scale 2 x 0.5, offset (0.25, 0.5): u' = 0.5 v + 0.25, v' = -2 u + 0.5.
    doc["materials"] = json::array({{{"pbrMetallicRoughness",
                                      {{"baseColorTexture",
                                        {{"index", 0},
                                         {"extensions", {{"KHR_texture_transform",
                                                          {{"offset", {0.25, 0.5}}, {"rotation", 1.5707963267948966},
                                                           {"scale", {2, 0.5}}}}}}}}}}}});
    doc["extensionsUsed"] = {"KHR_texture_transform"};
    doc["extensionsRequired"] = {"KHR_texture_transform"};  // refused before; applied now
    const Mesh mesh = read_gltf(b.write(dir, "ktt"));
    ASSERT_EQ(mesh.texcoords.size(), 1u);
    // Stored v-up: v_stored = 1 - v'. Corner 1 (1, 0): u' = 0.25, v' = -1.5. Corner 2 (0.5, 0.25): u' = 0.375, v' = -0.5.
    EXPECT_NEAR(mesh.texcoords[0][0].x, 0.25f, 1e-6f);
    EXPECT_NEAR(mesh.texcoords[0][0].y, 0.5f, 1e-6f);
    EXPECT_NEAR(mesh.texcoords[0][1].x, 0.25f, 1e-6f);
    EXPECT_NEAR(mesh.texcoords[0][1].y, 2.5f, 1e-6f);
    EXPECT_NEAR(mesh.texcoords[0][2].x, 0.375f, 1e-6f);
    EXPECT_NEAR(mesh.texcoords[0][2].y, 1.5f, 1e-6f);
}

}  // namespace
}  // namespace lodforge

namespace lodforge {
namespace {


TEST(GltfReader, ReportsProgressAndHonoursCancel) {
    test::RecordingProgress progress;
    read_gltf(test::shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"), &progress);
    ASSERT_GE(progress.fractions.size(), 2u);
    EXPECT_TRUE(std::is_sorted(progress.fractions.begin(), progress.fractions.end()));
    EXPECT_EQ(progress.fractions.back(), 1.0);
    CancelFlagProgress cancel;
    cancel.cancel();
    test::expect_error([&] { read_gltf(test::shared_data("tex-duck/glTF/Duck.gltf"), &cancel); },
                       Error::Kind::cancelled, {});
}

}  // namespace
}  // namespace lodforge

TEST(GltfInstances, StoredModeNotesExtraInstancesAndViewerModePlacesThem) {
    const std::string path = lodforge::test::shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf");
    const lodforge::Mesh stored = lodforge::read_gltf(path);
    EXPECT_EQ(stored.point_count(), 2978u);
    ASSERT_FALSE(stored.warnings.empty());
    EXPECT_NE(stored.warnings.front().find("instanced by 2 nodes"), std::string::npos) << stored.warnings.front();

    lodforge::GltfReadOptions all;
    all.place_every_instance = true;
    const lodforge::Mesh placed = lodforge::read_gltf(path, nullptr, all);
    // The wheel mesh appears twice: the extra copy adds its points and triangles once more.
    EXPECT_GT(placed.point_count(), stored.point_count());
    EXPECT_GT(placed.triangle_count(), stored.triangle_count());
    EXPECT_TRUE(placed.warnings.empty());
    // The copy sits elsewhere, not stacked on the first: it adds new distinct positions.
    auto distinct = [](const lodforge::Mesh& m) {
        std::set<std::tuple<float, float, float>> s;
        for (const auto& p : m.positions) s.insert({p.x, p.y, p.z});
        return s.size();
    };
    EXPECT_GT(distinct(placed), distinct(stored));
}
