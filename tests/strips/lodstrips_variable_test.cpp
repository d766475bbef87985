// Variable resolution: a per-vertex criterion with the collapse dependencies respected.
#include "strips/lodstrips_test_util.h"

#include <gtest/gtest.h>

#include <set>

namespace lodforge {
namespace {

using test::built;
using test::BuiltModel;

std::vector<std::uint32_t> triangles_of(const lodstrips::Data& d, const VariableResolution& v) {
    std::vector<std::uint32_t> out;
    for (std::size_t s = 0; s < d.strip_count(); ++s) {
        const std::uint32_t* p = v.indices.data() + d.strip_offsets[s];
        for (std::int32_t i = 0; i + 2 < v.draw_counts[s]; ++i) {
            std::uint32_t a = p[i], b = p[i + 1], c = p[i + 2];
            if (a == b || b == c || a == c) continue;
            if (i & 1) std::swap(a, b);
            out.insert(out.end(), {a, b, c});
        }
    }
    return out;
}

// The full-resolution faces (canonical numbers), from the strips.
std::vector<std::uint32_t> full_faces(const lodstrips::Data& d) {
    lodstrips::LodStrips rt;
    EXPECT_TRUE(rt.assign(d));
    std::vector<std::uint32_t> f;
    rt.triangles(f);
    return f;
}

// Independent of the strips: each face's corners mapped through the applied collapses.
std::vector<std::uint32_t> mapped_faces(const lodstrips::Data& d, const std::vector<std::uint8_t>& applied) {
    std::vector<std::uint32_t> to(d.vertex_count);
    for (std::uint32_t v = 0; v < d.vertex_count; ++v) to[v] = v;
    for (std::size_t k = 0; k < d.collapse_count(); ++k)
        if (applied[k])
            for (std::uint32_t o = d.collapse_begin[k]; o < d.collapse_begin[k + 1]; ++o) to[d.vertex_of_ordinal(o)] = d.targets[o];
    std::vector<std::uint32_t> out;
    const std::vector<std::uint32_t> faces = full_faces(d);
    for (std::size_t i = 0; i < faces.size(); i += 3) {
        std::uint32_t c[3];
        for (int k = 0; k < 3; ++k) {
            std::uint32_t v = faces[i + k];
            while (to[v] != v) v = to[v];
            c[k] = v;
        }
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        out.insert(out.end(), {c[0], c[1], c[2]});
    }
    return out;
}

class VariableResolutionReal : public ::testing::TestWithParam<std::pair<std::string, StripJoin>> {};

TEST_P(VariableResolutionReal, DistanceCriterionGivesAConsistentCut) {
    const BuiltModel& m = built(GetParam().first, GetParam().second);
    const lodstrips::Data& d = m.build.data;
    const LodStripsDependencies deps = lodstrips_dependencies(d);
    const std::size_t K = d.collapse_count();
    ASSERT_EQ(deps.begin.size(), K + 1);

    // Extremes: everything coarse is the coarsest level, nothing coarse is full detail.
    lodstrips::LodStrips rt;
    ASSERT_TRUE(rt.assign(d));
    std::vector<std::uint32_t> level;
    const VariableResolution all = extract_variable_resolution(d, deps, [](std::uint32_t) { return true; });
    EXPECT_EQ(all.collapses_applied, K);
    rt.go_to_level(K);
    rt.triangles(level);
    EXPECT_TRUE(test::sorted_tris(triangles_of(d, all)) == test::sorted_tris(level));
    const VariableResolution none = extract_variable_resolution(d, deps, [](std::uint32_t) { return false; });
    EXPECT_EQ(none.collapses_applied, 0u);
    EXPECT_EQ(none.indices, d.initial_indices);

    // Fine around one end of the model, coarse elsewhere.
    const Vec3f center{d.positions[0], d.positions[1], d.positions[2]};
    Bounds b;
    for (std::uint32_t v = 0; v < d.vertex_count; ++v) b.add({d.positions[3 * v], d.positions[3 * v + 1], d.positions[3 * v + 2]});
    const float radius = 0.3f * b.diagonal();
    const VariableResolution var = extract_variable_resolution(d, deps, center, radius);
    EXPECT_GT(var.collapses_applied, K / 10);
    EXPECT_LT(var.collapses_applied, K);
    // Closed under dependencies.
    for (std::size_t k = 0; k < K; ++k) {
        if (!var.applied[k]) continue;
        for (std::uint32_t i = deps.begin[k]; i < deps.begin[k + 1]; ++i)
            ASSERT_TRUE(var.applied[deps.parents[i]]) << "collapse " << k << " applied without its parent";
    }
    // No collapse of a vertex inside the sphere is applied.
    for (std::size_t k = 0; k < K; ++k) {
        const std::uint32_t v = d.vertex_of_ordinal(d.collapse_begin[k]);
        const Vec3f p{d.positions[3 * v], d.positions[3 * v + 1], d.positions[3 * v + 2]};
        if (length(p - center) <= radius) {
            ASSERT_FALSE(var.applied[k]);
        }
    }
    // The strips draw what the indexed mesh gives for the same cut, with the input winding.
    const std::vector<std::uint32_t> got = triangles_of(d, var);
    EXPECT_EQ(got.size() / 3, var.triangles);
    EXPECT_TRUE(test::sorted_tris(got) == test::sorted_tris(mapped_faces(d, var.applied)));
    EXPECT_GT(var.triangles, d.triangles.back());
    EXPECT_LT(var.triangles, d.triangles.front());

    // Every face is in a state it has at some uniform level (its own changes were applied in order).
    const std::vector<std::uint32_t> faces = full_faces(d);
    const std::size_t nf = faces.size() / 3;
    std::vector<std::vector<test::Tri>> history(nf);
    std::vector<test::Tri> state(nf);
    std::vector<std::vector<std::uint32_t>> faces_of(d.vertex_count);
    for (std::uint32_t f = 0; f < nf; ++f) {
        state[f] = {faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]};
        history[f].push_back(state[f]);
        for (std::uint32_t v : state[f]) faces_of[v].push_back(f);
    }
    for (std::size_t k = 0; k < K; ++k)
        for (std::uint32_t o = d.collapse_begin[k]; o < d.collapse_begin[k + 1]; ++o) {
            const std::uint32_t v = d.vertex_of_ordinal(o), t = d.targets[o];
            for (std::uint32_t f : faces_of[v]) {
                for (std::uint32_t& c : state[f])
                    if (c == v) c = t;
                history[f].push_back(state[f]);
                faces_of[t].push_back(f);
            }
            faces_of[v].clear();
        }
    std::vector<std::uint32_t> to(d.vertex_count);
    for (std::uint32_t v = 0; v < d.vertex_count; ++v) to[v] = v;
    for (std::size_t k = 0; k < K; ++k)
        if (var.applied[k])
            for (std::uint32_t o = d.collapse_begin[k]; o < d.collapse_begin[k + 1]; ++o) to[d.vertex_of_ordinal(o)] = d.targets[o];
    for (std::uint32_t f = 0; f < nf; ++f) {
        test::Tri t;
        for (int k = 0; k < 3; ++k) {
            std::uint32_t v = faces[3 * f + k];
            while (to[v] != v) v = to[v];
            t[k] = v;
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // gone: no state to compare
        ASSERT_NE(std::find(history[f].begin(), history[f].end(), t), history[f].end())
            << "face " << f << " is in a state no uniform level has";
    }
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, VariableResolutionReal,
                         ::testing::Values(std::pair{std::string("dragon_res4"), StripJoin::restart},
                                           std::pair{std::string("spot"), StripJoin::degenerate}),
                         [](const auto& param_info) { return param_info.param.first; });

}  // namespace
}  // namespace lodforge
