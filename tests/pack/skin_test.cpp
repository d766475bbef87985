// Skinned, animated meshes (docs/skinning.md): CesiumMan and RiggedSimple are read with their joints,
// weights, skin and animations; `convert` writes them back valid and unchanged; every level method that
// keeps vertices carries the influences of the vertices it keeps; welding keeps vertices that follow
// different joints apart; a pack binds every level to one skeleton with normalised, limited weights.
#include "pack_test_util.h"
#include "support/cli_run.h"
#include "support/test_paths.h"

#include "lodforge/error.h"
#include "lodforge/io/gltf_reader.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/pack/lod_pack.h"
#include "lodforge/pack/preset.h"
#include "lodforge/simplify/identical_vertices.h"
#include "lodforge/simplify/lod_chain.h"
#include "lodforge/simplify/simplify.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <string>

namespace {

using namespace lodforge;
using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;

const char* kCesiumMan = "skin-cesium-man/CesiumMan.glb";
const char* kRiggedSimple = "skin-rigged-simple/RiggedSimple.glb";

// The pack's explained notes, and NODE_EMPTY: the source's mesh node stays in the hierarchy, empty
// (docs/skinning.md).
std::vector<std::string> unexplained(const test::Validation& v) {
    std::vector<std::string> out;
    for (const std::string& s : test::unexplained_warnings(v))
        if (s.find("NODE_EMPTY") == std::string::npos) out.push_back(s);
    return out;
}

float weight_sum(const Mesh& m, std::size_t v) {
    float s = 0;
    for (const auto& set : m.weights) s += set[v].x + set[v].y + set[v].z + set[v].w;
    return s;
}

TEST(Skin, ReaderKeepsJointsWeightsSkinAndAnimations) {
    const Mesh man = read_mesh(shared_data(kCesiumMan));
    ASSERT_TRUE(man.has_skin());
    ASSERT_EQ(man.joints.size(), 1u);
    ASSERT_EQ(man.weights.size(), 1u);
    ASSERT_EQ(man.joints[0].size(), man.vertex_count());
    EXPECT_EQ(man.skeleton->joints.size(), 19u);
    EXPECT_EQ(man.skeleton->inverse_bind_matrices.size(), 19u);
    EXPECT_EQ(man.skeleton->nodes.size(), 22u);
    EXPECT_EQ(man.skeleton->skin_name, "Armature");
    EXPECT_EQ(man.skeleton->nodes[static_cast<std::size_t>(man.skeleton->skeleton_root)].name, "Skeleton_torso_joint_1");
    ASSERT_EQ(man.skeleton->animations.size(), 1u);
    EXPECT_EQ(man.skeleton->animations[0].channels.size(), 57u);
    EXPECT_GT(man.skeleton->animations[0].duration(), 1.f);
    std::set<int> used;
    for (std::size_t v = 0; v < man.vertex_count(); ++v) {
        EXPECT_NEAR(weight_sum(man, v), 1.f, 2e-3f) << v;
        for (std::uint16_t j : man.joints[0][v]) used.insert(j);
    }
    EXPECT_GT(used.size(), 10u) << "the body follows many joints";
    EXPECT_EQ(max_influence_count(man), 4u);

    const Mesh simple = read_mesh(shared_data(kRiggedSimple));
    ASSERT_TRUE(simple.has_skin());
    EXPECT_EQ(simple.skeleton->joints.size(), 4u);
    ASSERT_EQ(simple.skeleton->animations.size(), 1u);
    EXPECT_EQ(simple.skeleton->animations[0].name, "Anim_0_Armature");
    EXPECT_EQ(simple.skeleton->animations[0].channels.size(), 12u);
}

TEST(Skin, InfoListsTheSkin) {
    const CliRun r = run_cli("info " + quoted(shared_data(kCesiumMan)));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("joints0, weights0"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("skin:        19 joints, up to 4 influences per vertex"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("animation:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("57 channels"), std::string::npos) << r.out;
}

// Convert writes what it read: the same influences per vertex, skin and animation keys, and a file the
// Khronos validator accepts.
TEST(Skin, ConvertRoundTripsBothCharacters) {
    ScratchDir dir("skin-convert");
    for (const char* name : {kCesiumMan, kRiggedSimple}) {
        const std::string out = dir.file("out.glb");
        const CliRun r = run_cli("-q convert " + quoted(shared_data(name)) + " " + quoted(out));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        const auto v = test::validate_gltf(out);
        EXPECT_EQ(v.exit_code, 0) << v.raw;
        ASSERT_TRUE(v.report.is_object()) << v.raw;
        EXPECT_EQ(v.report["errors"], 0) << v.raw;
        EXPECT_TRUE(unexplained(v).empty()) << v.raw;

        const Mesh in = read_mesh(shared_data(name));
        const Mesh back = read_mesh(out);
        ASSERT_TRUE(back.has_skin()) << name;
        ASSERT_EQ(back.vertex_count(), in.vertex_count()) << name;
        EXPECT_EQ(back.positions, in.positions) << name;
        EXPECT_EQ(back.joints, in.joints) << name;
        EXPECT_EQ(back.weights, in.weights) << name;
        const Skeleton& a = *in.skeleton;
        const Skeleton& b = *back.skeleton;
        ASSERT_EQ(b.joints.size(), a.joints.size());
        EXPECT_EQ(b.inverse_bind_matrices, a.inverse_bind_matrices);
        for (std::size_t j = 0; j < a.joints.size(); ++j)
            EXPECT_EQ(b.nodes[static_cast<std::size_t>(b.joints[j])].name, a.nodes[static_cast<std::size_t>(a.joints[j])].name);
        ASSERT_EQ(b.animations.size(), a.animations.size());
        for (std::size_t k = 0; k < a.animations.size(); ++k) {
            const Animation& x = a.animations[k];
            const Animation& y = b.animations[k];
            EXPECT_EQ(y.name, x.name);
            ASSERT_EQ(y.channels.size(), x.channels.size());
            for (std::size_t c = 0; c < x.channels.size(); ++c) {
                EXPECT_EQ(y.channels[c].path, x.channels[c].path);
                EXPECT_EQ(b.nodes[static_cast<std::size_t>(y.channels[c].node)].name,
                          a.nodes[static_cast<std::size_t>(x.channels[c].node)].name);
                const AnimationSampler& sx = x.samplers[static_cast<std::size_t>(x.channels[c].sampler)];
                const AnimationSampler& sy = y.samplers[static_cast<std::size_t>(y.channels[c].sampler)];
                EXPECT_EQ(sy.input, sx.input);
                EXPECT_EQ(sy.output, sx.output);
                EXPECT_EQ(sy.interpolation, sx.interpolation);
            }
        }
    }
}

// A kept vertex keeps its influences: half-edge and optimal placement alike (optimal solves normals
// and UVs, never joints).
TEST(Skin, SimplifierKeepsTheInfluencesOfKeptVertices) {
    const Mesh man = read_mesh(shared_data(kCesiumMan));
    for (Placement placement : {Placement::half_edge, Placement::optimal}) {
        SimplifyParams p;
        p.target_ratio = 0.25f;
        p.placement = placement;
        const SimplifyResult r = simplify(man, p);
        const Mesh& out = r.mesh;
        ASSERT_TRUE(out.has_skin());
        EXPECT_EQ(out.skeleton, man.skeleton);
        ASSERT_EQ(out.joints.size(), 1u);
        ASSERT_EQ(out.joints[0].size(), out.vertex_count());
        ASSERT_EQ(r.vertex_map.size(), out.vertex_count());
        for (std::size_t i = 0; i < out.vertex_count(); ++i) {
            EXPECT_EQ(out.joints[0][i], man.joints[0][r.vertex_map[i]]) << i;
            EXPECT_EQ(out.weights[0][i], man.weights[0][r.vertex_map[i]]) << i;
        }
    }
}

TEST(Skin, LodChainSharedBufferCarriesInfluences) {
    const Mesh man = read_mesh(shared_data(kCesiumMan));
    LodChainParams p;
    p.levels = lod_levels_from_ratios({0.5f, 0.25f, 0.1f});
    p.measure = false;
    const LodChainResult chain = build_lod_chain(man, p);
    const Mesh& v = chain.shared.vertices;
    ASSERT_TRUE(v.has_skin());
    ASSERT_EQ(v.joints[0].size(), v.vertex_count());
    for (std::size_t i = 0; i < v.vertex_count(); ++i) {
        EXPECT_EQ(v.joints[0][i], man.joints[0][chain.shared.input_vertex[i]]);
        EXPECT_EQ(v.weights[0][i], man.weights[0][chain.shared.input_vertex[i]]);
    }
    for (std::size_t k = 1; k < chain.levels.size(); ++k) {
        const Mesh& level = chain.levels[k].mesh;
        ASSERT_TRUE(level.has_skin()) << k;
        for (std::size_t i = 0; i < level.vertex_count(); ++i)
            EXPECT_EQ(level.joints[0][i], man.joints[0][chain.levels[k].input_vertex[i]]);
    }
}

// Two triangles repeated as a soup; the copies of one corner differ only in their joints. Welding joins
// the true duplicates and keeps those two apart.
TEST(Skin, IdenticalVerticesDoNotMergeDifferentInfluences) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2, 3, 4, 5};
    m.joints = {{{0, 0, 0, 0}, {1, 0, 0, 0}, {2, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {3, 0, 0, 0}}};
    m.weights = {std::vector<Vec4f>(6, Vec4f{1, 0, 0, 0})};
    const IdenticalVertices iv = find_identical_vertices(m);
    EXPECT_EQ(iv.duplicates, 2u);
    EXPECT_EQ(iv.merged_of[0], iv.merged_of[3]);
    EXPECT_EQ(iv.merged_of[1], iv.merged_of[4]);
    EXPECT_NE(iv.merged_of[2], iv.merged_of[5]) << "vertex 5 follows joint 3, vertex 2 joint 2";
    const Mesh merged = iv.merged(m);
    ASSERT_EQ(merged.joints.size(), 1u);
    ASSERT_EQ(merged.joints[0].size(), 4u);
    EXPECT_EQ(merged.joints[0][iv.merged_of[5]][0], 3);
    EXPECT_EQ(merged.joints[0][iv.merged_of[2]][0], 2);
}

TEST(Skin, LimitInfluencesKeepsTheHeaviestRenormalised) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}};
    m.joints = {{{1, 2, 3, 4}, {0, 0, 0, 0}}, {{5, 6, 0, 0}, {0, 0, 0, 0}}};
    m.weights = {{{0.1f, 0.3f, 0.05f, 0.2f}, {0, 0, 0, 0}}, {{0.25f, 0.1f, 0, 0}, {0, 0, 0, 0}}};
    EXPECT_EQ(max_influence_count(m), 6u);
    Mesh four = m;
    limit_influences(four, 4);
    ASSERT_EQ(four.joints.size(), 1u);
    const Joints4 expect{2, 5, 4, 1};  // 0.3, 0.25, 0.2, 0.1
    EXPECT_EQ(four.joints[0][0], expect);
    EXPECT_NEAR(four.weights[0][0].x, 0.3f / 0.85f, 1e-6f);
    EXPECT_NEAR(weight_sum(four, 0), 1.f, 1e-6f);
    EXPECT_NEAR(weight_sum(four, 1), 1.f, 1e-6f) << "a vertex without weights is bound to joint 0";
    EXPECT_EQ(four.joints[0][1][0], 0);
    Mesh one = m;
    limit_influences(one, 1);
    EXPECT_EQ(one.joints[0][0][0], 2);
    EXPECT_EQ(one.weights[0][0], (Vec4f{1, 0, 0, 0}));
    EXPECT_EQ(max_influence_count(one), 1u);
}

// ---- the pack -------------------------------------------------------------------------------------

struct PackCheck {
    std::size_t levels = 0;
    std::vector<std::size_t> most_influences;  // per level node
};

// Every level node bound to skin 0 with JOINTS_0/WEIGHTS_0, weights summing to 1 within 1e-3.
PackCheck check_skinned_pack(const std::string& glb_path) {
    PackCheck c;
    const auto v = test::validate_gltf(glb_path);
    EXPECT_EQ(v.exit_code, 0) << v.raw;
    EXPECT_TRUE(v.report.is_object() && v.report["errors"] == 0) << v.raw;
    EXPECT_TRUE(unexplained(v).empty()) << v.raw;
    const test::Glb g = test::split_glb(test::read_bytes(glb_path));
    EXPECT_EQ(g.json["skins"].size(), 1u);
    EXPECT_GE(g.json["animations"].size(), 1u);
    std::vector<std::size_t> nodes{0};
    for (std::size_t id : test::lod_ids(g)) nodes.push_back(id);
    c.levels = nodes.size();
    for (std::size_t node : nodes) {
        const auto& n = g.json["nodes"][node];
        EXPECT_EQ(n.value("skin", -1), 0) << node;
        std::size_t most = 0;
        for (const auto& prim : g.json["meshes"][n["mesh"].get<std::size_t>()]["primitives"]) {
            EXPECT_TRUE(prim["attributes"].contains("JOINTS_0")) << node;
            EXPECT_TRUE(prim["attributes"].contains("WEIGHTS_0")) << node;
            if (!prim["attributes"].contains("WEIGHTS_0")) continue;
            for (const auto& w : test::vec4_values(g, prim["attributes"]["WEIGHTS_0"].get<std::size_t>())) {
                EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.f, 1e-3f);
                most = std::max<std::size_t>(most, static_cast<std::size_t>(std::count_if(w.begin(), w.end(), [](float x) { return x > 0; })));
            }
        }
        c.most_influences.push_back(most);
    }
    return c;
}

TEST(Skin, PackBindsEveryLevelToOneSkeleton) {
    ScratchDir dir("skin-pack");
    for (const char* name : {kCesiumMan, kRiggedSimple}) {
        const std::string out = dir.file(std::string("pack-") + (name == kCesiumMan ? "man" : "simple"));
        const CliRun r = run_cli("-q pack " + quoted(shared_data(name)) + " -o " + quoted(out));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        const std::string stem = name == kCesiumMan ? "CesiumMan" : "RiggedSimple";
        const PackCheck c = check_skinned_pack(out + "/" + stem + ".glb");
        EXPECT_GE(c.levels, 3u) << name;
        for (std::size_t most : c.most_influences) EXPECT_LE(most, 4u);
    }
}

TEST(Skin, PackPresetLimitsInfluencesPerLevel) {
    ScratchDir dir("skin-pack-limit");
    {
        std::ofstream preset(dir.file("few.json"));
        preset << R"({"levels": [{"ratio": 0.5}, {"ratio": 0.25}, {"ratio": 0.1}], "skin": {"max_influences": [3, 2, 1]}})";
    }
    const std::string out = dir.file("pack");
    const CliRun r = run_cli("-q pack " + quoted(shared_data(kCesiumMan)) + " --preset " + quoted(dir.file("few.json")) +
                             " -o " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const PackCheck c = check_skinned_pack(out + "/CesiumMan.glb");
    ASSERT_EQ(c.levels, 4u);
    EXPECT_EQ(c.most_influences[0], 4u) << "level 0 keeps every influence";
    EXPECT_EQ(c.most_influences[1], 3u);
    EXPECT_EQ(c.most_influences[2], 2u);
    EXPECT_EQ(c.most_influences[3], 1u);
}

// A pack whose collapse levels weigh sampled poses (skin.pose_samples) is as valid and as limited.
TEST(Skin, PackWithPoseSamplesIsValidAndLimited) {
    ScratchDir dir("skin-pack-poses");
    {
        std::ofstream preset(dir.file("poses.json"));
        preset << R"({"levels": [{"ratio": 0.5}, {"ratio": 0.25}, {"ratio": 0.1}],
                      "skin": {"max_influences": [4, 2], "pose_samples": 4, "weight": 2}})";
    }
    const std::string out = dir.file("pack");
    const CliRun r = run_cli("-q pack " + quoted(shared_data(kCesiumMan)) + " --preset " + quoted(dir.file("poses.json")) +
                             " -o " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const PackCheck c = check_skinned_pack(out + "/CesiumMan.glb");
    ASSERT_EQ(c.levels, 4u);
    EXPECT_EQ(c.most_influences[1], 4u);
    EXPECT_EQ(c.most_influences[2], 2u);
    EXPECT_EQ(c.most_influences[3], 2u) << "the last limit repeats";
}

TEST(Skin, LodStripsPackIsSkinned) {
    ScratchDir dir("skin-pack-strips");
    {
        std::ofstream preset(dir.file("strips.json"));
        preset << R"({"method": "lodstrips", "levels": [{"ratio": 0.5}, {"ratio": 0.2}]})";
    }
    const std::string out = dir.file("pack");
    const CliRun r = run_cli("-q pack " + quoted(shared_data(kRiggedSimple)) + " --preset " +
                             quoted(dir.file("strips.json")) + " -o " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const PackCheck c = check_skinned_pack(out + "/RiggedSimple.glb");
    EXPECT_EQ(c.levels, 3u);
    // Every level vertex is an input vertex (LODStrips keeps them) with that vertex's influences.
    const Mesh in = read_mesh(shared_data(kRiggedSimple));
    std::multimap<std::array<float, 3>, std::pair<Joints4, Vec4f>> input;
    for (std::size_t v = 0; v < in.vertex_count(); ++v)
        input.insert({{in.positions[v].x, in.positions[v].y, in.positions[v].z}, {in.joints[0][v], in.weights[0][v]}});
    const test::Glb g = test::split_glb(test::read_bytes(out + "/RiggedSimple.glb"));
    std::size_t checked = 0;
    for (const auto& mesh : g.json["meshes"])
        for (const auto& prim : mesh["primitives"]) {
            const auto& at = prim["attributes"];
            const auto p = test::vec4_values(g, at["POSITION"].get<std::size_t>());
            const auto j = test::vec4_values(g, at["JOINTS_0"].get<std::size_t>());
            const auto w = test::vec4_values(g, at["WEIGHTS_0"].get<std::size_t>());
            for (std::size_t v = 0; v < p.size(); ++v) {
                const auto [first, last] = input.equal_range({p[v][0], p[v][1], p[v][2]});
                bool found = false;
                for (auto it = first; it != last && !found; ++it) {
                    const Joints4& ij = it->second.first;
                    const Vec4f& iw = it->second.second;
                    found = ij[0] == j[v][0] && ij[1] == j[v][1] && ij[2] == j[v][2] && ij[3] == j[v][3] &&
                            std::fabs(iw.x - w[v][0]) < 1e-3f && std::fabs(iw.y - w[v][1]) < 1e-3f &&
                            std::fabs(iw.z - w[v][2]) < 1e-3f && std::fabs(iw.w - w[v][3]) < 1e-3f;
                }
                EXPECT_TRUE(found) << "vertex " << v;
                ++checked;
            }
        }
    EXPECT_GT(checked, 100u);
}

TEST(Skin, PresetRejectsBadInfluenceCounts) {
    EXPECT_THROW(parse_preset(R"({"skin": {"max_influences": [0]}})"), Error);
    EXPECT_THROW(parse_preset(R"({"skin": {"max_influences": []}})"), Error);
    EXPECT_THROW(parse_preset(R"({"skin": {"max_influences": [9]}})"), Error);
    EXPECT_THROW(parse_preset(R"({"skin": {"most": [2]}})"), Error);
    const Preset p = parse_preset(R"({"skin": {"max_influences": [4, 2]}})");
    EXPECT_EQ(p.skin.max_influences, (std::vector<std::uint32_t>{4, 2}));
    EXPECT_EQ(parse_preset(preset_to_json(p)), p);
}

}  // namespace
