// Node simplification of the out-of-core octree.
//
// Shaffie (UTM report 2006, §3.5, the "000" document): a modified vertex clustering (Rossignac &
// Borrel 1993) in which the node's boundary edges are preserved and fanned to one representative
// vertex, every interior triangle dropped; the representative minimises the node's generalized quadric
// (Garland & Heckbert, "Simplifying Surfaces with Color and Texture using Quadric Error Metrics",
// IEEE Visualization 1998; stored in Hoppe's 1999 form, quadric.h), solved with a pseudo-inverse around
// the mean vertex as in Lindstrom's OoCS (SIGGRAPH 2000) and clamped into the node cell. Boundary edges
// are found with a hash map of edge use counts (the document's list search is its §5.4 bottleneck).
#include "union_find.h"
#include "lodforge/octree_simplify.h"

#include "ooc_internal.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace lodforge {
namespace {

constexpr std::uint32_t kNone = ~0u;

double weight_or_floor(float w) { return std::max(static_cast<double>(w), 1e-4); }

double texcoord_weight(const SimplifyWeights& w) {
    return weight_or_floor(!w.texcoord_sets.empty() ? w.texcoord_sets[0] : w.texcoord);
}

}  // namespace

NodeMesh merge_node_meshes(const std::vector<const NodeMesh*>& parts) {
    NodeMesh out;
    std::size_t vertices = 0, indices = 0;
    for (const NodeMesh* p : parts) {
        vertices += p->vertex_count();
        indices += p->indices.size();
        out.layout = p->layout;
    }
    const std::size_t f = out.layout.floats();
    out.keys.reserve(vertices);
    out.vertices.reserve(vertices * f);
    out.indices.reserve(indices);
    ooc::FlatMap map(vertices);
    std::vector<std::uint32_t> local;
    for (const NodeMesh* p : parts) {
        local.resize(p->vertex_count());
        for (std::size_t i = 0; i < p->vertex_count(); ++i) {
            bool inserted = false;
            std::uint32_t& v = map.find_or_insert(p->keys[i], static_cast<std::uint32_t>(out.keys.size()), inserted);
            if (inserted) {
                out.keys.push_back(p->keys[i]);
                out.vertices.insert(out.vertices.end(), p->vertex(i), p->vertex(i) + f);
            }
            local[i] = v;
        }
        for (std::uint32_t i : p->indices) out.indices.push_back(local[i]);
    }
    return out;
}

Vec3d QuadricFrame::to_frame(const float* v) const {
    return {(v[0] - origin.x) / scale, (v[1] - origin.y) / scale, (v[2] - origin.z) / scale};
}

void QuadricFrame::attributes(const float* v, double* out) const {
    std::size_t j = 0, k = 3;
    if (layout.normals) {
        const double w = weight_or_floor(weights.normal);
        for (int a = 0; a < 3; ++a) out[j++] = w * v[k++];
    }
    if (layout.colors) {
        const double w = weight_or_floor(weights.color);
        for (int a = 0; a < 4; ++a) out[j++] = w * v[k++];
    }
    if (layout.texcoords) {
        const double w = texcoord_weight(weights);
        for (int a = 0; a < 2; ++a) out[j++] = w * v[k++];
    }
}

void NodeQuadric::add_triangle(const QuadricFrame& frame, const float* v0, const float* v1, const float* v2) {
    const Vec3d p0 = frame.to_frame(v0), p1 = frame.to_frame(v1), p2 = frame.to_frame(v2);
    for (const Vec3d& p : {p0, p1, p2}) {
        position_sum[0] += p.x;
        position_sum[1] += p.y;
        position_sum[2] += p.z;
    }
    position_count += 3;
    const Vec3d e1{p1.x - p0.x, p1.y - p0.y, p1.z - p0.z}, e2{p2.x - p0.x, p2.y - p0.y, p2.z - p0.z};
    Vec3d n{e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x};
    const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (!(len > 0)) return;
    n = {n.x / len, n.y / len, n.z / len};
    const double area = 0.5 * len;
    geometry += Quadric::from_plane(n, -(n.x * p0.x + n.y * p0.y + n.z * p0.z), area);
    const std::size_t m = frame.attribute_dimension();
    if (m == 0) return;
    double s[3][9];
    frame.attributes(v0, s[0]);
    frame.attributes(v1, s[1]);
    frame.attributes(v2, s[2]);
    attributes.add_triangle(0, p0, p1, p2, s[0], s[1], s[2], area);
}

void NodeQuadric::add(const NodeQuadric& other) {
    geometry += other.geometry;
    attributes.add(0, other.attributes, 0);
    for (int a = 0; a < 3; ++a) position_sum[a] += other.position_sum[a];
    position_count += other.position_count;
}

Vec3d clamped_minimizer(const Quadric& q, Vec3d around, const double lo[3], const double hi[3]) {
    const Vec3d v = minimizer_near(q, around);
    return {std::clamp(v.x, lo[0], hi[0]), std::clamp(v.y, lo[1], hi[1]), std::clamp(v.z, lo[2], hi[2])};
}

NodeMesh simplify_node(const NodeMesh& input, const NodeQuadric& quadric, const QuadricFrame& frame,
                       const float cell_min[3], float cell_size, std::uint64_t representative_key,
                       const std::vector<std::uint64_t>* odd_non_manifold_edges, NodeSimplifyStats* stats) {
    NodeSimplifyStats local_stats;
    NodeSimplifyStats& st = stats ? *stats : local_stats;
    st = {};
    const std::size_t n = input.vertex_count();
    const std::size_t tris = input.triangle_count();
    const std::uint32_t* idx = input.indices.data();
    auto degenerate = [&](std::size_t t) {
        const std::uint32_t a = idx[3 * t], b = idx[3 * t + 1], c = idx[3 * t + 2];
        return a == b || b == c || a == c;
    };
    auto edge_key = [](std::uint32_t a, std::uint32_t b) {
        return a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a);
    };
    // Per undirected edge: its net use (uses min→max minus max→min). A degenerate triangle (a, a, b)
    // would add a→b and b→a, which changes no net use, so dropping it changes no boundary.
    ooc::FlatMap slot_of(tris * 3 / 2 + 16);
    std::vector<std::int32_t> net;
    std::vector<std::uint32_t> edge_of(3 * tris, ~0u);  // corner k of triangle t → edge t.k..t.k+1
    for (std::size_t t = 0; t < tris; ++t) {
        if (degenerate(t)) {
            ++st.degenerate_dropped;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = idx[3 * t + k], b = idx[3 * t + (k + 1) % 3];
            bool inserted = false;
            const std::uint32_t e = slot_of.find_or_insert(edge_key(a, b), static_cast<std::uint32_t>(net.size()), inserted);
            if (inserted) net.push_back(0);
            net[e] += a < b ? 1 : -1;
            edge_of[3 * t + k] = e;
        }
    }
    // Edges of the input used an odd number ≥ 3 of times keep every use in every node.
    std::vector<std::uint8_t> keep_all(net.size(), 0);
    if (odd_non_manifold_edges && !odd_non_manifold_edges->empty())
        for (std::size_t t = 0; t < tris; ++t) {
            if (degenerate(t)) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t ka = input.keys[idx[3 * t + k]], kb = input.keys[idx[3 * t + (k + 1) % 3]];
                if ((ka | kb) & kRepresentativeKey) continue;
                const std::uint64_t key = ka < kb ? (ka << 32 | kb) : (kb << 32 | ka);
                if (std::binary_search(odd_non_manifold_edges->begin(), odd_non_manifold_edges->end(), key))
                    keep_all[edge_of[3 * t + k]] = 1;
            }
        }
    // Copies of each edge still to emit in its net direction.
    std::vector<std::int32_t> remaining(net.size());
    for (std::size_t e = 0; e < net.size(); ++e) remaining[e] = net[e] < 0 ? -net[e] : net[e];
    auto boundary = [&](std::size_t corner) {
        const std::uint32_t e = edge_of[corner];
        return keep_all[e] || net[e] != 0;
    };
    // Emits the use a→b (corner `corner`) when it belongs to the node's kept boundary.
    auto take = [&](std::size_t corner, std::uint32_t a, std::uint32_t b) {
        const std::uint32_t e = edge_of[corner];
        if (keep_all[e]) return true;
        if (remaining[e] == 0 || (net[e] > 0) != (a < b)) return false;
        --remaining[e];
        return true;
    };

    // Components (union-find over the triangles' vertices) and whether each has a boundary edge.
    detail::UnionFind sets(n);
    for (std::size_t t = 0; t < tris; ++t) {
        if (degenerate(t)) continue;
        sets.unite(idx[3 * t], idx[3 * t + 1]);
        sets.unite(idx[3 * t], idx[3 * t + 2]);
    }
    std::vector<std::uint8_t> has_boundary(n, 0);
    bool any_boundary = false;
    for (std::size_t t = 0; t < tris; ++t) {
        if (degenerate(t)) continue;
        for (int k = 0; k < 3; ++k)
            if (boundary(3 * t + k)) {
                has_boundary[sets.find(idx[3 * t])] = 1;
                any_boundary = true;
            }
    }

    NodeMesh out;
    out.layout = input.layout;
    const std::size_t f = input.layout.floats();
    std::vector<std::uint32_t> remap(n, kNone);
    auto use = [&](std::uint32_t v) {
        if (remap[v] == kNone) {
            remap[v] = static_cast<std::uint32_t>(out.keys.size());
            out.keys.push_back(input.keys[v]);
            out.vertices.insert(out.vertices.end(), input.vertex(v), input.vertex(v) + f);
        }
        return remap[v];
    };

    if (any_boundary) {
        // The representative: pseudo-inverse solve of the generalized quadric (attributes eliminated)
        // around the mean vertex, so flat and straight nodes stay put instead of flying off.
        Quadric total = quadric.geometry;
        if (frame.attribute_dimension() > 0) total += quadric.attributes.eliminated(0);
        const double k = quadric.position_count > 0 ? 1.0 / quadric.position_count : 0.0;
        Eigen::Vector3d xbar(quadric.position_sum[0] * k, quadric.position_sum[1] * k, quadric.position_sum[2] * k);
        if (quadric.position_count == 0) {
            xbar.setZero();
            for (std::size_t v = 0; v < n; ++v) {
                const Vec3d p = frame.to_frame(input.vertex(v));
                xbar += Eigen::Vector3d(p.x, p.y, p.z);
            }
            if (n) xbar /= static_cast<double>(n);
        }
        double lo[3], hi[3];
        const double o[3] = {frame.origin.x, frame.origin.y, frame.origin.z};
        for (int a = 0; a < 3; ++a) {
            lo[a] = (cell_min[a] - o[a]) / frame.scale;
            hi[a] = lo[a] + cell_size / frame.scale;
        }
        const Vec3d p = clamped_minimizer(total, {xbar(0), xbar(1), xbar(2)}, lo, hi);
        std::vector<float> rep(f);
        rep[0] = static_cast<float>(p.x * frame.scale + frame.origin.x);
        rep[1] = static_cast<float>(p.y * frame.scale + frame.origin.y);
        rep[2] = static_cast<float>(p.z * frame.scale + frame.origin.z);
        const std::size_t m = frame.attribute_dimension();
        if (m > 0) {
            double s[9] = {};
            if (!quadric.attributes.optimal_attributes(0, p, s)) {
                // No area to weigh by (all triangles degenerate): the plain mean of the node's vertices.
                double tmp[9];
                for (std::size_t v = 0; v < n; ++v) {
                    frame.attributes(input.vertex(v), tmp);
                    for (std::size_t j = 0; j < m; ++j) s[j] += tmp[j] / static_cast<double>(std::max<std::size_t>(n, 1));
                }
            }
            std::size_t j = 0, r = 3;
            if (frame.layout.normals) {
                const double w = weight_or_floor(frame.weights.normal);
                double nx = s[j] / w, ny = s[j + 1] / w, nz = s[j + 2] / w;
                const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
                if (len > 0) {
                    nx /= len;
                    ny /= len;
                    nz /= len;
                } else {
                    nx = 0;
                    ny = 0;
                    nz = 1;
                }
                rep[r++] = static_cast<float>(nx);
                rep[r++] = static_cast<float>(ny);
                rep[r++] = static_cast<float>(nz);
                j += 3;
            }
            if (frame.layout.colors) {
                const double w = weight_or_floor(frame.weights.color);
                for (int a = 0; a < 4; ++a) rep[r++] = static_cast<float>(std::clamp(s[j++] / w, 0.0, 1.0));
            }
            if (frame.layout.texcoords) {
                const double w = texcoord_weight(frame.weights);
                for (int a = 0; a < 2; ++a) rep[r++] = static_cast<float>(s[j++] / w);
            }
        }
        out.keys.push_back(representative_key);
        out.vertices.insert(out.vertices.end(), rep.begin(), rep.end());
        if (quadric.geometry.weight > 0)
            st.error = std::sqrt(quadric.geometry.evaluate(p) / quadric.geometry.weight) * frame.scale;
    }
    std::vector<std::uint8_t> counted(n, 0);
    for (std::size_t t = 0; t < tris; ++t) {
        if (degenerate(t)) continue;
        const std::uint32_t root = sets.find(idx[3 * t]);
        if (!has_boundary[root]) {
            if (!counted[root]) {
                counted[root] = 1;
                ++st.closed_components;
            }
            for (int k = 0; k < 3; ++k) out.indices.push_back(use(idx[3 * t + k]));
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = idx[3 * t + k], b = idx[3 * t + (k + 1) % 3];
            if (!take(3 * t + k, a, b)) continue;
            // The edge keeps its direction in its source triangle, so the fan faces the same way.
            out.indices.push_back(use(a));
            out.indices.push_back(use(b));
            out.indices.push_back(0);
            ++st.boundary_edges;
        }
    }
    return out;
}

}  // namespace lodforge
