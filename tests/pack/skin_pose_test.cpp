// Poses and pose-space error of skinned meshes (docs/skinning.md): the animation samplers interpolate as
// glTF says (LINEAR, STEP, CUBICSPLINE, slerp), CesiumMan walks (its feet move), `compare --poses`
// reports each level's error in the bind pose and over sampled frames, a mesh without skin is refused
// with a clear message, and the skinning-aware cost (poses sampled into the collapse cost) keeps
// CesiumMan's pose-space error within 1.2x its bind-pose error at 25 % and 10 %.
#include "support/cli_run.h"
#include "support/test_paths.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/pose_error.h"
#include "lodforge/pack/preset.h"
#include "lodforge/simplify/lod_chain.h"
#include "lodforge/simplify/simplify.h"
#include "lodforge/simplify/skin_cost.h"
#include "lodforge/skeleton.h"
#include "lodforge/skeleton_pose.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <string>

namespace {

using namespace lodforge;
using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;

const char* kWalkingMan = "skin-cesium-man/CesiumMan.glb";

// One triangle bound wholly to joint 0 (node 0, identity inverse bind), animated by `sampler` on `path`.
Mesh one_joint_triangle(const AnimationSampler& sampler, const std::string& path) {
    auto sk = std::make_shared<Skeleton>();
    sk->nodes.resize(1);
    sk->roots = {0};
    sk->joints = {0};
    sk->inverse_bind_matrices = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    Animation a;
    a.samplers.push_back(sampler);
    a.channels.push_back({0, 0, path});
    sk->animations.push_back(a);
    Mesh m;
    m.positions = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.indices = {0, 1, 2};
    m.joints = {std::vector<Joints4>(3, Joints4{0, 0, 0, 0})};
    m.weights = {std::vector<Vec4f>(3, Vec4f{1, 0, 0, 0})};
    m.skeleton = sk;
    return m;
}

Vec3f posed_first(const Mesh& m, double t) {
    PoseParams p;
    p.time = t;
    return pose_mesh(m, p).positions[0];
}

TEST(SkinPose, LinearStepAndCubicTranslation) {
    AnimationSampler s;
    s.input = {0.f, 2.f};
    s.output = {0, 0, 0, 4, 0, 0};
    const Mesh linear = one_joint_triangle(s, "translation");
    EXPECT_NEAR(posed_first(linear, 1.0).x, 1 + 2, 1e-5);  // vertex (1,0,0) moved halfway
    EXPECT_NEAR(posed_first(linear, -1.0).x, 1, 1e-5) << "before the first key: the first value";
    EXPECT_NEAR(posed_first(linear, 5.0).x, 1 + 4, 1e-5) << "after the last key: the last value";
    s.interpolation = "STEP";
    EXPECT_NEAR(posed_first(one_joint_triangle(s, "translation"), 1.9).x, 1, 1e-5);
    // CUBICSPLINE: in-tangent, value, out-tangent per key. Out-tangent 3 at key 0 (per second, scaled
    // by the interval 2): p(0.5) = 0.5*0 + 0.125*2*3 + 0.5*4 + (-0.125)*2*0 = 2.75.
    s.interpolation = "CUBICSPLINE";
    s.output = {0, 0, 0, 0, 0, 0, 3, 0, 0, /* key 1 */ 0, 0, 0, 4, 0, 0, 0, 0, 0};
    EXPECT_NEAR(posed_first(one_joint_triangle(s, "translation"), 1.0).x, 1 + 2.75, 1e-5);
}

TEST(SkinPose, RotationIsSlerped) {
    AnimationSampler s;
    s.components = 4;
    s.input = {0.f, 1.f};
    const double h = std::sqrt(0.5);
    s.output = {0, 0, 0, 1, 0, 0, float(h), float(h)};  // identity to 90 degrees about z
    const Vec3f p = posed_first(one_joint_triangle(s, "rotation"), 0.5);
    // Slerp: 45 degrees, still unit length (a normalised lerp of the matrices would not be).
    EXPECT_NEAR(p.x, std::cos(M_PI / 4), 1e-5);
    EXPECT_NEAR(p.y, std::sin(M_PI / 4), 1e-5);
    EXPECT_NEAR(p.z, 0, 1e-6);
}

TEST(SkinPose, MeshWithoutSkinIsRefused) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    try {
        pose_mesh(m, {});
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::invalid);
        EXPECT_NE(std::string(e.what()).find("no skin"), std::string::npos) << e.what();
    }
}

TEST(SkinPose, CesiumManRestPoseIsRigidAndTheWalkMovesTheFeet) {
    const Mesh man = read_mesh(shared_data(kWalkingMan));
    ASSERT_TRUE(man.has_skin());
    ASSERT_FALSE(man.skeleton->animations.empty());
    const double diagonal = man.bounds().diagonal();
    PoseParams rest;
    rest.rest = true;
    const std::vector<Vec3f> r = pose_mesh(man, rest).positions;
    // The inverse bind matrices undo the rest pose: the rest pose is the bind pose moved rigidly.
    for (std::size_t v = 1; v < man.vertex_count(); v += 97)
        EXPECT_NEAR(length(r[v] - r[0]), length(man.positions[v] - man.positions[0]), 1e-4 * diagonal) << v;

    // Feet: the lowest vertices of the rest pose (glTF is Y-up).
    std::vector<std::size_t> order(man.vertex_count());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return r[a].y < r[b].y; });
    order.resize(order.size() / 20);
    const double duration = man.skeleton->animations[0].duration();
    ASSERT_GT(duration, 0);
    PoseParams start, later;
    later.time = duration / 2;  // half a walk cycle: the feet have swapped
    const PoseResult a = pose_mesh(man, start), b = pose_mesh(man, later);
    ASSERT_EQ(a.normals.size(), man.vertex_count());
    double moved = 0;
    for (std::size_t v : order) moved += length(b.positions[v] - a.positions[v]);
    moved /= double(order.size());
    EXPECT_GT(moved, 0.05 * diagonal) << "mean foot displacement " << moved;
    for (std::size_t v = 0; v < a.normals.size(); v += 101) EXPECT_NEAR(length(a.normals[v]), 1.f, 1e-4f);
}

TEST(SkinPose, LevelErrorInPoses) {
    const Mesh man = read_mesh(shared_data(kWalkingMan));
    SimplifyParams sp;
    sp.target_ratio = 0.25f;
    const Mesh level = simplify(man, sp).mesh;
    ASSERT_TRUE(level.has_skin());
    PoseErrorParams p;
    p.poses = 4;
    p.distance.samples = 20000;
    const PoseErrorResult r = compare_poses(man, level, p);
    ASSERT_EQ(r.frames.size(), 4u);
    EXPECT_GT(r.bind.mean, 0);
    EXPECT_GT(r.mean_mean, 0);
    EXPECT_GE(r.worst_mean, r.mean_mean);
    EXPECT_GE(r.worst_hausdorff, r.worst_mean);
    for (const PoseFrameError& f : r.frames) EXPECT_GT(f.time, 0);
    // The original against itself is exact in every pose.
    const PoseErrorResult same = compare_poses(man, man, p);
    EXPECT_NEAR(same.worst_hausdorff, 0, 1e-6 * r.bind.diagonal);

    Mesh still = man;
    still.skeleton = nullptr;
    still.joints.clear();
    still.weights.clear();
    try {
        compare_poses(man, still, p, "man.glb", "still.glb");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("still.glb: the mesh has no skin"), std::string::npos) << e.what();
    }
}

TEST(SkinPose, CompareCliReportsPoses) {
    ScratchDir dir("skin-compare");
    const std::string level = dir.file("level.glb");
    ASSERT_EQ(run_cli("-q simplify " + quoted(shared_data(kWalkingMan)) + " --ratio 0.25 -o " + quoted(level)).exit_code, 0);
    const CliRun r = run_cli("compare " + quoted(shared_data(kWalkingMan)) + " " + quoted(level) +
                             " --poses 3 --samples 20000 --json");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    ASSERT_TRUE(j.contains("poses"));
    EXPECT_EQ(j["poses"]["count"], 3);
    EXPECT_EQ(j["poses"]["frames"].size(), 3u);
    EXPECT_GT(j["poses"]["mean_mean"].get<double>(), 0);
    EXPECT_GE(j["poses"]["worst_mean"].get<double>(), j["poses"]["mean_mean"].get<double>());
    EXPECT_GT(j["mean"].get<double>(), 0) << "the bind pose's error stays at the top level";

    const std::string obj = dir.file("static.obj");
    ASSERT_EQ(run_cli("-q convert " + quoted(level) + " " + quoted(obj)).exit_code, 0);
    const CliRun s = run_cli("compare " + quoted(shared_data(kWalkingMan)) + " " + quoted(obj) + " --poses 3");
    EXPECT_EQ(s.exit_code, 1) << s.out;
    EXPECT_NE(s.out.find("has no skin"), std::string::npos) << s.out;
    EXPECT_EQ(run_cli("compare " + quoted(level) + " " + quoted(level) + " --animation 1").exit_code, 2);
}

// Frames equal to the input's positions add nothing to the cost: the chain with them is the chain
// without, which holds only if every step gets the frames of its own vertices.
TEST(SkinPose, LodChainPassesFramesToEveryStep) {
    const Mesh man = read_mesh(shared_data(kWalkingMan));
    LodChainParams p;
    p.levels = lod_levels_from_ratios({0.5f, 0.25f, 0.1f});
    p.measure = false;
    const LodChainResult plain = build_lod_chain(man, p);
    const std::vector<Vec3f> same = man.positions;
    p.simplify.extra_frames = {&same};
    const LodChainResult framed = build_lod_chain(man, p);
    ASSERT_EQ(plain.levels.size(), framed.levels.size());
    for (std::size_t k = 0; k < plain.levels.size(); ++k)
        EXPECT_EQ(plain.levels[k].mesh.indices, framed.levels[k].mesh.indices) << "level " << k;
}

// The issue's goal (#34): with the pose-sampled cost, CesiumMan's mean error over its walk is at most
// 1.2x the bind-pose error of the same level at 25 % and 10 %, measured in 16 poses other than the 8
// the cost saw; and it is lower than the bind-pose-only cost's pose error.
TEST(SkinPose, PoseSampledCostKeepsTheWalkWithinTheGoal) {
    const Mesh man = read_mesh(shared_data(kWalkingMan));
    PoseErrorParams measure;
    measure.poses = 16;
    measure.distance.samples = 30000;
    SkinCostParams skin;
    skin.pose_samples = 8;
    const SkinPoseFrames poses = skin_pose_frames(man, skin);
    ASSERT_EQ(poses.frames.size(), 8u);
    for (float ratio : {0.25f, 0.1f}) {
        SimplifyParams sp;
        sp.target_ratio = ratio;
        sp.placement = Placement::half_edge;
        const PoseErrorResult plain = compare_poses(man, simplify(man, sp).mesh, measure);
        poses.attach(sp);
        const SimplifyResult r = simplify(man, sp);
        EXPECT_LE(r.triangles, std::size_t(std::ceil(ratio * float(man.triangle_count()))));
        const PoseErrorResult posed = compare_poses(man, r.mesh, measure);
        EXPECT_LE(posed.mean_mean, 1.2 * posed.bind.mean) << "ratio " << ratio;
        EXPECT_LT(posed.mean_mean, plain.mean_mean) << "ratio " << ratio;
        EXPECT_LT(posed.worst_hausdorff, plain.worst_hausdorff) << "ratio " << ratio;
    }
}

TEST(SkinPose, SimplifyCliPoseSamples) {
    ScratchDir dir("skin-simplify-poses");
    const std::string out = dir.file("level.glb");
    const CliRun r = run_cli("simplify " + quoted(shared_data(kWalkingMan)) + " --ratio 0.25 --pose-samples 4 -o " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("poses: 4 sampled"), std::string::npos) << r.out;
    EXPECT_TRUE(read_mesh(out).has_skin());
    EXPECT_EQ(run_cli("simplify " + quoted(shared_data(kWalkingMan)) + " --ratio 0.25 --pose-samples 4 --placement optimal -o " +
                      quoted(out)).exit_code, 2);
    const std::string obj = dir.file("static.obj");
    ASSERT_EQ(run_cli("-q convert " + quoted(out) + " " + quoted(obj)).exit_code, 0);
    const CliRun s = run_cli("simplify " + quoted(obj) + " --ratio 0.5 --pose-samples 4 -o " + quoted(dir.file("x.obj")));
    EXPECT_EQ(s.exit_code, 1) << s.out;
    EXPECT_NE(s.out.find("needs a skinned mesh"), std::string::npos) << s.out;
}

TEST(SkinPose, PresetReadsPoseSamples) {
    const Preset p = parse_preset(R"({"skin": {"max_influences": [4], "pose_samples": 8, "weight": 2}})");
    EXPECT_EQ(p.skin.pose_samples, 8u);
    EXPECT_EQ(p.skin.weight, 2.0);
    EXPECT_EQ(parse_preset(preset_to_json(p)), p);
    EXPECT_THROW(parse_preset(R"({"skin": {"pose_samples": 65}})"), Error);
    EXPECT_THROW(parse_preset(R"({"skin": {"weight": -1}})"), Error);
}

}  // namespace
