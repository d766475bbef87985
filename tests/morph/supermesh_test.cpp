// Case (b) of issue 8: the supermesh of two genus-0 meshes (topology check, sphere maps, landmark
// alignment, overlay), on Spot and generated spheres, through the library and the CLI.
#include "lodforge/error.h"
#include "lodforge/morph/landmarks.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/morph/morph.h"
#include "lodforge/morph/supermesh.h"

#include "support/cli_run.h"
#include "support/icosphere.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <cmath>
#include <map>
#include <set>

namespace {

using namespace lodforge;
using lodforge::test::icosphere;

std::string spot() { return test::shared_data("tex-spot/spot_triangulated.obj"); }
std::string bunny() { return test::shared_data("scan-bunny/bun_zipper.ply"); }

Mesh torus(int nu, int nv)
{
    Mesh m;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const float u = 2 * float(M_PI) * i / nu, v = 2 * float(M_PI) * j / nv;
            m.positions.push_back({(2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v)});
        }
    auto id = [&](int i, int j) { return std::uint32_t(((i + nu) % nu) * nv + (j + nv) % nv); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j)
            m.indices.insert(m.indices.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    return m;
}

Error::Kind kind_of(const std::function<void()>& f, std::string* message = nullptr)
{
    try {
        f();
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.kind();
    }
    ADD_FAILURE() << "no error";
    return Error::Kind::cancelled;
}

using lodforge::test::contains;

// Landmarks on Spot and on a sphere around it: the sphere vertex nearest to the ray from Spot's centre
// through each of a few Spot vertices (nose, tail, feet, top); an honest, reproducible pairing.
Landmarks spot_sphere_landmarks(const Mesh& spot_mesh, const Mesh& ball, const std::vector<std::uint32_t>& spot_vertices)
{
    const Vec3f c = spot_mesh.bounds().center();
    Landmarks l;
    for (std::uint32_t v : spot_vertices) {
        Vec3f d = spot_mesh.positions[v] - c;
        d = d * (1.f / length(d));
        std::uint32_t best = 0;
        float best_dot = -2;
        const Vec3f bc = ball.bounds().center();
        for (std::uint32_t w = 0; w < ball.vertex_count(); ++w) {
            Vec3f e = ball.positions[w] - bc;
            const float dd = dot(d, e * (1.f / length(e)));
            if (dd > best_dot) best_dot = dd, best = w;
        }
        l.pairs.push_back({v, best});
    }
    return l;
}

// Extreme vertices of a mesh along ±x, ±y, +z: distinct, well spread landmarks.
std::vector<std::uint32_t> extremes(const Mesh& m)
{
    std::vector<std::uint32_t> out;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = -1; sign <= 1; sign += 2) {
            if (axis == 2 && sign < 0) continue;
            std::uint32_t best = 0;
            for (std::uint32_t v = 0; v < m.vertex_count(); ++v)
                if (sign * m.positions[v][axis] > sign * m.positions[best][axis]) best = v;
            out.push_back(best);
        }
    return out;
}

// orient3d of three sphere points against the centre, det[p, q − p, s − p] (accurate for tiny faces).
double sphere_det(const std::array<double, 3>& p, const std::array<double, 3>& q0, const std::array<double, 3>& s0)
{
    const double q[3] = {q0[0] - p[0], q0[1] - p[1], q0[2] - p[2]}, s[3] = {s0[0] - p[0], s0[1] - p[1], s0[2] - p[2]};
    return p[0] * (q[1] * s[2] - q[2] * s[1]) - p[1] * (q[0] * s[2] - q[2] * s[0]) + p[2] * (q[0] * s[1] - q[1] * s[0]);
}

double surface_area(const std::vector<Vec3f>& p, const std::vector<std::uint32_t>& idx)
{
    double s = 0;
    for (std::size_t i = 0; i < idx.size(); i += 3) s += 0.5 * double(length(cross(p[idx[i + 1]] - p[idx[i]], p[idx[i + 2]] - p[idx[i]])));
    return s;
}

// The checks every supermesh must pass: both inputs' points present at their positions, one closed
// genus-0 connectivity, positive faces on the sphere, each frame covering its input's surface once.
void expect_valid_supermesh(const SupermeshResult& r, const Mesh& a, const Mesh& b)
{
    const MorphMesh& m = r.morph;
    ASSERT_EQ(m.frame_count(), 2u);
    ASSERT_EQ(m.vertex_count(), r.a_points + r.b_points + r.crossings);
    // Every input vertex present (found by position, not by trusting the layout).
    for (int frame = 0; frame < 2; ++frame) {
        const Mesh& in = frame == 0 ? a : b;
        std::set<std::array<float, 3>> have;
        for (const Vec3f& p : m.frame_positions[std::size_t(frame)]) have.insert({p.x, p.y, p.z});
        std::size_t missing = 0;
        for (const Vec3f& p : in.positions) missing += have.count({p.x, p.y, p.z}) ? 0 : 1;
        EXPECT_EQ(missing, 0u) << "frame " << frame;
    }
    // No self-intersection on the sphere: every face positively oriented against the centre.
    ASSERT_EQ(r.sphere_points.size(), m.vertex_count());
    std::size_t negative = 0;
    for (std::size_t i = 0; i < m.base.indices.size(); i += 3) {
        negative += sphere_det(r.sphere_points[m.base.indices[i]], r.sphere_points[m.base.indices[i + 1]],
                               r.sphere_points[m.base.indices[i + 2]]) > 0 ? 0 : 1;
    }
    EXPECT_EQ(negative, 0u);
    // A closed genus-0 surface itself (Euler characteristic 2, manifold, consistently oriented).
    EXPECT_NO_THROW(check_sphere_topology(m.base, "supermesh"));
    // Frame 0 covers A once, frame 1 covers B once.
    const double area_a = surface_area(a.positions, a.indices), area_b = surface_area(b.positions, b.indices);
    EXPECT_NEAR(surface_area(m.frame_positions[0], m.base.indices) / area_a, 1.0, 1e-4);
    EXPECT_NEAR(surface_area(m.frame_positions[1], m.base.indices) / area_b, 1.0, 1e-4);
    EXPECT_LT(r.landmark_residual, 1e-5);
}

Mesh weld_copy(const Mesh& m)
{
    // Spot as points only (its texcoord seams split wedges; the supermesh works on points).
    Mesh out;
    std::vector<std::uint32_t> ids = m.position_ids;
    if (ids.empty()) return m;
    std::size_t n = 0;
    for (auto id : ids) n = std::max<std::size_t>(n, id + 1);
    out.positions.resize(n);
    for (std::size_t v = 0; v < m.vertex_count(); ++v) out.positions[ids[v]] = m.positions[v];
    for (auto i : m.indices) out.indices.push_back(ids[i]);
    return out;
}

}  // namespace

TEST(SphereTopology, AcceptsSpheresAndSpot)
{
    const SphereTopology t = check_sphere_topology(icosphere(2), "ico");
    EXPECT_EQ(t.points.size(), 162u);
    EXPECT_EQ(t.faces.size(), 320u);
    const Mesh s = read_mesh(spot());
    const SphereTopology ts = check_sphere_topology(s, "spot");
    EXPECT_EQ(ts.points.size(), 2930u);  // welded across the texcoord seams
    EXPECT_EQ(ts.faces.size(), 5856u);
}

TEST(SphereTopology, RejectsOtherTopologiesByName)
{
    std::string msg;
    EXPECT_EQ(kind_of([] { check_sphere_topology(torus(24, 12), "torus.ply"); }, &msg), Error::Kind::unsupported);
    EXPECT_TRUE(contains(msg, "torus.ply") && contains(msg, "genus 1")) << msg;

    const Mesh bun = read_mesh(bunny());
    EXPECT_EQ(kind_of([&] { check_sphere_topology(bun, "bun_zipper.ply"); }, &msg), Error::Kind::invalid);
    EXPECT_TRUE(contains(msg, "bun_zipper.ply") && contains(msg, "border edges")) << msg;

    Mesh two = icosphere(1);
    const Mesh other = icosphere(1, 1.f, {3, 0, 0});
    for (auto i : other.indices) two.indices.push_back(i + std::uint32_t(two.positions.size()));
    two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
    EXPECT_EQ(kind_of([&] { check_sphere_topology(two, "two.obj"); }, &msg), Error::Kind::unsupported);
    EXPECT_TRUE(contains(msg, "2 components")) << msg;

    Mesh flipped = icosphere(1);
    std::swap(flipped.indices[1], flipped.indices[2]);
    EXPECT_EQ(kind_of([&] { check_sphere_topology(flipped, "flip.obj"); }, &msg), Error::Kind::invalid);
    EXPECT_TRUE(contains(msg, "inconsistently oriented")) << msg;

    Mesh extra = icosphere(1);
    extra.positions.push_back({5, 5, 5});
    EXPECT_EQ(kind_of([&] { check_sphere_topology(extra, "x.obj"); }, &msg), Error::Kind::invalid);
    EXPECT_TRUE(contains(msg, "used by no face")) << msg;
}

TEST(SphereMap, SpotMapsWithoutFolds)
{
    const SphereTopology t = check_sphere_topology(read_mesh(spot()), "spot");
    const SphereMap m = map_to_sphere(t, {}, "spot");
    ASSERT_EQ(m.points.size(), t.points.size());
    std::size_t folded = 0;
    for (const auto& f : t.faces) {
        folded += sphere_det(m.points[f[0]], m.points[f[1]], m.points[f[2]]) > 0 ? 0 : 1;
    }
    EXPECT_EQ(folded, 0u);
    for (const auto& p : m.points) EXPECT_NEAR(p[0] * p[0] + p[1] * p[1] + p[2] * p[2], 1.0, 1e-9);
    EXPECT_GT(m.min_face_orient, 0.0);
}

TEST(Supermesh, SpotAndIcosphere)
{
    const Mesh a = weld_copy(read_mesh(spot()));
    const Mesh b = icosphere(4, 0.6f, a.bounds().center());
    const Landmarks l = spot_sphere_landmarks(a, b, extremes(a));
    const SupermeshResult r = build_supermesh(a, b, l, {}, "spot", "ico", "l.json");
    expect_valid_supermesh(r, a, b);
    EXPECT_EQ(r.a_points, 2930u);
    EXPECT_EQ(r.b_points, 2562u);
    EXPECT_GT(r.crossings, 0u);
    // The landmark pairs meet: the sphere points of each pair coincide after the warp.
    for (const auto& p : l.pairs) {
        const auto& x = r.sphere_points[p.a];
        const auto& y = r.sphere_points[r.a_points + p.b];
        EXPECT_LT(std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]), 1e-4);
    }
}

namespace {

// The npm bunny (1,839 points, closed genus 0): `exports.positions=[[x,y,z],...]` and
// `exports.cells=[[i,j,k],...]` in a JavaScript file.
Mesh npm_bunny()
{
    std::ifstream in(test::shared_data("scan-bunny-npm/index.js"));
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto array_after = [&](const std::string& name) {
        std::size_t start = text.find(name);
        EXPECT_NE(start, std::string::npos) << name;
        start += name.size();
        std::size_t end = text.find("exports.", start);
        std::string s = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
        while (!s.empty() && (std::isspace(static_cast<unsigned char>(s.back())) || s.back() == ';')) s.pop_back();
        return nlohmann::json::parse(s);
    };
    Mesh m;
    for (const auto& p : array_after("exports.positions=")) m.positions.push_back({p[0].get<float>(), p[1].get<float>(), p[2].get<float>()});
    for (const auto& c : array_after("exports.cells="))
        for (int k = 0; k < 3; ++k) m.indices.push_back(c[std::size_t(k)].get<std::uint32_t>());
    return m;
}

}  // namespace

TEST(Supermesh, TwoRealMeshesSpotAndBunny)
{
    // Two real genus-0 scans with different connectivity, both at full size; landmarks at the extremes
    // (nose, tail, sides, top) of both, pairs matched by direction from each mesh's centre.
    const Mesh a = weld_copy(read_mesh(spot()));
    const Mesh b = npm_bunny();
    ASSERT_EQ(b.vertex_count(), 1839u);
    // Four pairs (Spot's extremes along +x, -y, +y, +z); more pairs below.
    std::vector<std::uint32_t> four = extremes(a);
    four.erase(four.begin());
    const Landmarks l = spot_sphere_landmarks(a, b, four);
    const SupermeshResult r = build_supermesh(a, b, l, {}, "spot", "bunny", "l.json");
    expect_valid_supermesh(r, a, b);
    EXPECT_GT(r.rotation_residual, r.landmark_residual);  // the warp did work beyond the rotation
}

namespace {

// Landmarks at recognisable places: the extreme vertex of each mesh along up to 14 directions (box
// axes, then the box diagonals) in each mesh's normalised box (nose, tail, back, belly, feet, ears...),
// A's and B's extremes along the same direction paired; a direction whose extreme repeats one already
// taken is skipped.
Landmarks direction_landmarks(const Mesh& a, const Mesh& b, std::size_t n)
{
    auto extreme = [](const Mesh& m, Vec3f d) {
        const Bounds box = m.bounds();
        const Vec3f c = box.center(), size = box.max - box.min;
        std::uint32_t best = 0;
        float best_value = -1e30f;
        for (std::uint32_t v = 0; v < m.vertex_count(); ++v) {
            const Vec3f p = m.positions[v] - c;
            const float value = dot(Vec3f{p.x / size.x, p.y / size.y, p.z / size.z}, d);
            if (value > best_value) best_value = value, best = v;
        }
        return best;
    };
    const std::vector<Vec3f> dirs = {{1, 0, 0},   {-1, 0, 0},  {0, 1, 0},  {0, -1, 0}, {0, 0, 1},  {0, 0, -1}, {1, 1, 1},
                                     {-1, -1, -1}, {1, -1, 1}, {-1, 1, -1}, {1, 1, -1}, {-1, -1, 1}, {-1, 1, 1}, {1, -1, -1}};
    Landmarks l;
    std::set<std::uint32_t> used_a, used_b;
    for (const Vec3f& d : dirs) {
        if (l.pairs.size() == n) break;
        const Vec3f u = d * (1.f / length(d));
        const std::uint32_t va = extreme(a, u), vb = extreme(b, u);
        if (used_a.count(va) || used_b.count(vb)) continue;
        used_a.insert(va), used_b.insert(vb);
        l.pairs.push_back({va, vb});
    }
    return l;
}

void expect_pairs_met(const SupermeshResult& r, const Landmarks& l)
{
    for (const auto& p : l.pairs) {
        const auto& x = r.sphere_points[p.a];
        const auto& y = r.sphere_points[r.a_points + p.b];
        EXPECT_LT(std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]), 1e-4);
    }
}

}  // namespace

TEST(Supermesh, SpotAndBunnyWithEightTenAndTwelvePairs)
{
    // 8, 10 and 12 well-spread pairs on two real meshes (the flow alone stalled beyond 4): Möbius
    // pre-alignment, both maps flowing halfway, local untangling with the landmarks held.
    const Mesh a = weld_copy(read_mesh(spot()));
    const Mesh b = npm_bunny();
    for (std::size_t n : {8u, 10u, 12u}) {
        const Landmarks l = direction_landmarks(a, b, n);
        ASSERT_EQ(l.pairs.size(), n);
        const SupermeshResult r = build_supermesh(a, b, l, {}, "spot", "bunny", "l.json");
        expect_valid_supermesh(r, a, b);
        expect_pairs_met(r, l);
        EXPECT_LT(r.landmark_residual, 1e-5) << n;
        EXPECT_LE(r.mobius_residual, r.rotation_residual) << n;  // the Möbius map is kept only when it helps
    }
}

TEST(Supermesh, SpotAndIcosphereWithTenPairs)
{
    const Mesh a = weld_copy(read_mesh(spot()));
    const Mesh b = icosphere(4, 0.6f, a.bounds().center());
    // Spot's extremes along the 14 directions, each paired with the sphere vertex in its direction.
    std::vector<std::uint32_t> spots;
    for (const auto& p : direction_landmarks(a, a, 14).pairs) spots.push_back(p.a);
    Landmarks l;
    std::set<std::uint32_t> taken;
    for (const auto& p : spot_sphere_landmarks(a, b, spots).pairs)
        if (taken.insert(p.b).second && l.pairs.size() < 10) l.pairs.push_back(p);
    ASSERT_GE(l.pairs.size(), 8u);
    SupermeshResult r;
    try {
        r = build_supermesh(a, b, l, {}, "spot", "ico", "l.json");
    } catch (const Error& e) {
        FAIL() << e.what();
    }
    expect_valid_supermesh(r, a, b);
    expect_pairs_met(r, l);
}

TEST(Supermesh, WedgeMeshesAndTheMorphPipeline)
{
    // Spot as read (texcoord seams: 3,225 wedges on 2,930 points): points are what gets overlaid, and the
    // supermesh then goes through LOD, the .lfmorph file and extraction like any MorphMesh.
    test::ScratchDir dir("supermesh-pipeline");
    const Mesh a = read_mesh(spot());
    const Mesh b = icosphere(3, 0.5f, a.bounds().center());
    write_mesh(b, dir.file("ball.ply"));
    Landmarks l = spot_sphere_landmarks(a, b, extremes(a));
    write_landmarks(l, dir.file("l.json"));
    SupermeshParams params;
    params.frames = 4;
    const MorphMesh m = load_supermesh(spot(), dir.file("ball.ply"), dir.file("l.json"), params);
    ASSERT_EQ(m.frame_count(), 4u);
    EXPECT_EQ(m.frame_names.front(), spot());
    // Frame 1 of 4 is the blend at t = 1/3, exactly.
    const Mesh third = morph_mesh_at(m, 1.0 / 3);
    for (std::size_t v = 0; v < m.vertex_count(); v += 97) {
        EXPECT_NEAR(third.positions[v].x, m.frame_positions[1][v].x, 1e-5);
        EXPECT_NEAR(third.positions[v].z, m.frame_positions[1][v].z, 1e-5);
    }
    EXPECT_NO_THROW(check_sphere_topology(m.base, "supermesh"));

    // Two wedges of one point in two pairs is one point asked to be in two places.
    std::uint32_t w0 = 0, w1 = 0;
    for (std::uint32_t v = 0; v < a.vertex_count() && !w1; ++v)
        for (std::uint32_t u = 0; u < v; ++u)
            if (a.position_ids[u] == a.position_ids[v]) {
                w0 = u, w1 = v;
                break;
            }
    ASSERT_NE(w1, 0u);
    Landmarks twice;
    twice.pairs = {{w0, 0}, {w1, 5}};
    std::string msg;
    EXPECT_EQ(kind_of([&] { build_supermesh(a, b, twice, {}, "spot", "ball", "l.json"); }, &msg), Error::Kind::invalid);
    EXPECT_TRUE(contains(msg, "l.json") && contains(msg, "same point")) << msg;
}

TEST(Supermesh, BadLandmarksAndTopologiesAreRejected)
{
    const Mesh a = icosphere(2);
    const Mesh b = icosphere(3);
    std::string msg;
    Landmarks none;
    EXPECT_EQ(kind_of([&] { build_supermesh(a, b, none, {}, "a", "b", "l.json"); }, &msg), Error::Kind::invalid);
    EXPECT_TRUE(contains(msg, "l.json") && contains(msg, "no landmark")) << msg;
    Landmarks out_of_range;
    out_of_range.pairs = {{0, 642}};  // b has 642 vertices
    EXPECT_EQ(kind_of([&] { build_supermesh(a, b, out_of_range, {}, "a", "b", "l.json"); }, &msg), Error::Kind::invalid);
    EXPECT_TRUE(contains(msg, "l.json")) << msg;

    // Pairs that need a warp, with no warp steps allowed: refused, naming the landmark file. (Three pairs
    // in mirrored order are no such case: a Möbius map takes any three points to any three, and the
    // supermesh is valid, if twisted.)
    Landmarks mirrored;
    mirrored.pairs = {{0, 0}, {5, 1}, {1, 5}};  // icosphere vertices 0, 1, 5 form a face: (0, 5, 1) turns the other way
    const SupermeshResult twisted = build_supermesh(a, b, mirrored, {}, "a", "b", "mirror.json");
    EXPECT_LT(twisted.landmark_residual, 1e-5);
    EXPECT_NO_THROW(check_sphere_topology(twisted.morph.base, "supermesh"));
    Landmarks four = mirrored;
    four.pairs.push_back({2, 2});
    SupermeshParams no_steps;
    no_steps.max_warp_steps = 0;
    EXPECT_EQ(kind_of([&] { build_supermesh(a, b, four, no_steps, "a", "b", "four.json"); }, &msg), Error::Kind::invalid);
    EXPECT_TRUE(contains(msg, "four.json") && contains(msg, "cannot be brought together")) << msg;

    Landmarks one;
    one.pairs = {{0, 0}};
    EXPECT_EQ(kind_of([&] { build_supermesh(torus(16, 8), b, one, {}, "torus.obj", "b", "l.json"); }, &msg),
              Error::Kind::unsupported);
    EXPECT_TRUE(contains(msg, "torus.obj") && contains(msg, "genus 1")) << msg;
    Mesh inside_out = b;
    for (std::size_t i = 0; i < inside_out.indices.size(); i += 3) std::swap(inside_out.indices[i + 1], inside_out.indices[i + 2]);
    EXPECT_EQ(kind_of([&] { build_supermesh(a, inside_out, one, {}, "a", "inv.obj", "l.json"); }, &msg), Error::Kind::invalid);
    EXPECT_TRUE(contains(msg, "inv.obj") && contains(msg, "inwards")) << msg;
}

TEST(CliSupermesh, BuildInfoExtractAndErrors)
{
    test::ScratchDir dir("cli-supermesh");
    const Mesh a = read_mesh(spot());
    write_mesh(icosphere(3, 0.5f, a.bounds().center()), dir.file("ball.obj"));
    write_mesh(torus(20, 10), dir.file("torus.obj"));
    const Mesh ball = read_mesh(dir.file("ball.obj"));
    write_landmarks(spot_sphere_landmarks(a, ball, extremes(a)), dir.file("l.json"));
    const std::string out = dir.file("s.lfmorph");
    auto r = test::run_cli("morph build " + test::quoted(spot()) + " " + test::quoted(dir.file("ball.obj")) + " --landmarks " +
                           test::quoted(dir.file("l.json")) + " -o " + test::quoted(out) + " --levels 0.5,0.1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "2 frames")) << r.out;
    r = test::run_cli("morph info " + test::quoted(out) + " --json", false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["frames"], 2);
    EXPECT_GT(j["vertices"].get<std::size_t>(), 2930u + 642u);  // every point of both, plus the crossings
    r = test::run_cli("morph extract " + test::quoted(out) + " --t 1 --lod 1 -o " + test::quoted(dir.file("b.ply")));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const Mesh shape_b = read_mesh(dir.file("b.ply"));
    // At t = 1 every vertex lies on the ball (16-bit positions: within the quantisation step).
    const Vec3f c = a.bounds().center();
    float worst = 0;
    for (const Vec3f& p : shape_b.positions) worst = std::max(worst, std::fabs(length(p - c) - 0.5f));
    EXPECT_LT(worst, 0.01f);

    // --frames 3: the blend sampled at t = 0, 0.5, 1 as keyframes.
    r = test::run_cli("morph build " + test::quoted(spot()) + " " + test::quoted(dir.file("ball.obj")) + " --landmarks " +
                      test::quoted(dir.file("l.json")) + " -o " + test::quoted(dir.file("s3.lfmorph")) +
                      " --levels 0.5 --frames 3 --order per-frame");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "3 frames") && contains(r.out, "3 sequence(s)")) << r.out;

    Landmarks first;
    first.pairs = {{0, 0}};
    write_landmarks(first, dir.file("l0.json"));
    r = test::run_cli("morph build " + test::quoted(dir.file("torus.obj")) + " " + test::quoted(dir.file("ball.obj")) +
                      " --landmarks " + test::quoted(dir.file("l0.json")) + " -o " + test::quoted(dir.file("t.lfmorph")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "lodforge: error: " + dir.file("torus.obj")) && contains(r.out, "genus 1")) << r.out;
    r = test::run_cli("morph build " + test::quoted(bunny()) + " " + test::quoted(dir.file("ball.obj")) + " --landmarks " +
                      test::quoted(dir.file("l0.json")) + " -o " + test::quoted(dir.file("t.lfmorph")));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.out, "border edges")) << r.out;
    r = test::run_cli("morph build " + test::quoted(spot()) + " " + test::quoted(dir.file("ball.obj")) + " -o " +
                      test::quoted(dir.file("t.lfmorph")));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_TRUE(contains(r.out, "--landmarks")) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("t.lfmorph")));
}
