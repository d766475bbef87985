// Extracting a mesh from the prioritized marching-cube octree at a priority or a triangle budget.
//
// The 003 document (KAIST thesis, 2007, §6.1-6.2): for the nodes numbered i, i - 1, ..., 1 the children
// not expanded themselves are triangulated; the budget is turned into a priority through the cumulative
// triangle table. We walk the order forwards instead (the same set of nodes, no 'expanded' flags to
// reset), and triangulate each node of the cut by table look-up; a node with a finer neighbour is
// re-triangulated with its shared faces split (mc_tables.cpp), which closes the seam by index with no
// moved vertices. No floating-point work: positions, normals and colours were computed at build time.
#include "lodforge/error.h"
#include "mc_octree_internal.h"

#include <algorithm>

namespace lodforge {

using mc::none;

std::uint64_t mc_triangles_at(const McOctree& tree, std::size_t priority) {
    if (tree.triangle_counts.empty()) return 0;
    return tree.triangle_counts[std::min(priority, tree.triangle_counts.size() - 1)];
}

std::size_t mc_priority_for_triangles(const McOctree& tree, std::uint64_t triangles) {
    const auto& t = tree.triangle_counts;
    if (t.empty() || t[0] > triangles) return 0;
    // Binary search over the cumulative table (monotone on the meshes we measured, docs/mcoctree.md);
    // stepping back afterwards keeps the answer within the budget even where a refinement removed triangles.
    std::size_t i = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), triangles) - t.begin()) - 1;
    while (i > 0 && t[i] > triangles) --i;
    return i;
}

McOctreeExtractor::McOctreeExtractor(const McOctree& tree)
    : tree_(&tree), seams_(std::make_unique<mc::SeamCache>()) {
    remap_.assign(2 * tree.positions.size(), 0);  // (stamp, output index) pairs: one cache line per look-up
    priority_.resize(tree.nodes.size());
    for (std::size_t i = 0; i < tree.nodes.size(); ++i) priority_[i] = tree.nodes[i].priority;
    // The smallest priority among a node's neighbours: below it the node has no seam, which settles most
    // nodes of a cut without reading their 18 neighbours.
    first_seam_.assign(tree.nodes.size(), mc::none);
    for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
        if (tree.nodes[i].level == 0) continue;
        for (int s = 0; s < mc::neighbour_slots; ++s) {
            const std::uint32_t nb = tree.neighbours[i * mc::neighbour_slots + std::size_t(s)];
            if (nb != mc::none) first_seam_[i] = std::min(first_seam_[i], priority_[nb]);
        }
    }
    active_.assign((tree.nodes.size() + 63) / 64, 0);
}

McOctreeExtractor::~McOctreeExtractor() = default;

const McExtraction& McOctreeExtractor::extract(std::size_t priority) {
    const McOctree& tree = *tree_;
    if (priority > tree.max_priority())
        throw Error(Error::Kind::argument, "mcoctree: priority " + std::to_string(priority) + " is above the maximum " +
                                               std::to_string(tree.max_priority()));
    if (++generation_ == 0) {  // stamps wrapped: start over
        for (std::size_t v = 0; v < remap_.size(); v += 2) remap_[v] = 0;
        generation_ = 1;
    }
    McExtraction& r = result_;
    r.priority = priority;
    r.active_nodes = r.transition_nodes = 0;
    Mesh& m = r.mesh;
    m.positions.clear();
    m.normals.clear();
    m.colors.clear();
    // Sized from the triangle table, but grown when needed: the table comes from a file and may lie.
    m.indices.resize(3 * std::min<std::uint64_t>(mc_triangles_at(tree, priority), 3 * tree.vertex_ids.size()));
    std::size_t used = 0;
    const bool colors = tree.has_colors();
    const mc::CaseTable& table = mc::case_table();
    const std::uint32_t* prio = priority_.data();
    auto priority_of = [prio](std::uint32_t n) { return prio[n]; };
    std::uint32_t* remap = remap_.data();
    const std::uint32_t gen = generation_;

    // The cut: children of expanded nodes that are not expanded themselves. Marked in a bitmap and then
    // walked in storage order (level by level, Morton order within a level), which keeps the node and
    // vertex reads local; the priority order itself jumps all over the model.
    std::fill(active_.begin(), active_.end(), 0);
    auto mark = [&](std::uint32_t i) { active_[i >> 6] |= std::uint64_t(1) << (i & 63); };
    if (priority == 0) {
        if (!tree.nodes.empty()) mark(0);
    } else {
        for (std::size_t k = 0; k < priority; ++k) {
            const McNode& p = tree.nodes[tree.order[k]];
            const int children = std::popcount(unsigned(p.child_mask));
            for (int c = 0; c < children; ++c) {
                const std::uint32_t ci = p.first_child + static_cast<std::uint32_t>(c);
                if (prio[ci] > priority) mark(ci);
            }
        }
    }
    std::uint32_t vid[mc::sub_edge_count];
    for (std::size_t w = 0; w < active_.size(); ++w) {
        for (std::uint64_t bits = active_[w]; bits; bits &= bits - 1) {
            const auto node = static_cast<std::uint32_t>(w * 64 + std::size_t(std::countr_zero(bits)));
            const McNode& n = tree.nodes[node];
            ++r.active_nodes;
            const std::uint32_t refine =
                first_seam_[node] > priority ? 0 : mc::refine_mask(tree, node, priority, priority_of);
            const std::uint8_t* edges;
            int count;
            if (refine == 0) {
                const std::uint32_t c = mc::corner_config(n.inside);
                edges = table.edges[c].data();
                count = table.count[c];
            } else {
                ++r.transition_nodes;
                edges = seams_->get(n.inside, refine, count);
            }
            if (count == 0) continue;
            // output index of every crossing sub-edge of the node (bits walked in order: no popcount)
            const std::uint32_t* ids = tree.vertex_ids.data() + n.first_vertex;
            std::uint64_t cross = refine == 0 ? (n.crossings & 0xfff) : n.crossings;
            for (; cross; cross &= cross - 1) {
                const std::uint32_t v = *ids++;
                std::uint32_t* slot = remap + 2 * std::size_t(v);
                if (slot[0] != gen) {
                    slot[0] = gen;
                    slot[1] = static_cast<std::uint32_t>(m.positions.size());
                    m.positions.push_back(tree.positions[v]);
                    m.normals.push_back(tree.normals[v]);
                    if (colors) m.colors.push_back(tree.colors[v]);
                }
                vid[std::countr_zero(cross)] = slot[1];
            }
            if (used + std::size_t(3 * count) > m.indices.size())
                m.indices.resize(std::max(2 * m.indices.size(), used + std::size_t(3 * count)));
            std::uint32_t* out = m.indices.data() + used;
            for (int k = 0; k < 3 * count; ++k) out[k] = vid[edges[k]];
            used += std::size_t(3 * count);
        }
    }
    m.indices.resize(used);
    return r;
}

std::vector<McCell> McOctreeExtractor::cells(std::size_t priority) const {
    const McOctree& tree = *tree_;
    std::vector<McCell> out;
    auto add = [&](std::uint32_t i) {
        const McNode& n = tree.nodes[i];
        const float size = tree.cube_size * float(1u << n.level);
        out.push_back({tree.origin + Vec3f{float(n.x), float(n.y), float(n.z)} * size, size, n.level, i});
    };
    priority = std::min(priority, tree.max_priority());
    if (priority == 0) {
        if (!tree.nodes.empty()) add(0);
        return out;
    }
    for (std::size_t k = 0; k < priority; ++k) {
        const McNode& p = tree.nodes[tree.order[k]];
        const int children = std::popcount(unsigned(p.child_mask));
        for (int c = 0; c < children; ++c) {
            const std::uint32_t ci = p.first_child + static_cast<std::uint32_t>(c);
            if (tree.nodes[ci].priority > priority) add(ci);
        }
    }
    return out;
}

McExtraction extract_mc_octree(const McOctree& tree, std::size_t priority) {
    McOctreeExtractor ex(tree);
    return ex.extract(priority);
}

}  // namespace lodforge
