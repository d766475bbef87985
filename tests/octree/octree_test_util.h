// Helpers shared by the out-of-core octree tests.
#pragma once

#include "lodforge/mesh.h"

#include <cstddef>
#include <cstdint>
#include <unordered_map>

namespace lodforge::test {

struct EdgeCounts {
    std::size_t border = 0;        // undirected edges used by exactly one triangle
    std::size_t non_manifold = 0;  // used by more than two
    std::size_t edges = 0;
    std::size_t unpaired = 0;      // directed edges a→b used a different number of times than b→a
};

// Topology by vertex index (the octree shares vertices between nodes by input index), so a crack shows
// up as border edges; degenerate triangles are ignored.
inline EdgeCounts edge_counts(const Mesh& m) {
    std::unordered_map<std::uint64_t, int> uses, directed;
    uses.reserve(m.indices.size());
    directed.reserve(m.indices.size());
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = m.indices[3 * t + k], b = m.indices[3 * t + (k + 1) % 3];
            if (a == b) continue;
            ++directed[std::uint64_t{a} << 32 | b];
            if (a > b) std::swap(a, b);
            ++uses[std::uint64_t{a} << 32 | b];
        }
    EdgeCounts c;
    c.edges = uses.size();
    for (const auto& [key, n] : uses) {
        if (n == 1) ++c.border;
        if (n > 2) ++c.non_manifold;
    }
    for (const auto& [key, n] : directed) {
        const std::uint64_t reverse = (key << 32) | (key >> 32);
        const auto it = directed.find(reverse);
        if (it == directed.end() || it->second != n) ++c.unpaired;
    }
    return c;
}

}  // namespace lodforge::test
