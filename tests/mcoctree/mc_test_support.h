// Helpers shared by the marching-cube octree tests: synthetic closed inputs and a watertightness check.
#pragma once

#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

namespace lodforge::test {

// Fibonacci-sampled sphere point cloud with outward normals (no faces), optionally coloured by height.
inline Mesh sphere_points(std::size_t n, float radius = 1.f, bool colors = false) {
    Mesh m;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (std::size_t i = 0; i < n; ++i) {
        const double y = 1.0 - 2.0 * (double(i) + 0.5) / double(n);
        const double r = std::sqrt(1.0 - y * y), phi = golden * double(i);
        const Vec3f d{float(r * std::cos(phi)), float(y), float(r * std::sin(phi))};
        m.positions.push_back(d * radius);
        m.normals.push_back(d);
        if (colors) m.colors.push_back({float(0.5 + 0.5 * y), 0.2f, float(0.5 - 0.5 * y), 1.f});
    }
    return m;
}

struct Watertight {
    std::size_t border_edges = 0;      // undirected edges with one triangle
    std::size_t unpaired_directed = 0; // directed edges without an opposite (orientation breaks)
    std::size_t degenerate = 0;        // triangles with a repeated vertex
};

// Vertices are identified by index after welding only exactly identical positions.
inline Watertight check_watertight(const Mesh& m) {
    std::map<std::tuple<float, float, float>, std::uint32_t> weld;
    std::vector<std::uint32_t> id(m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const Vec3f p = m.positions[i];
        id[i] = weld.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<std::uint32_t>(weld.size())).first->second;
    }
    Watertight w;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const std::uint32_t v[3] = {id[m.indices[t]], id[m.indices[t + 1]], id[m.indices[t + 2]]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
            ++w.degenerate;
            continue;
        }
        for (int k = 0; k < 3; ++k) ++directed[{v[k], v[(k + 1) % 3]}];
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> undirected;
    for (const auto& [e, c] : directed) {
        undirected[{std::min(e.first, e.second), std::max(e.first, e.second)}] += c;
        const auto it = directed.find({e.second, e.first});
        if (it == directed.end() || it->second != c) w.unpaired_directed += std::size_t(c);
    }
    for (const auto& [e, c] : undirected) w.border_edges += c == 1;
    return w;
}

// The whole tree, field-derived parts included (vertex positions, normals, colours, masks, numbering).
// `normals`: compare the vertex normals too (off where the inputs' normals differ by rounding).
inline void expect_same_tree(const McOctree& a, const McOctree& b, const char* what, bool normals = true) {
    SCOPED_TRACE(what);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const McNode &x = a.nodes[i], &y = b.nodes[i];
        ASSERT_TRUE(x.x == y.x && x.y == y.y && x.z == y.z && x.level == y.level && x.child_mask == y.child_mask &&
                    x.first_child == y.first_child && x.parent == y.parent && x.inside == y.inside &&
                    x.crossings == y.crossings && x.first_vertex == y.first_vertex && x.priority == y.priority)
            << "node " << i;
    }
    EXPECT_EQ(a.positions, b.positions);
    if (normals) {
        EXPECT_EQ(a.normals, b.normals);
    }
    EXPECT_EQ(a.colors, b.colors);
    EXPECT_EQ(a.vertex_ids, b.vertex_ids);
    EXPECT_EQ(a.neighbours, b.neighbours);
    EXPECT_EQ(a.order, b.order);
    EXPECT_EQ(a.cuts, b.cuts);
    EXPECT_EQ(a.triangle_counts, b.triangle_counts);
    EXPECT_EQ(a.metric, b.metric);
}

}  // namespace lodforge::test
