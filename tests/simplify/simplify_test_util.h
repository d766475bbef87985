// Topology checks on points (position_ids) shared by the simplification tests.
#pragma once

#include "lodforge/mesh.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <tuple>
#include <utility>
#include <vector>

namespace lodforge::test {

struct EdgeCounts {
    std::size_t border = 0;        // edges (on points) with one face
    std::size_t non_manifold = 0;  // edges with more than two faces
};

inline EdgeCounts count_edges(const Mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    auto pid = [&](std::uint32_t v) { return m.position_ids.empty() ? v : m.position_ids[v]; };
    for (std::size_t f = 0; f < m.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = pid(m.indices[3 * f + k]), b = pid(m.indices[3 * f + (k + 1) % 3]);
            if (a == b) continue;
            if (a > b) std::swap(a, b);
            ++edges[{a, b}];
        }
    EdgeCounts c;
    for (const auto& [e, n] : edges) {
        if (n == 1) ++c.border;
        if (n > 2) ++c.non_manifold;
    }
    return c;
}

// Faces with two corners on one point, or with zero area.
inline std::size_t count_degenerate(const Mesh& m) {
    std::size_t n = 0;
    auto pid = [&](std::uint32_t v) { return m.position_ids.empty() ? v : m.position_ids[v]; };
    for (std::size_t f = 0; f < m.triangle_count(); ++f) {
        const std::uint32_t* i = &m.indices[3 * f];
        if (pid(i[0]) == pid(i[1]) || pid(i[1]) == pid(i[2]) || pid(i[0]) == pid(i[2])) { ++n; continue; }
        const Vec3f c = cross(m.positions[i[1]] - m.positions[i[0]], m.positions[i[2]] - m.positions[i[0]]);
        if (!(dot(c, c) > 0.f)) ++n;
    }
    return n;
}

// UV islands (charts) of a mesh: faces joined through a shared wedge (vertex), or through wedges at one
// point with the same texture coordinates (duplicates across glTF primitives are no seam). Returns the
// island of every vertex.
inline std::vector<std::uint32_t> wedge_islands(const Mesh& in) {
    const std::size_t nf = in.triangle_count();
    std::vector<std::uint32_t> parent(nf);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    auto pid = [&](std::uint32_t v) { return in.position_ids.empty() ? v : in.position_ids[v]; };
    std::map<std::tuple<std::uint32_t, float, float>, std::uint32_t> first_face;  // (point, u, v) -> face
    for (std::uint32_t f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = in.indices[3 * f + k];
            const Vec2f t = in.has_texcoords() ? in.texcoords[0][v] : Vec2f{};
            auto [it, inserted] = first_face.emplace(std::make_tuple(pid(v), t.x, t.y), f);
            if (!inserted) parent[find(f)] = find(it->second);
        }
    std::vector<std::uint32_t> island(in.vertex_count(), 0);
    for (std::uint32_t f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) island[in.indices[3 * f + k]] = find(f);
    return island;
}

// Faces of `out` (vertex_map: output vertex -> input vertex) whose corners come from different UV islands
// of `in`: their texture would be interpolated across charts (slits along the seams).
inline std::size_t faces_across_islands(const Mesh& in, const Mesh& out, const std::vector<std::uint32_t>& vertex_map) {
    const std::vector<std::uint32_t> island = wedge_islands(in);
    std::size_t across = 0;
    for (std::size_t f = 0; f < out.triangle_count(); ++f) {
        const std::uint32_t* i = &out.indices[3 * f];
        const std::uint32_t a = island[vertex_map[i[0]]], b = island[vertex_map[i[1]]], c = island[vertex_map[i[2]]];
        across += (a != b || b != c);
    }
    return across;
}

}  // namespace lodforge::test
