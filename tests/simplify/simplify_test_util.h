// Topology checks on points (position_ids) shared by the simplification tests.
#pragma once

#include "lodforge/mesh.h"

#include <algorithm>
#include <cstdint>
#include <map>
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

}  // namespace lodforge::test
