// Extracting a mesh from the prioritized marching-cube octree at a priority or a triangle budget.
//
// The 003 document (KAIST thesis, 2007, §6.1-6.2): for the nodes numbered i, i - 1, ..., 1 the children
// not expanded themselves are triangulated; the budget is turned into a priority through the cumulative
// triangle table. We walk the order forwards instead (the same set of nodes, no 'expanded' flags to
// reset), and triangulate each node of the cut by table look-up; a node with a finer neighbour uses a
// triangulation with its shared faces split (mc_tables.cpp), which closes the seam by index with no moved
// vertices. Every such triangulation a node can meet is prepared when the extractor is made, so the
// extraction reads tables and copies vertices only: no floating-point work, no neighbour reads, no hashing.
#include "lodforge/error.h"
#include "mc_octree_internal.h"

#include <algorithm>
#include <cstring>

namespace lodforge {

using mc::none;

std::uint64_t mc_triangles_at(const McOctree& tree, std::size_t priority) {
    if (tree.triangle_counts.empty()) return 0;
    return tree.triangle_counts[std::min(priority, tree.triangle_counts.size() - 1)];
}

std::size_t mc_priority_for_triangles(const McOctree& tree, std::uint64_t triangles) {
    const auto& t = tree.triangle_counts;
    if (t.empty() || t[0] > triangles) return 0;
    // The table is non-decreasing (D10 in docs/mcoctree.md; validated on reading): a binary search.
    return static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), triangles) - t.begin()) - 1;
}

McOctreeExtractor::McOctreeExtractor(const McOctree& tree) : tree_(&tree) {
    const std::size_t n = tree.nodes.size();
    remap_.assign(2 * tree.positions.size(), 0);  // (stamp, output index) pairs: one cache line per look-up
    emitted_.resize(tree.positions.size());
    std::vector<std::uint32_t> prio(n);
    for (std::size_t i = 0; i < n; ++i) prio[i] = tree.nodes[i].priority;
    lifetime_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t parent = tree.nodes[i].parent;
        const std::uint64_t p = parent == mc::none || parent >= n ? 0 : prio[parent];
        lifetime_[i] = p << 32 | prio[i];
    }

    // Every node's triangulations over its life in the cuts. A node is in the cut from its parent's
    // expansion (rank p) until its own (rank r); meanwhile its refinement only grows, by one slot each
    // time a same-level neighbour is expanded. So it meets at most 19 (samples, refinement) pairs, known
    // from the neighbours' ranks; each distinct pair is triangulated once (the same rule and code as the
    // numbering's simulation, so the counts match the table).
    mc::KeyMap known(1 << 12);
    auto entry = [&](std::uint32_t inside, std::uint32_t refine) -> std::uint32_t {
        const std::uint64_t key = refine == 0 ? std::uint64_t(mc::corner_config(inside))
                                              : std::uint64_t(inside & 0x7ffffff) | (std::uint64_t(refine) << 27);
        std::uint32_t at = known.find(key);
        if (at != mc::none) return at;
        std::uint8_t buf[3 * mc::max_triangles];
        int count;
        if (refine == 0) {
            const std::uint32_t c = mc::corner_config(inside);
            count = mc::case_table().count[c];
            std::copy_n(mc::case_table().edges[c].data(), 3 * count, buf);
        } else {
            count = mc::triangulate(inside, refine, buf);
        }
        // the sub-edges the triangles use: only their vertices are output (a refined node's other
        // crossings lie on parts that are not split, and would be unreferenced vertices)
        std::uint64_t used = 0;
        for (int k = 0; k < 3 * count; ++k) used |= std::uint64_t(1) << buf[k];
        at = static_cast<std::uint32_t>(pool_.size());
        pool_.push_back(static_cast<std::uint8_t>(count));
        pool_.push_back(refine != 0);
        for (int b = 0; b < 8; ++b) pool_.push_back(static_cast<std::uint8_t>(used >> (8 * b)));
        pool_.insert(pool_.end(), buf, buf + 3 * count);
        known.insert(key, at);
        return at;
    };
    const auto& bits = mc::slot_refinement();
    first_event_.resize(n + 1);
    events_.reserve(n + n / 4);
    std::pair<std::uint32_t, std::uint32_t> later[mc::neighbour_slots];  // (rank, refinement bits)
    for (std::size_t i = 0; i < n; ++i) {
        first_event_[i] = static_cast<std::uint32_t>(events_.size());
        const McNode& node = tree.nodes[i];
        const std::uint64_t p = node.parent == mc::none || node.parent >= n ? 0 : prio[node.parent];
        if (node.level == 0) {  // leaves have no finer neighbours
            events_.push_back(p << 32 | entry(node.inside, 0));
            continue;
        }
        std::uint32_t refine = 0;
        int m = 0;
        for (int s = 0; s < mc::neighbour_slots; ++s) {
            const std::uint32_t nb = tree.neighbours[i * mc::neighbour_slots + std::size_t(s)];
            if (nb == mc::none || nb >= n) continue;
            const std::uint32_t q = prio[nb];
            if (q <= p) refine |= bits[std::size_t(s)];
            else if (q < node.priority) later[m++] = {q, bits[std::size_t(s)]};
        }
        events_.push_back(p << 32 | entry(node.inside, refine));
        std::sort(later, later + m);
        for (int k = 0; k < m; ++k) {
            refine |= later[k].second;
            if (k + 1 < m && later[k + 1].first == later[k].first) continue;
            if (std::uint32_t(events_.back()) == entry(node.inside, refine)) continue;  // nothing new
            events_.push_back(std::uint64_t(later[k].first) << 32 | entry(node.inside, refine));
        }
    }
    first_event_[n] = static_cast<std::uint32_t>(events_.size());
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
    const std::uint64_t rank = tree.cuts.empty() ? 0 : tree.cuts[priority];
    std::uint32_t* remap = remap_.data();
    // Output vertices are numbered in the loop and copied after it: the loop then stores one index per new
    // vertex instead of growing three arrays (a cut never outputs a tree vertex twice, so V bounds it).
    std::uint32_t* emitted = emitted_.data();
    std::uint32_t vertex_count = 0;
    const std::uint32_t gen = generation_;

    // The cut: the nodes whose parent is expanded (rank p <= rank; the root has p = 0) and which are not
    // expanded themselves (rank < r). One sequential pass over (p, r) pairs in storage order (level by
    // level, Morton order within a level): the node, event and vertex-index reads then go forwards too,
    // where walking the priority order would jump all over the model.
    const std::uint64_t* events = events_.data();
    const std::uint32_t* first_event = first_event_.data();
    const std::uint8_t* pool = pool_.data();
    const std::uint64_t* life = lifetime_.data();
    std::uint32_t vid[mc::sub_edge_count];
    const std::size_t node_count = lifetime_.size();
    for (std::size_t ni = 0; ni < node_count; ++ni) {
        const std::uint64_t span = life[ni];
        if ((span >> 32) > rank || std::uint32_t(span) <= rank) continue;
        const auto node = static_cast<std::uint32_t>(ni);
        const McNode& n = tree.nodes[node];
        ++r.active_nodes;
        // the last triangulation whose rank is reached (the first one always is: the parent's)
        std::uint32_t e = first_event[node];
        const std::uint32_t last = first_event[node + 1] - 1;
        while (e < last && (events[e + 1] >> 32) <= rank) ++e;
        const std::uint8_t* entry = pool + std::uint32_t(events[e]);
        const int count = entry[0];
        r.transition_nodes += entry[1];
        if (count == 0) continue;
        std::uint64_t used_edges;
        std::memcpy(&used_edges, entry + 2, 8);
        const std::uint8_t* edges = entry + 10;
        // output index of every sub-edge the triangles use (the crossings walked in order: no popcount)
        const std::uint32_t* ids = tree.vertex_ids.data() + n.first_vertex;
        const int top = 64 - std::countl_zero(used_edges);  // walk the crossings up to the last one used
        const std::uint64_t below_top = top >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << top) - 1;
        for (std::uint64_t cross = n.crossings & below_top; cross; cross &= cross - 1) {
            const std::uint32_t v = *ids++;
            if (!((used_edges >> std::countr_zero(cross)) & 1)) continue;
            std::uint32_t* slot = remap + 2 * std::size_t(v);
            if (slot[0] != gen) {
                slot[0] = gen;
                slot[1] = vertex_count;
                emitted[vertex_count++] = v;
            }
            vid[std::countr_zero(cross)] = slot[1];
        }
        if (used + std::size_t(3 * count) > m.indices.size())
            m.indices.resize(std::max(2 * m.indices.size(), used + std::size_t(3 * count)));
        std::uint32_t* out = m.indices.data() + used;
        for (int k = 0; k < 3 * count; ++k) out[k] = vid[edges[k]];
        used += std::size_t(3 * count);
    }
    m.indices.resize(used);
    m.positions.resize(vertex_count);
    m.normals.resize(vertex_count);
    if (colors) m.colors.resize(vertex_count);
    for (std::uint32_t k = 0; k < vertex_count; ++k) {
        const std::uint32_t v = emitted[k];
        m.positions[k] = tree.positions[v];
        m.normals[k] = tree.normals[v];
        if (colors) m.colors[k] = tree.colors[v];
    }
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
    const std::size_t rank = tree.cuts.empty() ? 0 : tree.cuts[priority];
    if (rank == 0) {
        if (!tree.nodes.empty()) add(0);
        return out;
    }
    for (std::size_t k = 0; k < rank; ++k) {
        const McNode& p = tree.nodes[tree.order[k]];
        const int children = std::popcount(unsigned(p.child_mask));
        for (int c = 0; c < children; ++c) {
            const std::uint32_t ci = p.first_child + static_cast<std::uint32_t>(c);
            if (tree.nodes[ci].priority > rank) add(ci);
        }
    }
    return out;
}

McExtraction extract_mc_octree(const McOctree& tree, std::size_t priority) {
    McOctreeExtractor ex(tree);
    return ex.extract(priority);
}

}  // namespace lodforge
