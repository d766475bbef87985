// Interior simplification of an octree node's part by quadric edge collapse with its border locked.
//
// Garland & Heckbert, "Surface Simplification Using Quadric Error Metrics" (SIGGRAPH 1997), through
// the project's collapse simplifier (simplify.h) with half-edge placement: the kept vertices are input
// vertices with their records and keys unchanged, so siblings and parents still merge by key. The
// document's operator (Bade et al. 2006, §3.5) fans the whole border of a node to one representative,
// which is only a fair approximation of a part that is a flat disc: a folded sheet (an ear cut by the
// cell), a tube or a part whose border winds round the cell became a star through one point (issue #27).
#include "octree/part_collapse.h"

#include "lodforge/error.h"
#include "lodforge/simplify/simplify.h"

#include "octree/ooc_internal.h"

#include <algorithm>
#include <array>
#include <tuple>

namespace lodforge::ooc {
namespace {

constexpr std::uint32_t kNone = ~0u;

// Net use (uses min→max minus max→min) of every undirected edge of `indices`, added with `sign`.
void add_net(const std::uint32_t* indices, std::size_t count, int sign, FlatMap& slot, std::vector<std::int32_t>& net) {
    for (std::size_t c = 0; c < count; c += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = indices[c + k], b = indices[c + (k + 1) % 3];
            const std::uint64_t key = a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a);
            bool inserted = false;
            const std::uint32_t e = slot.find_or_insert(key, static_cast<std::uint32_t>(net.size()), inserted);
            if (inserted) net.push_back(0);
            net[e] += sign * (a < b ? 1 : -1);
        }
}

// The triangles of `triangles` less pairs of one triangle in both windings: such a pair (a flat pillow
// left where children's collapses met from both sides of a thin sheet) adds nothing to the oriented
// boundary, and the collapse simplifier drops repeated faces, which would change it.
std::vector<std::uint32_t> cancel_opposite_pairs(const NodeMesh& input, const std::vector<std::uint32_t>& triangles) {
    struct Face {
        std::array<std::uint32_t, 3> sorted;
        bool even;  // the corners in sorted order are an even rotation of the winding
        std::uint32_t triangle;
    };
    std::vector<Face> faces(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const std::uint32_t* c = &input.indices[3 * triangles[i]];
        Face& f = faces[i];
        f.sorted = {c[0], c[1], c[2]};
        std::sort(f.sorted.begin(), f.sorted.end());
        const int m = static_cast<int>(std::min_element(c, c + 3) - c);
        f.even = c[(m + 1) % 3] == f.sorted[1];
        f.triangle = triangles[i];
    }
    std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) {
        return std::tie(a.sorted, a.even, a.triangle) < std::tie(b.sorted, b.even, b.triangle);
    });
    std::vector<std::uint32_t> out;
    out.reserve(triangles.size());
    for (std::size_t i = 0; i < faces.size();) {
        std::size_t j = i, odd = 0;
        while (j < faces.size() && faces[j].sorted == faces[i].sorted) odd += !faces[j++].even;
        const std::size_t even = j - i - odd, pairs = std::min(even, odd);
        // Odd windings sort first: skip `pairs` of them and `pairs` of the even ones after them.
        for (std::size_t k = i + pairs; k < i + odd; ++k) out.push_back(faces[k].triangle);
        for (std::size_t k = i + odd + pairs; k < j; ++k) out.push_back(faces[k].triangle);
        i = j;
    }
    return out;
}

}  // namespace

bool collapse_part(const NodeMesh& input, const std::vector<std::uint32_t>& part, std::size_t target,
                   double max_error, bool lock_border, PartCollapse& out, bool weld) {
    const std::vector<std::uint32_t> triangles = cancel_opposite_pairs(input, part);
    if (triangles.empty()) {
        out.indices.clear();
        out.error = 0;
        return true;
    }
    const VertexLayout& layout = input.layout;
    std::vector<std::uint32_t> local(input.vertex_count(), kNone), global;
    Mesh mesh;
    mesh.indices.reserve(triangles.size() * 3);
    for (std::uint32_t t : triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = input.indices[3 * t + k];
            if (local[v] == kNone) {
                local[v] = static_cast<std::uint32_t>(global.size());
                global.push_back(v);
            }
            mesh.indices.push_back(local[v]);
        }
    mesh.positions.resize(global.size());
    if (layout.normals) mesh.normals.resize(global.size());
    if (layout.colors) mesh.colors.resize(global.size());
    if (layout.texcoords) mesh.texcoords.assign(1, std::vector<Vec2f>(global.size()));
    for (std::size_t i = 0; i < global.size(); ++i) {
        const float* r = input.vertex(global[i]);
        mesh.positions[i] = {r[0], r[1], r[2]};
        if (layout.normals) {
            const float* n = r + layout.normal_offset();
            mesh.normals[i] = {n[0], n[1], n[2]};
        }
        if (layout.colors) {
            const float* c = r + layout.color_offset();
            mesh.colors[i] = {c[0], c[1], c[2], c[3]};
        }
        if (layout.texcoords) {
            const float* uv = r + layout.texcoord_offset();
            mesh.texcoords[0][i] = {uv[0], uv[1]};
        }
    }
    SimplifyParams params;
    params.target_triangles = std::max<std::size_t>(target, 1);
    Bounds box;
    for (const Vec3f& p : mesh.positions) box.add(p);
    const double diagonal = box.diagonal();
    if (diagonal > 0 && max_error < INFINITY) params.max_error = static_cast<float>(max_error / diagonal);
    params.lock_border = lock_border;
    // Vertices are the node's keys: two at one position (a wedge-UV seam, the dragon's zipped cracks) are
    // different vertices with a border between them, which every level keeps (unless the caller welds).
    params.weld = weld;
    SimplifyResult r;
    try {
        r = simplify(mesh, params);
    } catch (const Error&) {
        return false;  // the caller fans the part instead
    }
    // A dropped repeated face would change the part's boundary; a welded node keeps none.
    if (r.dropped_faces && !weld) return false;
    out.indices.clear();
    out.indices.reserve(r.mesh.indices.size());
    for (std::uint32_t v : r.mesh.indices) out.indices.push_back(global[r.vertex_map[v]]);
    out.error = r.error;
    if (!lock_border) return true;
    // The part's oriented boundary must come out unchanged: that is what keeps every cut crack-free.
    FlatMap slot(triangles.size() * 3 / 2 + 16);
    std::vector<std::int32_t> net;
    add_net(mesh.indices.data(), mesh.indices.size(), 1, slot, net);
    std::vector<std::uint32_t> kept(out.indices.size());
    for (std::size_t i = 0; i < out.indices.size(); ++i) kept[i] = local[out.indices[i]];
    add_net(kept.data(), kept.size(), -1, slot, net);
    return std::none_of(net.begin(), net.end(), [](std::int32_t n) { return n != 0; });
}

}  // namespace lodforge::ooc
