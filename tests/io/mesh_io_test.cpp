#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <fstream>

using namespace lodforge;

namespace {
Error::Kind error_kind_of(const std::function<void()>& f, std::string* message = nullptr) {
    try {
        f();
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.kind();
    }
    ADD_FAILURE() << "no lodforge::Error thrown";
    return Error::Kind::argument;
}
}  // namespace

TEST(MeshIo, FormatFromExtensionIsCaseInsensitive) {
    EXPECT_EQ(format_from_extension("a/b.PLY"), FileFormat::ply);
    EXPECT_EQ(format_from_extension("b.Obj"), FileFormat::obj);
    EXPECT_EQ(format_from_extension("c.gltf"), FileFormat::gltf);
    EXPECT_EQ(format_from_extension("d.GLB"), FileFormat::glb);
    EXPECT_EQ(format_from_extension("e.stl"), FileFormat::unknown);
}

TEST(MeshIo, DetectsFormatByMagicWhenTheExtensionSaysNothing) {
    test::ScratchDir dir("magic");
    { std::ofstream(dir.file("scan.dat")) << "ply\nformat ascii 1.0\nend_header\n"; }
    { std::ofstream(dir.file("model.bin")) << "glTF\x02\0\0\0"; }
    { std::ofstream(dir.file("other.dat")) << "hello"; }
    EXPECT_EQ(detect_format(dir.file("scan.dat")), FileFormat::ply);
    EXPECT_EQ(detect_format(dir.file("model.bin")), FileFormat::glb);
    EXPECT_EQ(detect_format(dir.file("other.dat")), FileFormat::unknown);
}

TEST(MeshIo, MissingFileDirectoryAndUnknownFormatAreClearErrors) {
    test::ScratchDir dir("errors");
    std::string msg;
    EXPECT_EQ(error_kind_of([&] { read_mesh(dir.file("absent.ply")); }, &msg), Error::Kind::io);
    EXPECT_NE(msg.find("absent.ply: no such file"), std::string::npos) << msg;
    EXPECT_EQ(error_kind_of([&] { read_mesh(dir.path().string()); }, &msg), Error::Kind::io);
    EXPECT_NE(msg.find("directory"), std::string::npos) << msg;
    { std::ofstream(dir.file("notes.txt")) << "not a mesh"; }
    EXPECT_EQ(error_kind_of([&] { read_mesh(dir.file("notes.txt")); }, &msg), Error::Kind::unsupported);
    EXPECT_NE(msg.find("notes.txt"), std::string::npos) << msg;
}

TEST(MeshIo, WritingAnUnsupportedFormatIsRefusedWithoutCreatingAFile) {
    test::ScratchDir dir("write-unsupported");
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    EXPECT_EQ(error_kind_of([&] { write_mesh(m, dir.file("out.stl")); }), Error::Kind::unsupported);
    EXPECT_FALSE(std::filesystem::exists(dir.file("out.stl")));
}

TEST(MeshIo, ValidationRejectsNaNPositionsNamingTheFile) {
    test::ScratchDir dir("nan");
    {
        std::ofstream out(dir.file("nan.ply"));
        out << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
               "0 0 0\nnan 1 0\n0 1 0\n3 0 1 2\n";
    }
    std::string msg;
    EXPECT_EQ(error_kind_of([&] { read_mesh(dir.file("nan.ply")); }, &msg), Error::Kind::invalid);
    EXPECT_NE(msg.find("nan.ply"), std::string::npos) << msg;
}

TEST(MeshIo, ConvertsBetweenPlyAndObjKeepingCounts) {
    test::ScratchDir dir("convert");
    const Mesh bunny = read_mesh(test::shared_data("scan-bunny/bun_zipper.ply"));
    write_mesh(bunny, dir.file("bunny.obj"));
    const Mesh via_obj = read_mesh(dir.file("bunny.obj"));
    EXPECT_EQ(via_obj.point_count(), bunny.point_count());
    EXPECT_EQ(via_obj.triangle_count(), bunny.triangle_count());
    write_mesh(via_obj, dir.file("bunny.ply"));
    const Mesh back = read_mesh(dir.file("bunny.ply"));
    ASSERT_EQ(back.positions.size(), bunny.positions.size());
    EXPECT_EQ(back.indices, bunny.indices);
    for (std::size_t i = 0; i < bunny.positions.size(); i += 97) EXPECT_EQ(back.positions[i], bunny.positions[i]);
}
