// Every real PLY in ../shared/data imports with the counts its README lists.

#include "ply_test_util.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

using namespace lodforge;
using lodforge::test::shared_data;

namespace {

struct Expected {
    const char* path;
    std::size_t vertices;  // stored (points)
    std::size_t triangles;
    bool normals, colors, texcoords;
};

void expect_counts(const Expected& e) {
    SCOPED_TRACE(e.path);
    const Mesh mesh = read_ply(shared_data(e.path));
    EXPECT_EQ(mesh.point_count(), e.vertices);
    EXPECT_EQ(mesh.triangle_count(), e.triangles);
    EXPECT_EQ(mesh.has_normals(), e.normals);
    EXPECT_EQ(mesh.has_colors(), e.colors);
    EXPECT_EQ(mesh.has_texcoords(), e.texcoords);
    for (std::uint32_t i : mesh.indices) ASSERT_LT(i, mesh.vertex_count());
    for (const Vec3f& p : mesh.positions) ASSERT_TRUE(is_finite(p));
    EXPECT_FALSE(mesh.bounds().empty());
}

}  // namespace

TEST(PlyRealFiles, BunnyWithExtraScalars) {
    expect_counts({"scan-bunny/bun_zipper.ply", 35947, 69451, false, false, false});
    // confidence and intensity are skipped, x y z still land right: the first vertex of the file.
    const Mesh mesh = read_ply(shared_data("scan-bunny/bun_zipper.ply"));
    EXPECT_FLOAT_EQ(mesh.positions[0].x, -0.0378297f);
    EXPECT_FLOAT_EQ(mesh.positions[0].y, 0.12794f);
    EXPECT_FLOAT_EQ(mesh.positions[0].z, 0.00447467f);
}

TEST(PlyRealFiles, DragonResolutions) {
    expect_counts({"scan-dragon/dragon_vrip_res2.ply", 100250, 202520, false, false, false});
    expect_counts({"scan-dragon/dragon_vrip_res3.ply", 22998, 47794, false, false, false});
    expect_counts({"scan-dragon/dragon_vrip_res4.ply", 5205, 11102, false, false, false});
}

TEST(PlyRealFiles, DragonFullAscii) {
    expect_counts({"scan-dragon/dragon_vrip.ply", 437645, 871414, false, false, false});
}

TEST(PlyRealFiles, HappyBuddhaAndLucy) {
    expect_counts({"scan-happy-buddha/happy_vrip_res3.ply", 32328, 67240, false, false, false});
    expect_counts({"scan-lucy100k/Lucy100k.ply", 50002, 100000, false, false, false});
}

TEST(PlyRealFiles, Frag115NormalsAndColours) {
    expect_counts({"color-open3d-frag115/frag_115.ply", 64365, 127229, true, true, false});
    const Mesh mesh = read_ply(shared_data("color-open3d-frag115/frag_115.ply"));
    bool some_colour = false;
    for (const Vec4f& c : mesh.colors) {
        ASSERT_GE(c.x, 0.f);
        ASSERT_LE(c.x, 1.f);
        ASSERT_EQ(c.w, 1.f);  // no alpha in the file
        // uchar / 255 exactly
        ASSERT_FLOAT_EQ(c.y * 255.f, std::round(c.y * 255.f));
        some_colour |= c.x > 0.f;
    }
    EXPECT_TRUE(some_colour);
    for (const Vec3f& n : mesh.normals) ASSERT_NEAR(length(n), 1.f, 1e-3f);
}

TEST(PlyRealFiles, ColorSmallWithAlpha) {
    expect_counts({"color-open3d-small/color.ply", 3017, 5537, true, true, false});
    PlyReader reader(shared_data("color-open3d-small/color.ply"));
    EXPECT_TRUE(reader.vertex_attributes().alpha);
    EXPECT_EQ(reader.header().format, PlyEncoding::binary_little_endian);
}

TEST(PlyRealFiles, WedgeTexcoordFilesSplitSeams) {
    struct Case {
        const char* path;
        std::size_t vertices, triangles;
        const char* texture;
    };
    for (const Case& c : {Case{"tex-ply-wedge-uv/matteonormb.ply", 292, 500, "matteonormb.png"},
                          Case{"tex-ply-wedge-uv/laurana500.ply", 266, 494, "laurana500.png"}}) {
        SCOPED_TRACE(c.path);
        const std::string path = shared_data(c.path);
        const Mesh mesh = read_ply(path);
        EXPECT_EQ(mesh.point_count(), c.vertices);
        EXPECT_EQ(mesh.triangle_count(), c.triangles);
        EXPECT_GT(mesh.vertex_count(), c.vertices);  // seams were split
        ASSERT_EQ(mesh.texcoords.size(), 1u);
        ASSERT_EQ(mesh.texcoords[0].size(), mesh.vertex_count());
        ASSERT_EQ(mesh.position_ids.size(), mesh.vertex_count());
        for (std::size_t i = 0; i < c.vertices; ++i) ASSERT_EQ(mesh.position_ids[i], i);
        for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
            ASSERT_EQ(mesh.positions[i], mesh.positions[mesh.position_ids[i]]);
        ASSERT_EQ(mesh.materials.size(), 1u);
        EXPECT_EQ(mesh.materials[0].base_color_texture.path, c.texture);
        EXPECT_EQ(mesh.face_materials, std::vector<std::uint32_t>(mesh.triangle_count(), 0u));
        EXPECT_TRUE(std::filesystem::exists(mesh.resolve_texture_path(mesh.materials[0].base_color_texture)));

        // Every corner samples exactly the UV the file gives that corner, and uses its stored point.
        PlyReader reader(path);
        PlyFaceChunk faces;
        while (reader.current_element()) {
            if (reader.at_faces()) reader.read_faces(100, faces);
            else reader.skip_element();
        }
        ASSERT_EQ(faces.corner_texcoords.size(), mesh.indices.size());
        for (std::size_t k = 0; k < mesh.indices.size(); ++k) {
            ASSERT_EQ(mesh.texcoords[0][mesh.indices[k]], faces.corner_texcoords[k]) << "corner " << k;
            ASSERT_EQ(mesh.position_ids[mesh.indices[k]], faces.indices[k]) << "corner " << k;
        }
        // No two wedges of one point carry the same UV (splitting reuses copies).
        std::map<std::pair<std::uint32_t, std::pair<float, float>>, int> seen;
        for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
            const auto key = std::make_pair(mesh.position_ids[i], std::make_pair(mesh.texcoords[0][i].x, mesh.texcoords[0][i].y));
            ASSERT_EQ(seen[key]++, 0) << "vertex " << i;
        }
    }
}

TEST(PlyRealFiles, HeaderModelOfTheWedgeFile) {
    PlyReader reader(shared_data("tex-ply-wedge-uv/matteonormb.ply"));
    const PlyHeader& h = reader.header();
    EXPECT_EQ(h.format, PlyEncoding::ascii);
    EXPECT_EQ(h.version, "1.0");
    ASSERT_EQ(h.elements.size(), 2u);
    EXPECT_EQ(h.elements[0].name, "vertex");
    EXPECT_EQ(h.elements[0].count, 292u);
    ASSERT_EQ(h.elements[1].properties.size(), 2u);
    EXPECT_EQ(h.elements[1].properties[1].name, "texcoord");
    EXPECT_EQ(h.elements[1].properties[1].count_type, PlyType::uint8);
    EXPECT_EQ(h.elements[1].properties[1].type, PlyType::float32);
    EXPECT_EQ(h.texture_files, std::vector<std::string>{"matteonormb.png"});
    EXPECT_EQ(h.comments.size(), 7u);
    EXPECT_TRUE(reader.has_corner_texcoords());
    EXPECT_FALSE(reader.has_texnumbers());
    EXPECT_EQ(reader.position(), h.data_offset);
}
