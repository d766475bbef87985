// glTF export of morphing LOD: the Khronos validator finds no error, every level has the same morph
// targets, the animation drives every level, and our own glTF reader gives each level's frames back.
#include "lodforge/error.h"
#include "lodforge/io/gltf_reader.h"
#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_gltf.h"
#include "lodforge/morph/morph_lod.h"
#include "lodforge/morph/morph_lodstrips.h"

#include "../pack/pack_test_util.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>

namespace {

using namespace lodforge;

struct Export {
    MorphMesh morph;
    MorphLod lod;
    MorphStripsBuild strips;
};

Export make(const std::string& source, std::size_t frames, std::vector<float> levels, bool close_seams = false) {
    Export x;
    MorphLoadOptions o;
    o.frames = frames;
    x.morph = load_morph(source, o);
    MorphLodParams p;
    p.levels = std::move(levels);
    p.simplify.preserve_seams = !close_seams;
    x.lod = build_morph_lod(x.morph, p);
    x.strips = build_morph_lodstrips(x.morph, x.lod);
    return x;
}

std::string sphere_path() { return test::shared_data("morph-animated-morph-sphere/AnimatedMorphSphere.gltf"); }

// The GLB with a different scene root, so that a reader that follows the scene reads level `node`.
void write_with_root(const test::Glb& glb, std::size_t node, const std::string& path) {
    nlohmann::json j = glb.json;
    j["scenes"][0]["nodes"] = nlohmann::json::array({node});
    j["nodes"][node].erase("extensions");
    std::string text = j.dump();
    while (text.size() % 4) text += ' ';
    std::vector<std::uint8_t> out;
    auto u32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    };
    u32(0x46546C67);
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + glb.bin.size()));
    u32(static_cast<std::uint32_t>(text.size()));
    u32(0x4E4F534A);
    out.insert(out.end(), text.begin(), text.end());
    u32(static_cast<std::uint32_t>(glb.bin.size()));
    u32(0x004E4942);
    out.insert(out.end(), glb.bin.begin(), glb.bin.end());
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(out.data()), std::streamsize(out.size()));
}

// Validates, checks the structure, and reads every level back through read_gltf.
// Quantised (the default): positions within the bound of GlbMorphTargets::quantize, relative to the
// diagonal of every frame's box; normals as directions (renderers normalise n + d), within the BYTE
// rounding amplified by the fitted scale λ >= 1/4 (morph_gltf_targets).
void check_export(const Export& x, const MorphGltfTiming& timing, const std::string& name, bool quantize = true) {
    test::ScratchDir dir("morph-gltf-" + name);
    const std::string path = dir.file(name + ".glb");
    MorphGltfOptions o;
    o.name = name;
    o.timing = timing;
    o.quantize = quantize;
    const MorphGltfResult r = write_morph_glb(x.morph, x.lod, x.strips, o, path);
    const std::size_t K = x.morph.frame_count();
    EXPECT_EQ(r.targets, K - 1);
    ASSERT_EQ(r.level_triangles.size(), 1 + x.lod.levels.size());

    const test::Validation v = test::validate_gltf(path);
    ASSERT_TRUE(v.report.is_object()) << v.raw;
    EXPECT_EQ(v.report["errors"], 0) << v.raw;
    EXPECT_EQ(v.exit_code, 0) << v.raw;
    EXPECT_TRUE(test::unexplained_warnings(v).empty()) << v.raw;

    const test::Glb glb = test::split_glb(test::read_bytes(path));
    const auto& meshes = glb.json["meshes"];
    ASSERT_EQ(meshes.size(), r.level_triangles.size());
    const auto& accessors = glb.json["accessors"];
    for (const auto& mesh : meshes) {
        EXPECT_EQ(mesh["weights"].size(), K - 1);
        for (const auto& p : mesh["primitives"]) {
            EXPECT_EQ(p["targets"].size(), K - 1) << mesh["name"];
            for (const auto& t : p["targets"]) {
                const auto& pos = accessors[t["POSITION"].get<int>()];
                const auto& nrm = accessors[t["NORMAL"].get<int>()];
                EXPECT_EQ(pos["componentType"], quantize ? 5122 : 5126) << mesh["name"];
                EXPECT_EQ(nrm["componentType"], quantize ? 5120 : 5126) << mesh["name"];
                EXPECT_EQ(pos.value("normalized", false), quantize);
                EXPECT_EQ(nrm.value("normalized", false), quantize);
            }
        }
    }
    const auto required = glb.json.value("extensionsRequired", nlohmann::json::array());
    EXPECT_EQ(required.size(), quantize ? 1u : 0u);
    if (quantize) {
        EXPECT_EQ(required[0], "KHR_mesh_quantization");
        for (const auto& node : glb.json["nodes"]) EXPECT_EQ(node["scale"], glb.json["nodes"][0]["scale"]);
    }
    if (timing.animated) {
        ASSERT_EQ(glb.json["animations"].size(), 1u);
        const auto& a = glb.json["animations"][0];
        EXPECT_EQ(a["channels"].size(), meshes.size());
        const auto& input = glb.json["accessors"][a["samplers"][0]["input"].get<int>()];
        EXPECT_EQ(input["count"], K);
        EXPECT_NEAR(input["min"][0].get<double>(), timing.start_seconds, 1e-6);
        EXPECT_NEAR(input["max"][0].get<double>(), timing.start_seconds + timing.seconds_per_frame * double(K - 1), 1e-5);
    } else {
        EXPECT_FALSE(glb.json.contains("animations"));
    }

    Bounds all;
    for (const auto& frame : x.morph.frame_positions)
        for (const Vec3f& p : frame) all.add(p);
    const double diagonal = double(all.diagonal());
    // The dequantisation step: the uniform node scale over 32767, at most the diagonal over 32767.
    const double scale = quantize ? glb.json["nodes"][0]["scale"][0].get<double>() : 0.0;
    EXPECT_LE(scale, diagonal);
    const double tol = quantize ? 0.5 * scale / 32767.0 + 2e-6 * diagonal : 1e-6 * double(x.morph.base.bounds().diagonal()) + 1e-7;
    EXPECT_LE(tol, 2.0e-5 * diagonal);  // the bound, relative to the diagonal
    double worst_normal = 0;
    std::size_t over = 0, far = 0, normals = 0;
    for (std::size_t level = 0; level < meshes.size(); ++level) {
        const std::string one = dir.file("level" + std::to_string(level) + ".glb");
        write_with_root(glb, level, one);
        GltfMorphTargets mt;
        GltfReadOptions ro;
        ro.morph_targets = &mt;
        const Mesh m = read_gltf(one, nullptr, ro);
        const std::string where = name + " level " + std::to_string(level);
        ASSERT_EQ(m.triangle_count(), r.level_triangles[level]) << where;
        ASSERT_EQ(mt.target_count(), K - 1) << where;
        ASSERT_EQ(m.vertex_count(), r.level_vertices[level]) << where;
        if (timing.animated) {
            EXPECT_EQ(mt.key_times.size(), K) << where;
        }
        // frame 0 = the base, frame j = base + target j-1 (weight 1), for positions and normals
        for (std::size_t c = 0; c < m.vertex_count(); ++c) {
            const std::uint32_t i = x.strips.input_vertex[c];
            for (std::size_t j = 0; j < K; ++j) {
                const Vec3f p = j == 0 ? m.positions[c] : m.positions[c] + mt.position_deltas[j - 1][c];
                const Vec3f e = x.morph.frame_positions[j][i];
                ASSERT_NEAR(p.x, e.x, tol) << where << " vertex " << c << " frame " << j;
                ASSERT_NEAR(p.y, e.y, tol) << where << " vertex " << c << " frame " << j;
                ASSERT_NEAR(p.z, e.z, tol) << where << " vertex " << c << " frame " << j;
                const Vec3f n = j == 0 ? m.normals[c] : m.normals[c] + mt.normal_deltas[j - 1][c];
                const Vec3f en = x.morph.frame_normals[j][i];
                if (!quantize) {
                    ASSERT_NEAR(n.x, en.x, 1e-5) << where << " vertex " << c << " frame " << j;
                    ASSERT_NEAR(n.y, en.y, 1e-5) << where;
                    ASSERT_NEAR(n.z, en.z, 1e-5) << where;
                } else {
                    const float len = length(n);
                    const double angle =
                        len > 0 ? std::acos(std::clamp(double(dot(n, en)) / double(len), -1.0, 1.0)) : M_PI;
                    worst_normal = std::max(worst_normal, angle);
                    over += angle > 0.01 ? 1 : 0;
                    far += angle > 0.1 ? 1 : 0;
                    ++normals;
                }
            }
        }
    }
    // BYTE rounding turns a normal by <= 0.0068 rad when its displacement fits; the near-reversals that do
    // not fit (horse: legs turning past 90 degrees from an axis-aligned normal) are the rest.
    EXPECT_LE(double(over), 0.015 * double(normals)) << name;
    EXPECT_LE(double(far), 0.002 * double(normals)) << name;
    if (quantize)
        std::printf("%s: worst normal angle %.4f rad, %zu of %zu over 0.01 rad, %zu over 0.1 rad; position bound %.3g of "
                    "the diagonal\n", name.c_str(), worst_normal, over, normals, far, tol / diagonal);
}

}  // namespace

TEST(MorphGltf, HorseGallopExportValidatesAndReloadsEveryLevelsFrames) {
    const Export x = make(test::shared_data("seq-horse-gallop"), 4, {0.5f, 0.1f, 0.03f});
    const MorphGltfTiming timing = morph_gltf_timing(x.morph);
    EXPECT_TRUE(timing.animated);
    EXPECT_DOUBLE_EQ(timing.seconds_per_frame, 1.0 / 30.0);
    check_export(x, timing, "horse");
}

TEST(MorphGltf, FloatTargetsOnRequestAreExact) {
    const Export x = make(test::shared_data("seq-horse-gallop"), 3, {0.5f, 0.1f});
    check_export(x, morph_gltf_timing(x.morph), "horse-float", false);
}

TEST(MorphGltf, QuantisedTargetsAreAtLeastTwiceSmaller) {
    const Export x = make(test::shared_data("seq-horse-gallop"), 6, {0.5f, 0.1f});
    test::ScratchDir dir("morph-gltf-size");
    MorphGltfOptions o;
    o.timing = morph_gltf_timing(x.morph);
    const MorphGltfResult q = write_morph_glb(x.morph, x.lod, x.strips, o, dir.file("q.glb"));
    o.quantize = false;
    const MorphGltfResult f = write_morph_glb(x.morph, x.lod, x.strips, o, dir.file("f.glb"));
    // The target views: per vertex and target 8 + 4 bytes (SHORT positions and BYTE normals, each padded
    // to 4-byte elements) instead of 12 + 12, once for all levels.
    auto target_bytes = [](const std::string& path) {
        const test::Glb glb = test::split_glb(test::read_bytes(path));
        std::set<int> views;
        for (const auto& mesh : glb.json["meshes"])
            for (const auto& p : mesh["primitives"])
                for (const auto& t : p["targets"])
                    for (const char* a : {"POSITION", "NORMAL"})
                        views.insert(glb.json["accessors"][t[a].get<int>()]["bufferView"].get<int>());
        std::size_t bytes = 0;
        for (int v : views) bytes += glb.json["bufferViews"][std::size_t(v)]["byteLength"].get<std::size_t>();
        return bytes;
    };
    const std::size_t n = x.strips.data.strips.vertex_count, targets = x.morph.frame_count() - 1;
    EXPECT_EQ(target_bytes(dir.file("q.glb")), targets * n * 12);
    EXPECT_EQ(target_bytes(dir.file("f.glb")), targets * n * 24);
    EXPECT_LT(q.glb.bytes, f.glb.bytes);
}

TEST(MorphGltf, MorphSphereKeepsItsOwnAnimationTimes) {
    const Export x = make(sphere_path(), 8, {0.5f, 0.1f});
    const MorphGltfTiming timing = morph_gltf_timing(x.morph);
    ASSERT_TRUE(timing.animated);
    GltfMorphTargets mt;
    GltfReadOptions ro;
    ro.morph_targets = &mt;
    read_gltf(sphere_path(), nullptr, ro);
    ASSERT_FALSE(mt.key_times.empty());
    EXPECT_NEAR(timing.start_seconds, mt.key_times.front(), 1e-6);
    EXPECT_NEAR(timing.start_seconds + timing.seconds_per_frame * 7.0, mt.key_times.back(), 1e-5);
    check_export(x, timing, "sphere");
}

TEST(MorphGltf, MorphCubeWithoutAnimationWritesNone) {
    const Export x = make(test::shared_data("morph-animated-morph-cube/AnimatedMorphCube.gltf"), 0, {0.5f}, true);
    MorphGltfTiming timing;
    timing.animated = false;
    check_export(x, timing, "cube");
}

TEST(MorphGltf, TargetsThatDoNotMatchTheBufferAreRefused) {
    const Export x = make(sphere_path(), 3, {0.5f});
    const SharedLodBuffers shared = morph_gltf_buffers(x.morph, x.lod, x.strips);
    GlbMorphTargets t = morph_gltf_targets(x.morph, x.strips, {});
    t.position_deltas[0].pop_back();
    EXPECT_THROW(encode_glb(shared, GlbOptions{}, t), Error);
    t = morph_gltf_targets(x.morph, x.strips, {});
    t.key_weights[1].push_back(0.f);
    EXPECT_THROW(encode_glb(shared, GlbOptions{}, t), Error);
    t = morph_gltf_targets(x.morph, x.strips, {});
    t.key_times[2] = t.key_times[1];
    EXPECT_THROW(encode_glb(shared, GlbOptions{}, t), Error);
    t = morph_gltf_targets(x.morph, x.strips, {});
    t.position_deltas[1][3].x = std::nanf("");
    EXPECT_THROW(encode_glb(shared, GlbOptions{}, t), Error);
}
