// The GLB writer on the real textured, coloured and multi-material meshes: every file passes the
// Khronos validator, and what a loader reads back (levels, triangles, images, colours, UVs) is what
// was written.
#include "pack_test_util.h"
#include "support/test_paths.h"

#include "lodforge/error.h"
#include "lodforge/io/gltf_writer.h"
#include "lodforge/io/image_decode.h"
#include "lodforge/simplify/lod_chain.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/simplify/simplify_cluster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace {

using namespace lodforge;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;

struct Model {
    const char* name;
    const char* path;
    std::size_t images;      // distinct images the materials use
    std::size_t materials;
};

// Printed by gtest for parameter names.
void PrintTo(const Model& m, std::ostream* os) { *os << m.name; }

const Model kModels[] = {
    {"spot", "tex-spot/spot_triangulated.obj", 1, 1},
    {"duck", "tex-duck/glTF/Duck.gltf", 1, 1},
    {"duckglb", "tex-duck/glTF_Binary/Duck.glb", 1, 1},  // texture bytes embedded in the source
    {"frag115", "color-open3d-frag115/frag_115.ply", 0, 0},
    {"milktruck", "tex-cesium-milk-truck/CesiumMilkTruck.gltf", 1, 4},
    {"waterbottle", "tex-water-bottle/WaterBottle.gltf", 5, 1},
};

LodChainResult chain_of(const Mesh& mesh, std::vector<float> ratios) {
    LodChainParams p;
    p.levels = lod_levels_from_ratios(ratios);
    p.measure = false;
    return build_lod_chain(mesh, p);
}

class GlbModels : public ::testing::TestWithParam<Model> {};

TEST_P(GlbModels, SharedChainValidatesAndReloads) {
    const Model& model = GetParam();
    const Mesh mesh = read_mesh(shared_data(model.path));
    const LodChainResult chain = chain_of(mesh, {0.5f, 0.2f});
    ScratchDir dir(std::string("glb-") + model.name);
    const std::string path = dir.file("out.glb");
    GlbOptions options;
    options.name = model.name;
    options.screen_coverage = {0.4, 0.05, 0};
    const GlbResult written = write_glb(chain.shared, options, path);
    EXPECT_TRUE(written.warnings.empty()) << written.warnings.front();

    const auto v = test::validate_gltf(path);
    ASSERT_EQ(v.exit_code, 0) << v.raw;
    EXPECT_EQ(v.report["errors"], 0) << v.raw;
    EXPECT_EQ(test::unexplained_warnings(v), std::vector<std::string>{}) << v.raw;

    const auto bytes = test::read_bytes(path);
    EXPECT_EQ(bytes.size(), written.bytes);
    const test::Glb g = test::split_glb(bytes);
    ASSERT_TRUE(g.json.is_object());
    EXPECT_EQ(g.json["scenes"][0]["nodes"], nlohmann::json::array({0}));
    EXPECT_EQ(test::lod_ids(g), (std::vector<std::size_t>{1, 2}));
    EXPECT_EQ(g.json["nodes"][0]["extras"]["MSFT_screencoverage"], nlohmann::json::array({0.4, 0.05, 0}));
    EXPECT_EQ(g.json["extensionsUsed"], nlohmann::json::array({"MSFT_lod"}));
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(test::node_triangles(g, k), chain.levels[k].triangles) << k;
    // One vertex buffer: every level's POSITION views the same bufferView.
    auto position_view = [&](std::size_t node) {
        const auto& prim = g.json["meshes"][g.json["nodes"][node]["mesh"].get<std::size_t>()]["primitives"][0];
        return g.json["accessors"][prim["attributes"]["POSITION"].get<std::size_t>()]["bufferView"];
    };
    EXPECT_EQ(position_view(0), position_view(2));
    for (const auto& view : g.json["bufferViews"]) EXPECT_EQ(view["byteOffset"].get<std::size_t>() % 4, 0u);
    EXPECT_EQ(bytes.size() % 4, 0u);

    // Textures embedded, each decodes to a real image.
    const std::size_t images = g.json.contains("images") ? g.json["images"].size() : 0;
    EXPECT_EQ(images, model.images);
    EXPECT_EQ(written.images, model.images);
    for (std::size_t i = 0; i < images; ++i) {
        TextureRef ref;
        ref.bytes = test::image_bytes(g, i);
        const Image img = decode_texture(Mesh{}, ref);
        EXPECT_GT(img.width, 0);
        EXPECT_GT(img.height, 0);
    }
    const std::size_t materials = g.json.contains("materials") ? g.json["materials"].size() : 0;
    EXPECT_EQ(materials, model.materials);

    // A glTF reader sees level 0 (MSFT_lod is optional) with the attributes of the input vertices.
    const Mesh back = read_mesh(path);
    EXPECT_EQ(back.triangle_count(), mesh.triangle_count());
    ASSERT_EQ(back.vertex_count(), chain.shared.vertices.vertex_count());
    EXPECT_EQ(back.has_colors(), mesh.has_colors());
    EXPECT_EQ(back.texcoords.size(), mesh.texcoords.size());
    // (the reader gives material-less primitives a default material)
    EXPECT_EQ(back.materials.size(), std::max<std::size_t>(model.materials, 1));
    double worst_color = 0, worst_uv = 0, worst_pos = 0;
    for (std::size_t i = 0; i < back.vertex_count(); ++i) {
        const std::uint32_t in = chain.shared.input_vertex[i];
        worst_pos = std::max(worst_pos, double(length(back.positions[i] - mesh.positions[in])));
        if (mesh.has_colors()) {
            const Vec4f a = back.colors[i], b = mesh.colors[in];
            worst_color = std::max({worst_color, double(std::fabs(a.x - b.x)), double(std::fabs(a.y - b.y)),
                                    double(std::fabs(a.z - b.z))});
        }
        for (std::size_t s = 0; s < mesh.texcoords.size(); ++s) {
            const Vec2f a = back.texcoords[s][i], b = mesh.texcoords[s][in];
            worst_uv = std::max({worst_uv, double(std::fabs(a.x - b.x)), double(std::fabs(a.y - b.y))});
        }
    }
    EXPECT_EQ(worst_pos, 0.0);
    EXPECT_LE(worst_color, 1e-6);
    EXPECT_LE(worst_uv, 1e-6);  // v flipped on write and flipped back on read
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, GlbModels, ::testing::ValuesIn(kModels),
                         [](const ::testing::TestParamInfo<Model>& p) { return std::string(p.param.name); });

TEST(GltfWriter, IndependentLevelsValidateAndShareMaterialsAndImages) {
    const Mesh mesh = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
    std::vector<Mesh> levels{mesh};
    for (float r : {0.3f, 0.05f}) {
        ClusterParams p;
        p.target_ratio = r;
        levels.push_back(simplify_cluster(mesh, p).mesh);
    }
    ScratchDir dir("glb-cluster");
    const std::string path = dir.file("cluster.glb");
    const GlbResult r = write_glb(levels, {}, path);
    EXPECT_EQ(r.levels, 3u);
    EXPECT_EQ(r.materials, 1u);
    EXPECT_EQ(r.images, 1u);
    const auto v = test::validate_gltf(path);
    ASSERT_EQ(v.exit_code, 0) << v.raw;
    EXPECT_EQ(test::unexplained_warnings(v), std::vector<std::string>{}) << v.raw;
    const test::Glb g = test::split_glb(test::read_bytes(path));
    EXPECT_EQ(test::lod_ids(g), (std::vector<std::size_t>{1, 2}));
    EXPECT_FALSE(g.json["nodes"][0].contains("extras"));  // no coverage given, none written
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(test::node_triangles(g, k), levels[k].triangle_count());
}

TEST(GltfWriter, SingleLevelHasNoLodExtension) {
    const Mesh mesh = read_mesh(shared_data("tex-duck/glTF/Duck.gltf"));
    ScratchDir dir("glb-single");
    write_glb(std::vector<Mesh>{mesh}, {}, dir.file("duck.glb"));
    const auto v = test::validate_gltf(dir.file("duck.glb"));
    ASSERT_EQ(v.exit_code, 0) << v.raw;
    EXPECT_EQ(v.report["warnings"], 0) << v.raw;
    EXPECT_TRUE(test::lod_ids(test::split_glb(test::read_bytes(dir.file("duck.glb")))).empty());
}

TEST(GltfWriter, MissingTextureIsAnErrorNamingTheFileOrAWarningWhenAsked) {
    Mesh mesh = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
    ASSERT_FALSE(mesh.materials.empty());
    mesh.materials[0].base_color_texture.path = "no_such_texture.png";
    ScratchDir dir("glb-missing");
    const std::string path = dir.file("spot.glb");
    try {
        write_glb(std::vector<Mesh>{mesh}, {}, path);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::io);
        EXPECT_NE(std::string(e.what()).find("no_such_texture.png"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));

    GlbOptions skip;
    skip.skip_missing_textures = true;
    const GlbResult r = write_glb(std::vector<Mesh>{mesh}, skip, path);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("no_such_texture.png"), std::string::npos);
    EXPECT_EQ(r.images, 0u);
    EXPECT_EQ(test::validate_gltf(path).exit_code, 0);
}

TEST(GltfWriter, NonPngJpegTextureIsUnsupported) {
    Mesh mesh = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
    mesh.materials[0].base_color_texture = TextureRef{};
    mesh.materials[0].base_color_texture.bytes = {'B', 'M', 0, 0, 0, 0};
    try {
        encode_glb(std::vector<Mesh>{mesh}, {});
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::unsupported);
        EXPECT_NE(std::string(e.what()).find("PNG"), std::string::npos) << e.what();
    }
}

TEST(GltfWriter, BadLevelsAreRefusedWithoutWritingAFile) {
    const Mesh mesh = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
    ScratchDir dir("glb-bad");
    const std::string path = dir.file("bad.glb");
    auto kind_of = [&](const std::vector<Mesh>& levels, const GlbOptions& o) {
        try {
            write_glb(levels, o, path);
        } catch (const Error& e) {
            return e.kind();
        }
        return Error::Kind::io;  // not expected: no error
    };
    EXPECT_EQ(kind_of({}, {}), Error::Kind::argument);
    GlbOptions three;
    three.screen_coverage = {1, 0.5, 0};
    EXPECT_EQ(kind_of({mesh}, three), Error::Kind::argument);
    Mesh bad_material = mesh;
    bad_material.face_materials.assign(mesh.triangle_count(), 7);
    EXPECT_EQ(kind_of({bad_material}, {}), Error::Kind::invalid);
    Mesh bad_index = mesh;
    bad_index.indices[5] = static_cast<std::uint32_t>(mesh.vertex_count());
    EXPECT_EQ(kind_of({mesh, bad_index}, {}), Error::Kind::invalid);
    Mesh nan = mesh;
    nan.positions[3].y = NAN;
    EXPECT_EQ(kind_of({nan}, {}), Error::Kind::invalid);
    Mesh empty = mesh;
    empty.indices.clear();
    EXPECT_EQ(kind_of({mesh, empty}, {}), Error::Kind::invalid);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(GltfWriter, CancelLeavesNoFile) {
    const Mesh mesh = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
    ScratchDir dir("glb-cancel");
    CancelFlagProgress progress;
    progress.cancel();
    try {
        write_glb(std::vector<Mesh>{mesh}, {}, dir.file("c.glb"), &progress);
        FAIL() << "not cancelled";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::cancelled);
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(GltfWriter, OutOfRangeMaterialFactorsAreClampedToValidGltf) {
    Mesh mesh = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
    mesh.materials[0].base_color = {1.5f, -0.2f, 0.5f, 1.f};
    mesh.materials[0].emissive = {2.f, 0.f, NAN};
    mesh.materials[0].roughness = 3.f;
    ScratchDir dir("glb-factors");
    write_glb(std::vector<Mesh>{mesh}, {}, dir.file("f.glb"));
    const auto v = test::validate_gltf(dir.file("f.glb"));
    EXPECT_EQ(v.exit_code, 0) << v.raw;
    const test::Glb g = test::split_glb(test::read_bytes(dir.file("f.glb")));
    const auto& m = g.json["materials"][0];
    EXPECT_EQ(m["pbrMetallicRoughness"]["baseColorFactor"], nlohmann::json::array({1.0, 0.0, 0.5, 1.0}));
    EXPECT_EQ(m["emissiveFactor"], nlohmann::json::array({1.0, 0.0, 0.0}));
    EXPECT_EQ(m["pbrMetallicRoughness"]["roughnessFactor"], 1.0);
}

TEST(GltfWriter, SecondTexcoordSetZeroNormalsAndMissingSetBindings) {
    Mesh mesh = read_mesh(shared_data("tex-duck/glTF/Duck.gltf"));
    ASSERT_TRUE(mesh.has_normals());
    mesh.texcoords.push_back(mesh.texcoords[0]);
    for (Vec2f& uv : mesh.texcoords[1]) uv = {uv.x * 0.5f, uv.y * 0.5f};
    mesh.materials[0].base_color_texture.texcoord_set = 1;
    mesh.materials[0].emissive_texture = mesh.materials[0].base_color_texture;
    mesh.materials[0].emissive_texture.texcoord_set = 2;  // no such set: the binding is dropped
    mesh.normals[0] = {0, 0, 0};
    mesh.normals[1] = {3, 0, 0};
    ScratchDir dir("glb-uv1");
    const GlbResult r = write_glb(std::vector<Mesh>{mesh}, {}, dir.file("uv1.glb"));
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("texture coordinate set 2"), std::string::npos) << r.warnings[0];
    const auto v = test::validate_gltf(dir.file("uv1.glb"));
    ASSERT_EQ(v.exit_code, 0) << v.raw;
    EXPECT_EQ(v.report["warnings"], 0) << v.raw;
    const test::Glb g = test::split_glb(test::read_bytes(dir.file("uv1.glb")));
    const auto& material = g.json["materials"][0];
    EXPECT_EQ(material["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"], 1);
    EXPECT_FALSE(material.contains("emissiveTexture"));
    EXPECT_TRUE(g.json["meshes"][0]["primitives"][0]["attributes"].contains("TEXCOORD_1"));
    const Mesh back = read_mesh(dir.file("uv1.glb"));
    ASSERT_EQ(back.texcoords.size(), 2u);
    EXPECT_FLOAT_EQ(back.texcoords[1][5].y, mesh.texcoords[1][5].y);
    EXPECT_FLOAT_EQ(back.normals[1].x, 1.f);
    EXPECT_FLOAT_EQ(back.normals[0].z, 1.f);
}

TEST(GltfWriter, EncodingIsDeterministic) {
    const Mesh mesh = read_mesh(shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"));
    const LodChainResult chain = chain_of(mesh, {0.5f});
    GlbOptions o;
    o.screen_coverage = {0.1, 0};
    EXPECT_EQ(encode_glb(chain.shared, o), encode_glb(chain.shared, o));
}

}  // namespace
