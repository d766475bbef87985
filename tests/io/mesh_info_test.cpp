#include "lodforge/io/mesh_info.h"
#include "lodforge/io/mesh_io.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

using namespace lodforge;

TEST(MeshInfo, JsonOfTheSpotSampleHasCountsAttributesTextureAndBounds) {
    const std::string path = test::sample("spot/spot_triangulated.obj");
    const MeshInfo info = mesh_info(read_mesh(path), path, "OBJ");
    const auto j = nlohmann::json::parse(to_json(info));
    EXPECT_EQ(j["vertices"], 2930);
    EXPECT_EQ(j["triangles"], 5856);
    EXPECT_GT(j["wedges"].get<int>(), 2930) << "UV seams must be split into wedges";
    const auto attrs = j["attributes"].get<std::vector<std::string>>();
    EXPECT_NE(std::find(attrs.begin(), attrs.end(), "texcoord0"), attrs.end());
    ASSERT_EQ(j["textures"].size(), 1u);
    EXPECT_NE(j["textures"][0].get<std::string>().find("spot_texture.png"), std::string::npos);
    EXPECT_TRUE(j["missing_textures"].empty());
    ASSERT_TRUE(j["bounds"].is_object());
    EXPECT_GT(j["bounds"]["diagonal"].get<double>(), 1.0);
}

TEST(MeshInfo, MissingTexturesAreListed) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    m.source_dir = "/nonexistent-dir";
    Material material;
    material.base_color_texture.path = "gone.png";
    m.materials.push_back(material);
    const MeshInfo info = mesh_info(m);
    ASSERT_EQ(info.missing_textures.size(), 1u);
    EXPECT_EQ(info.missing_textures[0], "/nonexistent-dir/gone.png");
    EXPECT_NE(to_text(info).find("MISSING"), std::string::npos);
}

TEST(MeshInfo, ImporterWarningsReachTheReport) {
    test::ScratchDir dir("info-warnings");
    {
        std::ofstream out(dir.file("lonely.obj"));
        out << "mtllib nothere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    }
    const MeshInfo info = mesh_info(read_mesh(dir.file("lonely.obj")));
    ASSERT_FALSE(info.warnings.empty());
    EXPECT_NE(info.warnings.front().find("nothere.mtl"), std::string::npos) << info.warnings.front();
    EXPECT_NE(to_text(info).find("nothere.mtl"), std::string::npos);
    const auto j = nlohmann::json::parse(to_json(info));
    EXPECT_FALSE(j["warnings"].empty());
}
