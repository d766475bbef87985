#include "mcoctree/mc_winding.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace lodforge::mc {

namespace {

constexpr std::uint32_t kLeafSize = 8;

struct Builder {
    const Mesh& mesh;
    WindingTree& tree;
    std::vector<Vec3f> centroid;

    Vec3f corner(std::uint32_t t, int k) const { return mesh.positions[mesh.indices[3 * std::size_t(t) + std::size_t(k)]]; }

    std::uint32_t build(std::uint32_t first, std::uint32_t count) {
        const auto id = static_cast<std::uint32_t>(tree.nodes.size());
        tree.nodes.emplace_back();
        // Dipole: vector area and area-weighted centre.
        double ax = 0, ay = 0, az = 0, cx = 0, cy = 0, cz = 0, weight = 0;
        Bounds box;
        for (std::uint32_t i = first; i < first + count; ++i) {
            const std::uint32_t t = tree.order[i];
            const Vec3f a = corner(t, 0), b = corner(t, 1), c = corner(t, 2);
            const Vec3f n = cross(b - a, c - a);
            ax += 0.5 * n.x, ay += 0.5 * n.y, az += 0.5 * n.z;
            const double w = 0.5 * double(length(n));
            cx += w * centroid[t].x, cy += w * centroid[t].y, cz += w * centroid[t].z, weight += w;
            box.add(a), box.add(b), box.add(c);
        }
        WindingTree::Node node;
        node.area = {float(ax), float(ay), float(az)};
        node.centre = weight > 0 ? Vec3f{float(cx / weight), float(cy / weight), float(cz / weight)} : box.center();
        float r2 = 0;
        for (std::uint32_t i = first; i < first + count; ++i)
            for (int k = 0; k < 3; ++k) {
                const Vec3f d = corner(tree.order[i], k) - node.centre;
                r2 = std::max(r2, dot(d, d));
            }
        node.radius = std::sqrt(r2);
        if (count <= kLeafSize) {
            node.first = first, node.count = count;
            tree.nodes[id] = node;
            return id;
        }
        // Split at the median centroid along the box's longest axis.
        const Vec3f ext = box.size();
        const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
        const auto begin = tree.order.begin() + first, mid = begin + count / 2, end = begin + count;
        std::nth_element(begin, mid, end, [&](std::uint32_t s, std::uint32_t t) { return centroid[s][axis] < centroid[t][axis]; });
        tree.nodes[id] = node;
        const std::uint32_t left = build(first, count / 2);
        const std::uint32_t right = build(first + count / 2, count - count / 2);
        tree.nodes[id].left = left, tree.nodes[id].right = right;
        return id;
    }
};

// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee).
double solid_angle(Vec3f a, Vec3f b, Vec3f c) {
    const double la = length(a), lb = length(b), lc = length(c);
    const double num = dot(a, cross(b, c));
    const double den = la * lb * lc + double(dot(a, b)) * lc + double(dot(b, c)) * la + double(dot(c, a)) * lb;
    return 2 * std::atan2(num, den);
}

}  // namespace

double openness(const Mesh& mesh) {
    double sx = 0, sy = 0, sz = 0, total = 0;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const Vec3f a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                    c = mesh.positions[mesh.indices[t + 2]];
        const Vec3f n = cross(b - a, c - a);
        sx += n.x, sy += n.y, sz += n.z, total += length(n);
    }
    return total > 0 ? std::sqrt(sx * sx + sy * sy + sz * sz) / total : 1.0;
}

WindingTree build_winding_tree(const Mesh& mesh) {
    WindingTree tree;
    tree.mesh = &mesh;
    const auto faces = static_cast<std::uint32_t>(mesh.triangle_count());
    if (faces == 0) return tree;
    Builder b{mesh, tree, {}};
    b.centroid.resize(faces);
    for (std::uint32_t t = 0; t < faces; ++t)
        b.centroid[t] = (b.corner(t, 0) + b.corner(t, 1) + b.corner(t, 2)) * (1.f / 3);
    tree.order.resize(faces);
    std::iota(tree.order.begin(), tree.order.end(), 0u);
    tree.nodes.reserve(2 * (faces / kLeafSize + 1));
    b.build(0, faces);
    return tree;
}

double winding_number(const WindingTree& tree, Vec3f q, double beta) {
    if (tree.nodes.empty()) return 0;
    const Mesh& mesh = *tree.mesh;
    double omega = 0;
    std::array<std::uint32_t, 128> stack;
    std::size_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const WindingTree::Node& n = tree.nodes[stack[--top]];
        const Vec3f d = n.centre - q;
        const double dist = length(d);
        if (dist > beta * double(n.radius)) {
            omega += double(dot(d, n.area)) / (dist * dist * dist);  // the node as one dipole
            continue;
        }
        if (n.count > 0) {
            for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
                const std::size_t t = 3 * std::size_t(tree.order[i]);
                omega += solid_angle(mesh.positions[mesh.indices[t]] - q, mesh.positions[mesh.indices[t + 1]] - q,
                                     mesh.positions[mesh.indices[t + 2]] - q);
            }
            continue;
        }
        // depth is about log2(faces / 8) < 64 for any mesh that fits in memory; two slots per level
        stack[top++] = n.left;
        stack[top++] = n.right;
    }
    return omega / (4 * M_PI);
}

}  // namespace lodforge::mc
