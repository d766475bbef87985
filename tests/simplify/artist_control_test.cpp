// Artist control in the collapse simplifier (issue 31, docs/artist-control.md): a painted region keeps
// its detail at the same triangle count, locked vertices stay bit for bit in simplify() output and in
// every level of a chain, with half-edge and optimal placement, and bad masks are refused.
#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/simplify/lod_chain.h"
#include "lodforge/simplify/simplify.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace lodforge;

namespace {

const Mesh& spot() {
    static const Mesh m = read_mesh(test::sample("spot/spot_triangulated.obj"));
    return m;
}

// Spot's head: the vertices within 0.3 of (0, 0.65, -0.3) in the sample's coordinates (y up, the head
// towards -z; the sphere takes the head, a sixth of the vertices, and nothing of the body or legs).
bool in_head(Vec3f p) {
    const Vec3f d = p - Vec3f{0.f, 0.65f, -0.3f};
    return dot(d, d) < 0.3f * 0.3f;
}

// The input's faces with every corner in the head, as a mesh of their own.
Mesh head_of(const Mesh& in) {
    Mesh head;
    head.positions = in.positions;
    for (std::size_t f = 0; f < in.triangle_count(); ++f) {
        const std::uint32_t* i = &in.indices[3 * f];
        if (in_head(in.positions[i[0]]) && in_head(in.positions[i[1]]) && in_head(in.positions[i[2]]))
            head.indices.insert(head.indices.end(), i, i + 3);
    }
    return head;
}

// Mean distance from the input's head surface to the simplified mesh.
double head_error(const Mesh& head, const Mesh& out) {
    DistanceParams d;
    d.vertex_errors = false;
    d.include_vertices = false;
    d.samples = 100000;
    return compare(out, head, d).test_to_reference.mean;
}

bool same_bits(Vec3f a, Vec3f b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Locks every vertex in a band across the body and every 37th vertex elsewhere.
std::vector<std::uint8_t> lock_mask(const Mesh& m) {
    std::vector<std::uint8_t> lock(m.vertex_count(), 0);
    const Bounds b = m.bounds();
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const float t = (m.positions[v].x - b.min.x) / (b.max.x - b.min.x);
        lock[v] = (t > 0.47f && t < 0.53f) || v % 37 == 0;
    }
    return lock;
}

// Every vertex of the output that comes from a locked input vertex has its position and attributes bit
// for bit (normals renormalised, as every output normal is), and every locked point of the input (its
// position) is still in the output.
void expect_locked_kept(const Mesh& in, const std::vector<std::uint8_t>& lock, const Mesh& out,
                        const std::vector<std::uint32_t>& input_vertex) {
    std::vector<std::uint8_t> used(in.vertex_count(), 0);
    for (std::uint32_t i : in.indices) used[i] = 1;
    std::vector<std::uint8_t> present(in.vertex_count(), 0);
    std::size_t checked = 0;
    for (std::size_t v = 0; v < out.vertex_count(); ++v) {
        const std::uint32_t iv = input_vertex[v];
        if (!lock[iv]) continue;
        present[iv] = 1;
        ++checked;
        EXPECT_TRUE(same_bits(out.positions[v], in.positions[iv])) << "vertex " << iv;
        if (in.has_normals()) {
            const Vec3f n = in.normals[iv];
            EXPECT_TRUE(same_bits(out.normals[v], length(n) > 0.f ? n * (1.f / length(n)) : n)) << "vertex " << iv;
        }
        for (std::size_t s = 0; s < in.texcoords.size(); ++s) {
            if (in.texcoords[s].empty()) continue;
            EXPECT_EQ(std::memcmp(&out.texcoords[s][v], &in.texcoords[s][iv], sizeof(Vec2f)), 0) << "vertex " << iv;
        }
    }
    EXPECT_GT(checked, 0u);
    // Locked points: some vertex at the position survives (a wedge nothing uses any more may go).
    for (std::size_t v = 0; v < in.vertex_count(); ++v) {
        if (!lock[v] || !used[v] || present[v]) continue;
        bool found = false;
        for (std::size_t w = 0; w < out.vertex_count() && !found; ++w) found = same_bits(out.positions[w], in.positions[v]);
        EXPECT_TRUE(found) << "locked vertex " << v << " was removed";
    }
}

}  // namespace

TEST(ArtistControl, PaintedHeadKeepsItsDetail) {
    const Mesh& in = spot();
    std::vector<float> importance(in.vertex_count(), 0.f);
    std::size_t painted = 0;
    for (std::size_t v = 0; v < in.vertex_count(); ++v)
        if (in_head(in.positions[v])) importance[v] = 1.f, ++painted;
    ASSERT_GT(painted, in.vertex_count() / 8);
    ASSERT_LT(painted, in.vertex_count() / 4);
    const Mesh head = head_of(in);

    SimplifyParams p;
    p.target_ratio = 0.05f;
    const SimplifyResult plain = simplify(in, p);
    p.importance = importance;
    const SimplifyResult painted_run = simplify(in, p);
    const double before = head_error(head, plain.mesh), after = head_error(head, painted_run.mesh);
    DistanceParams d;
    d.vertex_errors = false;
    std::printf("Spot 5%%: head mean error %.3e unpainted, %.3e painted (%.1fx lower); whole model %.3e, %.3e; "
                "%zu and %zu triangles\n",
                before, after, before / after, compare(in, plain.mesh, d).mean_relative,
                compare(in, painted_run.mesh, d).mean_relative, plain.triangles, painted_run.triangles);
    EXPECT_GE(before, 3.0 * after);
    EXPECT_NEAR(double(painted_run.triangles), double(plain.triangles), 0.01 * double(plain.triangles));
}

TEST(ArtistControl, ZeroImportanceChangesNothing) {
    // Importance 0 everywhere takes the general cost path; it must give the fast paths' result.
    const Mesh& in = spot();
    SimplifyParams p;
    p.target_ratio = 0.2f;
    const SimplifyResult a = simplify(in, p);
    p.importance.assign(in.vertex_count(), 0.f);
    const SimplifyResult b = simplify(in, p);
    EXPECT_EQ(a.mesh.indices, b.mesh.indices);
}

TEST(ArtistControl, LockedVerticesStayInSimplifyOutput) {
    for (const char* name : {"spot", "duck"}) {
        const Mesh in = std::string(name) == "spot" ? spot() : read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"));
        for (Placement placement : {Placement::half_edge, Placement::optimal}) {
            SCOPED_TRACE(std::string(name) + (placement == Placement::optimal ? " optimal" : " half-edge"));
            SimplifyParams p;
            p.target_ratio = 0.1f;
            p.placement = placement;
            p.lock = lock_mask(in);
            const SimplifyResult r = simplify(in, p);
            EXPECT_LT(r.triangles, in.triangle_count() / 2);
            expect_locked_kept(in, p.lock, r.mesh, r.vertex_map);
        }
    }
}

TEST(ArtistControl, LockingOneWedgeLocksThePoint) {
    // Spot's UV seams give several vertices at one position: locking only the first of them must keep
    // the others at that position too (a point moves as a whole).
    const Mesh& in = spot();
    std::vector<std::uint8_t> lock(in.vertex_count(), 0), seam(in.vertex_count(), 0);
    std::size_t seams = 0;
    for (std::size_t v = 0; v < in.vertex_count(); ++v)
        for (std::size_t w = 0; w < v; ++w)
            if (same_bits(in.positions[v], in.positions[w])) {
                if (seams % 2 == 0) lock[w] = 1;  // half the seam points, through their first wedge only
                seam[v] = 1;
                ++seams;
                break;
            }
    ASSERT_GT(seams, 10u);
    SimplifyParams p;
    p.target_ratio = 0.05f;
    p.lock = lock;
    const SimplifyResult r = simplify(in, p);
    std::vector<std::uint8_t> point_locked(in.vertex_count(), 0);
    for (std::size_t v = 0; v < in.vertex_count(); ++v)
        for (std::size_t w = 0; w < in.vertex_count(); ++w)
            if (lock[w] && same_bits(in.positions[v], in.positions[w])) point_locked[v] = 1;
    expect_locked_kept(in, point_locked, r.mesh, r.vertex_map);
}

TEST(ArtistControl, LockedVerticesStayInEveryLevel) {
    const Mesh& in = spot();
    LodChainParams p;
    p.levels = lod_levels_from_ratios({0.5f, 0.35f, 0.25f, 0.2f});  // ~300 locked points: 0.1 would stop short
    p.measure = false;
    p.simplify.lock = lock_mask(in);
    p.simplify.importance.assign(in.vertex_count(), 0.f);
    for (std::size_t v = 0; v < in.vertex_count(); ++v) p.simplify.importance[v] = in_head(in.positions[v]) ? 1.f : 0.f;
    const LodChainResult r = build_lod_chain(in, p);
    ASSERT_EQ(r.levels.size(), 5u);
    for (std::size_t l = 1; l < r.levels.size(); ++l) {
        SCOPED_TRACE("level " + std::to_string(l));
        EXPECT_LT(r.levels[l].triangles, r.levels[l - 1].triangles);
        expect_locked_kept(in, p.simplify.lock, r.levels[l].mesh, r.levels[l].input_vertex);
    }
}

TEST(ArtistControl, SoupKeepsItsMasks) {
    // A triangle soup is simplified on its merged vertices: the masks must follow them there.
    const Mesh& in = spot();
    Mesh soup;
    soup.positions.reserve(in.indices.size());
    for (std::uint32_t i : in.indices) {
        soup.indices.push_back(static_cast<std::uint32_t>(soup.positions.size()));
        soup.positions.push_back(in.positions[i]);
    }
    std::vector<std::uint8_t> lock(soup.vertex_count(), 0);
    const Bounds b = soup.bounds();
    for (std::size_t v = 0; v < soup.vertex_count(); ++v) lock[v] = soup.positions[v].y > b.max.y - 0.1f * (b.max.y - b.min.y);
    SimplifyParams p;
    p.target_ratio = 0.1f;
    p.lock = lock;
    const SimplifyResult r = simplify(soup, p);
    expect_locked_kept(soup, lock, r.mesh, r.vertex_map);
}

TEST(ArtistControl, BadMasksAreRefused) {
    const Mesh& in = spot();
    SimplifyParams p;
    p.target_ratio = 0.5f;
    auto refused = [&](const SimplifyParams& q, const char* what) {
        try {
            simplify(in, q);
            ADD_FAILURE() << "accepted " << what;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::argument) << what;
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    SimplifyParams q = p;
    q.importance.assign(in.vertex_count() - 1, 0.f);
    refused(q, "importance has");
    q.importance.assign(in.vertex_count(), 0.f);
    q.importance[7] = std::numeric_limits<float>::quiet_NaN();
    refused(q, "vertex 7");
    q.importance[7] = 1.5f;
    refused(q, "outside [0, 1]");
    q = p;
    q.lock.assign(3, 1);
    refused(q, "lock has");
}
