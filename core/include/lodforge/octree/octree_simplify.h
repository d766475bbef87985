// The node simplification operator of the out-of-core octree (docs/octree.md, "Node simplification"):
// the node's boundary edges kept and fanned to a representative vertex from the generalized quadric,
// everything else dropped. One fan per connected part of the node's patch and per simple boundary cycle
// (so no fan crosses the space between separate sheets, and no spoke is used more than twice); a part
// whose fan would not be smaller than its triangles keeps them, so a node never grows.
//
// "Boundary edge" here is the oriented boundary of the node's surface patch: an edge whose uses a→b and
// b→a inside the node do not cancel, kept |a→b − b→a| times in the surviving direction, plus every use
// of an edge the whole input uses an odd number ≥ 3 of times (odd non-manifold). For a manifold, consistently oriented
// input that is exactly the document's "edge used once inside the node": an edge shared with a triangle
// in another node, or a border edge of the input. The oriented boundary of a patch is a cycle, so the
// fan's spokes come in opposite pairs, and a node's boundary at every level is made of *input* edges:
// the boundary of the union of its leaves. Any cut through the octree (nodes at mixed levels) therefore
// has every input edge with its input use count or none, and no border edge the input did not have.
#pragma once

#include "lodforge/octree/ooc_soup.h"
#include "lodforge/simplify/quadric.h"
#include "lodforge/simplify/simplify.h"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace lodforge {

// Vertex identity shared by all nodes of an asset: input vertices keep their PLY index (with wedge UVs,
// a UV hash in bits 32-62 above it); the apex of fan i (0, 1, ...) of node n is kRepresentativeKey | i << 32 | n,
// the cluster vertices of its clustered closed components kRepresentativeKey | 1 << 62 | (cell + 1) << 32 | n.
constexpr std::uint64_t kRepresentativeKey = std::uint64_t{1} << 63;

// An indexed mesh of one node at one level. Vertices carry `layout.floats()` floats each (position
// first) and a key; indices are local, 3 per triangle, winding as in the input.
struct NodeMesh {
    VertexLayout layout;
    std::vector<std::uint64_t> keys;
    std::vector<float> vertices;
    std::vector<std::uint32_t> indices;

    std::size_t vertex_count() const { return keys.size(); }
    std::size_t triangle_count() const { return indices.size() / 3; }
    const float* vertex(std::size_t i) const { return &vertices[i * layout.floats()]; }
    std::size_t memory_bytes() const { return keys.capacity() * 8 + (vertices.capacity() + indices.capacity()) * 4; }
};

// The union of several node meshes of one layout, vertices with equal keys merged (the shared boundary
// vertices of sibling nodes).
NodeMesh merge_node_meshes(const std::vector<const NodeMesh*>& parts);

// The frame quadrics are accumulated in: positions mapped by (p − origin) / scale into the root cube
// [0, 1]³ (conditioning), attributes multiplied by their weights (SimplifyWeights, as in
// simplify_cluster) so that they count against position like in the in-core simplifiers.
struct QuadricFrame {
    Vec3d origin;
    double scale = 1;
    VertexLayout layout;
    SimplifyWeights weights;

    std::size_t attribute_dimension() const { return layout.floats() - 3 - (layout.material ? 1 : 0); }
    Vec3d to_frame(const float* vertex) const;
    // Weighted attribute vector of a vertex record (attribute_dimension() values).
    void attributes(const float* vertex, double* out) const;
};

// Generalized quadric (Garland & Heckbert 1998 in Hoppe's 1999 form) of everything under a node:
// position quadric plus the attribute quadric, both in QuadricFrame units.
struct NodeQuadric {
    Quadric geometry;
    AttributeQuadrics attributes;  // one entry
    double position_sum[3] = {0, 0, 0};
    double position_count = 0;

    explicit NodeQuadric(std::size_t dimension = 0) : attributes(1, dimension) {}
    void add_triangle(const QuadricFrame& frame, const float* v0, const float* v1, const float* v2);
    void add(const NodeQuadric& other);
};

// Minimiser of q by pseudo-inverse around `around` (eigenvalues below 1e-3 of the largest are
// ignored, so flat and straight regions keep the nearest point to `around`), clamped into [lo, hi].
// Used for node representatives and for OoCS cells (Lindstrom 2000).
Vec3d clamped_minimizer(const Quadric& q, Vec3d around, const double lo[3], const double hi[3]);

// What a node may simplify beyond the document's operator (docs/octree.md, "Coarse levels"): edges no
// other node shares. Chains of free edges are replaced by one chord between their pinned ends, and
// closed components (no boundary edge in the node) are vertex-clustered instead of copied.
struct NodeBorderEdges {
    // Input border edges (one use in the whole input), sorted keys min << 32 | max of input vertex ids
    // (SoupResult::border_edges).
    const std::vector<std::uint64_t>* input = nullptr;
    // Chords the node's descendants made (NodeSimplifyStats::chords, merged), sorted (min key, max key).
    const std::vector<std::pair<std::uint64_t, std::uint64_t>>* chords = nullptr;
    bool cluster_closed = true;
    // Fraction of its triangles each part keeps when simplified by edge collapse (never below its fan's
    // size): 0 collapses to the fan's size or the error bound, the old schedule; 0.35 makes a node about
    // 35 % of its children's meshes, so each level is that fraction of the one below until the cells'
    // locked cut lines are all that is left (docs/octree.md, "Level sizes").
    double keep_ratio = 0;
    // The node shares nothing with another node (the root: a cut holding it holds nothing else): its
    // whole input collapses freely, UV seams welded, to `alone_triangles` (0: by keep_ratio).
    bool alone = false;
    std::size_t alone_triangles = 0;
};

struct NodeSimplifyStats {
    std::size_t boundary_edges = 0;      // kept directed edge uses fanned (= fan triangles)
    std::size_t collapsed_parts = 0;     // parts simplified by edge collapse instead of a fan
    std::size_t closed_components = 0;   // components with no boundary edge (clustered, or kept unchanged)
    std::size_t closed_triangles_in = 0, closed_triangles_out = 0;  // of those components, when clustered
    std::size_t free_uses_removed = 0;   // free boundary uses replaced by chords or dropped with their loop
    std::vector<std::pair<std::uint64_t, std::uint64_t>> chords;  // made here (sorted): free for the parent
    std::size_t degenerate_dropped = 0;  // input triangles with a repeated vertex
    double error = 0;                    // largest RMS plane distance of an apex, model units
};

// The operator. `cell_min`/`cell_size` are the node's cell in model units (each apex is clamped into it
// and into the bounds of its part's vertices; a single part's apex minimises `quadric`, several parts'
// apexes the quadrics of their own triangles in `input`). The output never has more triangles than `input`. A connected component of `input` without boundary edges (a closed surface wholly
// inside the node, or a closed model at the root) is copied unchanged rather than lost, or, with
// `border` (cluster_closed), clustered on a 16³ grid over the cell into a closed chain.
// With `border`, chains of free edges shrink to chords (NodeBorderEdges).
// `odd_non_manifold_edges` (sorted keys min << 32 | max of input vertex ids, SoupResult) are kept with
// all their uses.
NodeMesh simplify_node(const NodeMesh& input, const NodeQuadric& quadric, const QuadricFrame& frame,
                       const float cell_min[3], float cell_size, std::uint64_t representative_key,
                       const std::vector<std::uint64_t>* odd_non_manifold_edges = nullptr,
                       NodeSimplifyStats* stats = nullptr, const NodeBorderEdges* border = nullptr);

}  // namespace lodforge
