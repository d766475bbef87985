// The morph model: loading keyframe sequences and glTF morph targets, blending in t.
#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/morph/morph.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace {

using namespace lodforge;
namespace fs = std::filesystem;

std::string horse_dir() { return test::shared_data("seq-horse-gallop"); }
std::string sphere() { return test::shared_data("morph-animated-morph-sphere/AnimatedMorphSphere.gltf"); }
std::string cube() { return test::shared_data("morph-animated-morph-cube/AnimatedMorphCube.gltf"); }

double diagonal_of(const std::vector<Vec3f>& p) {
    Bounds b;
    for (const Vec3f& x : p) b.add(x);
    return b.diagonal();
}

double max_distance(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
    double d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, double(length(a[i] - b[i])));
    return d;
}

Error::Kind kind_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.kind();
    }
    ADD_FAILURE() << "no error";
    return Error::Kind::argument;
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace

TEST(Morph, HorseEndpointsReproduceTheFirstAndLastFiles) {
    MorphLoadOptions o;
    o.frames = 6;
    const MorphMesh m = load_morph(horse_dir(), o);
    ASSERT_EQ(m.frame_count(), 6u);
    EXPECT_EQ(m.frame_names.front(), "0001.obj");
    EXPECT_EQ(m.frame_names.back(), "0048.obj");
    EXPECT_EQ(m.vertex_count(), 8431u);
    EXPECT_EQ(m.base.triangle_count(), 16843u);
    const Mesh first = read_mesh(horse_dir() + "/0001.obj");
    const Mesh last = read_mesh(horse_dir() + "/0048.obj");
    std::vector<Vec3f> p0, p1;
    morph_positions_at(m, 0.0, p0);
    morph_positions_at(m, 1.0, p1);
    const double diag = diagonal_of(first.positions);
    EXPECT_LE(max_distance(p0, first.positions), 1e-6 * diag);
    EXPECT_LE(max_distance(p1, last.positions), 1e-6 * diag);
    EXPECT_GT(max_distance(p0, p1), 1e-2 * diag);  // the gallop really moves
    EXPECT_FALSE(m.normals_from_input);            // the OBJ frames carry no normals: computed per frame
}

TEST(Morph, AllHorseFramesLoadAndKeyframesAreHit) {
    const MorphMesh m = load_morph(horse_dir());
    ASSERT_EQ(m.frame_count(), 48u);
    const Mesh f20 = read_mesh(horse_dir() + "/0021.obj");
    std::vector<Vec3f> p;
    morph_positions_at(m, 20.0 / 47.0, p);
    EXPECT_LE(max_distance(p, f20.positions), 1e-6 * diagonal_of(f20.positions));
}

TEST(Morph, BlendBetweenKeyframesIsExactLinearInterpolation) {
    MorphLoadOptions o;
    o.frames = 5;
    const MorphMesh m = load_morph(horse_dir(), o);
    const double t = (1.0 + 0.3) / 4.0;  // 30% of the way from keyframe 1 to 2
    const MorphSpan span = morph_span(m.frame_count(), t);
    EXPECT_EQ(span.frame, 1u);
    EXPECT_NEAR(span.s, 0.3, 1e-6);
    std::vector<Vec3f> p;
    morph_positions_at(m, t, p);
    const auto& a = m.frame_positions[1];
    const auto& b = m.frame_positions[2];
    double worst = 0;
    for (std::size_t v = 0; v < p.size(); ++v) {
        const Vec3f expected = a[v] * (1.f - span.s) + b[v] * span.s;
        worst = std::max(worst, double(length(p[v] - expected)));
    }
    EXPECT_EQ(worst, 0.0);
    // And the midpoint of the segment is the mean of its ends (independent of morph_span).
    morph_positions_at(m, 1.5 / 4.0, p);
    worst = 0;
    for (std::size_t v = 0; v < p.size(); ++v) worst = std::max(worst, double(length(p[v] - (a[v] + b[v]) * 0.5f)));
    EXPECT_LE(worst, 1e-6 * diagonal_of(a));
}

TEST(Morph, BlendedNormalsAreUnitLength) {
    MorphLoadOptions o;
    o.frames = 4;
    for (const MorphMesh& m : {load_morph(horse_dir(), o), load_morph(sphere())}) {
        for (double t : {0.0, 0.17, 0.5, 0.83, 1.0}) {
            std::vector<Vec3f> n;
            morph_normals_at(m, t, n);
            ASSERT_EQ(n.size(), m.vertex_count());
            for (const Vec3f& x : n) ASSERT_NEAR(length(x), 1.0, 1e-5) << m.source << " t=" << t;
        }
    }
}

TEST(Morph, ComputedNormalsPointOutOfTheHorse) {
    MorphLoadOptions o;
    o.frames = 2;
    const MorphMesh m = load_morph(horse_dir(), o);
    // On a closed surface, area-weighted outward normals point away from the centroid on average.
    Vec3f c{};
    for (const Vec3f& p : m.frame_positions[0]) c = c + p;
    c = c * (1.f / float(m.vertex_count()));
    double s = 0;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) s += dot(m.frame_normals[0][v], m.frame_positions[0][v] - c);
    EXPECT_GT(s, 0.0);
}

TEST(Morph, SphereTargetsAreReadAndAnimationKeysReproduced) {
    const MorphMesh m = load_morph(sphere());
    EXPECT_TRUE(m.normals_from_input);
    EXPECT_EQ(m.vertex_count(), 1876u);
    EXPECT_EQ(m.base.triangle_count(), 960u);
    ASSERT_EQ(m.frame_count(), 217u);  // the weights animation has 217 evenly spaced keys
    const Mesh plain = read_mesh(sphere());  // the glTF reader without morphing: the base shape
    const double diag = diagonal_of(plain.positions);
    // The animation starts and ends at weights (0, 0): both ends are the base shape.
    std::vector<Vec3f> p;
    morph_positions_at(m, 0.0, p);
    EXPECT_LE(max_distance(p, plain.positions), 1e-6 * diag);
    morph_positions_at(m, 1.0, p);
    EXPECT_LE(max_distance(p, plain.positions), 1e-6 * diag);
    // Somewhere in between the shape changes a lot (the targets are larger than the sphere).
    double most = 0;
    for (const auto& f : m.frame_positions) most = std::max(most, max_distance(f, plain.positions));
    EXPECT_GT(most, 0.5 * diag);
}

TEST(Morph, WithoutAnimationTheFramesAreBasePlusEachTarget) {
    MorphLoadOptions o;
    o.frames = 64;  // the animation resampled at 64 evenly spaced times
    EXPECT_EQ(load_morph(sphere(), o).frame_count(), 64u);
    const MorphMesh animated = load_morph(cube());
    EXPECT_EQ(animated.vertex_count(), 24u);
    EXPECT_EQ(animated.frame_count(), 127u);
    // The same cube with its animation removed: base, base + "thin", base + "angle".
    test::ScratchDir dir("morph-cube");
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(cube()));
    doc.erase("animations");
    std::ofstream(dir.file("cube.gltf")) << doc.dump();
    fs::copy_file(test::shared_data("morph-animated-morph-cube/AnimatedMorphCube.bin"), dir.file("AnimatedMorphCube.bin"));
    const MorphMesh m = load_morph(dir.file("cube.gltf"));
    ASSERT_EQ(m.frame_count(), 3u);
    EXPECT_EQ(m.frame_names[1], "target 0 'thin'");
    EXPECT_EQ(m.frame_names[2], "target 1 'angle'");
    EXPECT_TRUE(m.normals_from_input);
    const Mesh plain = read_mesh(cube());
    EXPECT_EQ(max_distance(m.frame_positions[0], plain.positions), 0.0);
    // Each target moves the cube's top by about its size (deltas up to 0.019 in a 0.02 cube, times 100).
    const double size = diagonal_of(plain.positions);
    EXPECT_GT(max_distance(m.frame_positions[1], plain.positions), 0.3 * size);
    EXPECT_GT(max_distance(m.frame_positions[2], plain.positions), 0.3 * size);
    EXPECT_GT(max_distance(m.frame_positions[1], m.frame_positions[2]), 0.01 * size);
}

TEST(Morph, MismatchedConnectivityNamesTheFileAndFace) {
    test::ScratchDir dir("morph-mismatch");
    fs::copy_file(horse_dir() + "/0001.obj", dir.file("a.obj"));
    fs::copy_file(horse_dir() + "/0002.obj", dir.file("b.obj"));
    // c.obj: same vertices, one face's corners rotated differently (0-based face 5 changed).
    {
        std::ifstream in(horse_dir() + "/0003.obj");
        std::ofstream out(dir.file("c.obj"));
        std::string line;
        int faces = 0;
        while (std::getline(in, line)) {
            if (line.rfind("f ", 0) == 0 && faces++ == 5) line = "f 1 2 3";
            out << line << "\n";
        }
    }
    const std::string msg = message_of([&] { load_morph(dir.path().string()); });
    EXPECT_NE(msg.find("c.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("face 5"), std::string::npos) << msg;
    EXPECT_NE(msg.find("a.obj"), std::string::npos) << msg;
    EXPECT_EQ(kind_of([&] { load_morph(dir.path().string()); }), Error::Kind::invalid);

    // A frame with fewer vertices.
    fs::remove(dir.file("c.obj"));
    fs::copy_file(test::shared_data("tex-spot/spot_triangulated.obj"), dir.file("c.obj"));
    const std::string msg2 = message_of([&] { load_morph(dir.path().string()); });
    EXPECT_NE(msg2.find("c.obj"), std::string::npos) << msg2;
    EXPECT_NE(msg2.find("vertices"), std::string::npos) << msg2;
}

TEST(Morph, BadInputsGiveClearErrors) {
    test::ScratchDir dir("morph-bad");
    EXPECT_EQ(kind_of([&] { load_morph(dir.file("missing")); }), Error::Kind::io);
    EXPECT_EQ(kind_of([&] { load_morph(dir.path().string()); }), Error::Kind::invalid);  // empty directory
    fs::copy_file(horse_dir() + "/0001.obj", dir.file("a.obj"));
    EXPECT_NE(message_of([&] { load_morph(dir.path().string()); }).find("at least two"), std::string::npos);
    {
        std::ofstream(dir.file("b.obj")) << "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n";
    }
    const std::string msg = message_of([&] { load_morph(dir.path().string()); });
    EXPECT_NE(msg.find("b.obj"), std::string::npos) << msg;
    // glTF without morph targets, and a plain mesh file.
    EXPECT_EQ(kind_of([&] { load_morph(test::shared_data("tex-duck/glTF/Duck.gltf")); }), Error::Kind::unsupported);
    EXPECT_EQ(kind_of([&] { load_morph(horse_dir() + "/0001.obj"); }), Error::Kind::unsupported);
    // Truncated binary buffer of a morph glTF.
    fs::copy_file(sphere(), dir.file("s.gltf"));
    {
        std::ifstream in(test::shared_data("morph-animated-morph-sphere/AnimatedMorphSphere.bin"), std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream(dir.file("AnimatedMorphSphere.bin"), std::ios::binary) << bytes.substr(0, 100000);
    }
    const std::string msg3 = message_of([&] { load_morph(dir.file("s.gltf")); });
    EXPECT_NE(msg3.find("s.gltf"), std::string::npos) << msg3;
    // t outside [0, 1].
    MorphLoadOptions o;
    o.frames = 2;
    fs::remove(dir.file("b.obj"));
    fs::copy_file(horse_dir() + "/0002.obj", dir.file("b.obj"));
    const MorphMesh m = load_morph(dir.path().string(), o);
    std::vector<Vec3f> p;
    EXPECT_EQ(kind_of([&] { morph_positions_at(m, 1.5, p); }), Error::Kind::argument);
    EXPECT_EQ(kind_of([&] { morph_positions_at(m, std::nan(""), p); }), Error::Kind::argument);
}

TEST(Morph, PointsHoldInEveryFrame) {
    const MorphMesh m = load_morph(sphere());
    const std::vector<std::uint32_t> pts = morph_points(m);
    ASSERT_EQ(pts.size(), m.vertex_count());
    std::uint32_t count = 0;
    for (std::uint32_t p : pts) count = std::max(count, p + 1);
    EXPECT_LT(count, 1876u);  // the sphere's seams are welded...
    EXPECT_GE(count, 482u);   // ...but never more than its distinct base positions allow
    // Wedges of one point share their position in every frame.
    std::vector<std::uint32_t> first(count, 0xffffffffu);
    for (std::uint32_t v = 0; v < pts.size(); ++v) {
        if (first[pts[v]] == 0xffffffffu) { first[pts[v]] = v; continue; }
        for (const auto& f : m.frame_positions) ASSERT_EQ(f[v], f[first[pts[v]]]);
    }
}

TEST(Morph, PlySequenceLoadsLikeTheObjSequence) {
    test::ScratchDir dir("morph-ply");
    for (const char* name : {"0001", "0010", "0020"})
        write_mesh(read_mesh(horse_dir() + "/" + name + ".obj"), dir.file(std::string("f") + name + ".ply"));
    const MorphMesh m = load_morph(dir.path().string());
    ASSERT_EQ(m.frame_count(), 3u);
    EXPECT_EQ(m.frame_names[1], "f0010.ply");
    const Mesh f10 = read_mesh(horse_dir() + "/0010.obj");
    EXPECT_EQ(max_distance(m.frame_positions[1], f10.positions), 0.0);
    EXPECT_EQ(m.base.indices, f10.indices);
}
