// Hostile input (issue 32) that is not one reader's business: inputs that are not regular files, a
// binary PLY whose header lies low, OBJ material names with spaces, and the streaming vertex checks
// shared with validate(). The glTF cases are in gltf_reader_test.cpp.
#include "io_test_util.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/io/input_file.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/mesh_validate.h"
#include "lodforge/io/obj.h"
#include "lodforge/io/ply.h"
#include "lodforge/pack/preset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace lodforge {
namespace {
using test::expect_error;

// Each reader must refuse a FIFO before opening it (the open blocks until a writer comes) and a
// character device (read until memory runs out). Run in a thread so that a regression fails the test
// instead of hanging it.
TEST(HostileInput, FifoAndDeviceAreRefusedBeforeOpening) {
    test::ScratchDir dir("hostile-fifo");
    for (const char* name : {"in.ply", "in.obj", "in.gltf", "in.glb"}) {
        const std::string fifo = dir.file(name);
        ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
        auto result = std::async(std::launch::async, [&] {
            try {
                read_mesh(fifo);
            } catch (const Error& e) {
                return std::string(e.what());
            }
            return std::string("no error");
        });
        ASSERT_EQ(result.wait_for(std::chrono::seconds(20)), std::future_status::ready) << name << " blocked";
        const std::string message = result.get();
        EXPECT_NE(message.find(fifo), std::string::npos) << message;
        EXPECT_NE(message.find("not a regular file"), std::string::npos) << message;
    }
    expect_error([] { read_mesh("/dev/zero"); }, Error::Kind::io, {"/dev/zero", "not a regular file"});
    expect_error([] { read_ply("/dev/zero"); }, Error::Kind::io, {"/dev/zero", "not a regular file"});
    expect_error([] { check_input_file("/dev/null", "a preset file"); }, Error::Kind::io, {"/dev/null", "a preset file"});
    expect_error([&] { check_input_file(dir.path().string(), "a mesh file"); }, Error::Kind::io,
                 {"is a directory, not a mesh file"});
    expect_error([&] { check_input_file(dir.file("absent.ply"), "a mesh file"); }, Error::Kind::io, {"no such file"});
}

std::string float_bytes(std::initializer_list<float> values) {
    std::string out;
    for (float v : values) out.append(reinterpret_cast<const char*>(&v), sizeof v);
    return out;
}

// The header announces 3 vertices, the file holds 6: the face was read from vertex bytes (a 0-corner
// face, 0 triangles, "no problems found").
TEST(HostileInput, BinaryPlyHoldingMoreThanItsHeaderSaysIsAFormatError) {
    test::ScratchDir dir("hostile-ply-lying");
    const std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string vertices = float_bytes({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0, 1, 0, 1});
    std::string face(1, '\3');
    for (std::int32_t i : {0, 1, 2}) face.append(reinterpret_cast<const char*>(&i), 4);
    test::write_text(dir.file("lying.ply"), header + vertices + face);
    expect_error([&] { read_ply(dir.file("lying.ply")); }, Error::Kind::format,
                 {"lying.ply", "bytes of data follow the last element", "counts are smaller"});
    // The honest file reads, and a newline or a little zero padding after the data is tolerated.
    const std::string honest = header + vertices.substr(0, 36) + face;
    for (const std::string& tail : {std::string(), std::string("\n"), std::string(16, '\0')}) {
        test::write_text(dir.file("ok.ply"), honest + tail);
        EXPECT_EQ(read_ply(dir.file("ok.ply")).triangle_count(), 1u) << tail.size();
    }
}

TEST(HostileInput, ObjMaterialNamesWithSpacesKeepTheirMaterial) {
    test::ScratchDir dir("hostile-obj-spaces");
    test::write_text(dir.file("m.mtl"), "newmtl my red\nKd 1 0 0\nnewmtl my blue\nKd 0 0 1\nnewmtl plain\nKd 0 1 0\n");
    test::write_text(dir.file("m.obj"),
                     "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nusemtl my blue\nf 1 2 3\n"
                     "usemtl   my red  \r\nf 2 4 3\nusemtl plain\nf 1 3 4\n");
    const Mesh mesh = read_obj(dir.file("m.obj"));
    ASSERT_EQ(mesh.triangle_count(), 3u);
    ASSERT_EQ(mesh.face_materials.size(), 3u);
    auto name_of = [&](std::size_t face) { return mesh.materials.at(mesh.face_materials[face]).name; };
    EXPECT_EQ(name_of(0), "my blue");  // was the default material: tinyobjloader looked up "my"
    EXPECT_EQ(name_of(1), "my red");
    EXPECT_EQ(name_of(2), "plain");
    EXPECT_FLOAT_EQ(mesh.materials.at(mesh.face_materials[0]).base_color.z, 1.f);
}

TEST(HostileInput, StreamedVertexChunksGetValidatesErrors) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::vector<Vec3f> good = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    check_vertex_chunk("in.ply", 0, good);  // no throw
    std::vector<Vec3f> bad_position = good;
    bad_position[2].y = inf;
    expect_error([&] { check_vertex_chunk("in.ply", 100, bad_position); }, Error::Kind::invalid,
                 {"in.ply", "vertex 102", "coordinate"});
    std::vector<Vec3f> normals(3, Vec3f{0, 0, 1});
    normals[1].x = nan;
    expect_error([&] { check_vertex_chunk("in.ply", 0, good, normals); }, Error::Kind::invalid,
                 {"vertex 1", "normal, colour or texture coordinate"});
    std::vector<Vec4f> colors(3, Vec4f{1, 1, 1, 1});
    colors[0].w = nan;
    expect_error([&] { check_vertex_chunk("in.ply", 0, good, {}, colors); }, Error::Kind::invalid, {"vertex 0"});
    std::vector<Vec2f> uvs(3, Vec2f{0, 0});
    uvs[2].x = -inf;
    expect_error([&] { check_vertex_chunk("in.ply", 0, good, {}, {}, uvs); }, Error::Kind::invalid, {"vertex 2"});

    Bounds huge;
    huge.add({-1e38f, 0, 0});
    huge.add({1e38f, 1e38f, 0});
    expect_error([&] { check_extent("in.ply", huge); }, Error::Kind::invalid, {"in.ply", "coordinates too large"});
    check_extent("in.ply", Bounds{});  // empty: nothing to measure
    // validate() says the same about a whole mesh.
    Mesh mesh;
    mesh.positions = {{-1e38f, 0, 0}, {1e38f, 1e38f, 0}, {0, 0, 0}};
    mesh.indices = {0, 1, 2};
    const ValidationReport report = validate(mesh);
    ASSERT_NE(report.find("extent_overflow"), nullptr);
    EXPECT_NE(report.find("extent_overflow")->message.find("coordinates too large"), std::string::npos);
}

// A run killed by SIGKILL (or a power loss) cannot clean up; the next run removes what it left.
TEST(HostileInput, TemporariesOfDeadProcessesAreRemovedOnTheNextRun) {
    test::ScratchDir dir("hostile-stale");
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ASSERT_GT(child, 0);
    ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // `child` is now a PID without a process
    const std::string dead = std::to_string(child), live = std::to_string(::getppid());
    namespace fs = std::filesystem;
    auto make_dir = [&](const std::string& name) {
        fs::create_directories(dir.path() / name / "sub");
        test::write_text((dir.path() / name / "sub" / "soup").string(), "x");
    };
    const std::vector<std::string> stale = {".out.lfo.tmp-" + dead + "-0", ".lodforge-tmp-" + dead + "-3",
                                            ".pack.lodforge-tmp-" + dead + "-12", "lodforge-method-" + dead + "-1"};
    const std::vector<std::string> kept = {".out.lfo.tmp-" + live + "-0", ".lodforge-tmp-" + live + "-1",
                                           "out.lfo.tmp-" + dead + "-0",  // not hidden: a user's file
                                           ".notes.tmp-x-1", "mesh.ply", "lodforge-method-" + dead};
    test::write_text(dir.file(stale[0]), "partial");
    make_dir(stale[1]);
    make_dir(stale[2]);
    make_dir(stale[3]);
    for (const std::string& k : kept) test::write_text(dir.file(k), "keep");
    remove_stale_temporaries(dir.path().string());
    for (const std::string& s : stale) EXPECT_FALSE(fs::exists(dir.file(s))) << s;
    for (const std::string& k : kept) EXPECT_TRUE(fs::exists(dir.file(k))) << k;
    // AtomicFile does it for the directory it writes into.
    test::write_text(dir.file(stale[0]), "partial");
    AtomicFile out(dir.file("out.lfo"));
    out.stream() << "asset";
    out.commit();
    EXPECT_FALSE(fs::exists(dir.file(stale[0])));
}

TEST(HostileInput, PresetWithAHugeNumberOrThousandLevelsIsRefused) {
    // A 400-digit version was nlohmann's out_of_range: "internal error" (exit 3).
    expect_error([] { parse_preset("{\"version\": " + std::string(400, '9') + "}", "p.json"); }, Error::Kind::format,
                 {"p.json", "not valid JSON", "overflow"});
    auto with_levels = [](std::size_t n) {
        std::string text = "{\"version\": 1, \"levels\": [";
        for (std::size_t i = 0; i < n; ++i) text += (i ? ", " : "") + std::string("{\"triangles\": ") + std::to_string(10000 - i) + "}";
        return text + "]}";
    };
    // A thousand levels ran for minutes; the cap is checked before any level is read.
    expect_error([&] { parse_preset(with_levels(1000), "p.json"); }, Error::Kind::argument,
                 {"p.json", "levels", "1000", "at most 32"});
    EXPECT_EQ(parse_preset(with_levels(kMaxPresetLevels), "p.json").levels.size(), kMaxPresetLevels);
}

TEST(HostileInput, OutputThroughADanglingSymlinkCreatesItsDestination) {
    namespace fs = std::filesystem;
    test::ScratchDir dir("hostile-dangling");
    fs::create_directories(dir.path() / "assets");
    fs::create_symlink("assets/real.lfo", dir.path() / "link.lfo");  // relative, destination absent
    AtomicFile out(dir.file("link.lfo"));
    out.stream() << "asset";
    out.commit();
    EXPECT_TRUE(fs::is_symlink(dir.path() / "link.lfo")) << "the link was replaced by a file";
    EXPECT_EQ(test::read_bytes(dir.file("assets/real.lfo")).size(), 5u);
}

}  // namespace
}  // namespace lodforge
