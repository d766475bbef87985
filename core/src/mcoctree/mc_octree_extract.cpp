// Extracting a mesh from the prioritized marching-cube octree at a priority or a triangle budget.
//
// Hasup Lee, "Efficient Level-of-Detail Model Generation of 3D Objects using Prioritized Marching Cube
// Octree" (doctoral thesis, KAIST, 2007, §6.1-6.2): for the nodes numbered i, i - 1, ..., 1 the children
// not expanded themselves are triangulated; the budget is turned into a priority through the cumulative
// triangle table. We walk the order forwards instead (the same set of nodes, no 'expanded' flags to
// reset), and triangulate each node of the cut by table look-up; a node with a finer neighbour uses a
// triangulation with its shared faces split (mc_tables.cpp), which closes the seam by index with no moved
// vertices. Every such triangulation a node can meet is prepared when the extractor is made, in the order
// the cuts reach the nodes and over vertices renumbered by first use, so the extraction reads a prefix of
// those tables and copies a prefix of the vertices: no floating-point work, no neighbour reads, no hashing,
// nothing proportional to the whole tree.
#include "lodforge/error.h"
#include "mcoctree/mc_octree_internal.h"

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
    const std::size_t expanded = tree.order.size();
    std::vector<std::uint32_t> prio(n);
    for (std::size_t i = 0; i < n; ++i) prio[i] = tree.nodes[i].priority;

    // Records in the order the cuts reach them: a node enters the cuts at its parent's rank p, so the
    // root (p = 0) comes first, then the children of order[k] (p = k + 1) for k = 0, 1, ...
    std::vector<std::uint32_t> record_node;
    record_node.reserve(n);
    record_start_.assign(expanded + 2, 0);
    if (n > 0) record_node.push_back(0);
    record_start_[1] = static_cast<std::uint32_t>(record_node.size());
    for (std::size_t k = 0; k < expanded; ++k) {
        const std::uint32_t x = tree.order[k];
        if (x < n) {
            const McNode& p = tree.nodes[x];
            const auto children = static_cast<std::uint32_t>(std::popcount(unsigned(p.child_mask)));
            for (std::uint32_t c = 0; c < children && std::size_t(p.first_child) + c < n; ++c)
                record_node.push_back(p.first_child + c);
        }
        record_start_[k + 2] = static_cast<std::uint32_t>(record_node.size());
    }

    // Every node's triangulations over its life in the cuts. A node is in the cut from its parent's
    // expansion (rank p) until its own (rank r); meanwhile its refinement only grows, by one slot each
    // time a same-level neighbour is expanded. So it meets at most 19 (samples, refinement) pairs, known
    // from the neighbours' ranks; each distinct pair is triangulated once (the same rule and code as the
    // numbering's simulation, so the counts match the table). A pool entry holds its triangles over the
    // sub-edges it uses, numbered 0, 1, ... in sub-edge order; an event lists the tree vertices of those.
    struct Pattern {
        std::uint32_t at;
        std::uint64_t used;
    };
    std::vector<Pattern> patterns;
    mc::KeyMap known(1 << 12);
    auto entry = [&](std::uint32_t inside, std::uint32_t refine) -> std::uint32_t {
        const std::uint64_t key = refine == 0 ? std::uint64_t(mc::corner_config(inside))
                                              : std::uint64_t(inside & 0x7ffffff) | (std::uint64_t(refine) << 27);
        std::uint32_t id = known.find(key);
        if (id != mc::none) return id;
        std::uint8_t buf[3 * mc::max_triangles];
        int count;
        if (refine == 0) {
            const std::uint32_t c = mc::corner_config(inside);
            count = mc::case_table().count[c];
            std::copy_n(mc::case_table().edges[c].data(), 3 * count, buf);
        } else {
            count = mc::triangulate(inside, refine, buf);
        }
        // only the sub-edges the triangles use are output (a refined node's other crossings lie on parts
        // that are not split, and would be unreferenced vertices)
        std::uint64_t used = 0;
        for (int k = 0; k < 3 * count; ++k) used |= std::uint64_t(1) << buf[k];
        id = static_cast<std::uint32_t>(patterns.size());
        patterns.push_back({static_cast<std::uint32_t>(pool_.size()), used});
        pool_.push_back(static_cast<std::uint8_t>(count));
        pool_.push_back(refine != 0);
        for (int k = 0; k < 3 * count; ++k)
            pool_.push_back(static_cast<std::uint8_t>(std::popcount(used & ((std::uint64_t(1) << buf[k]) - 1))));
        known.insert(key, id);
        return id;
    };
    std::vector<std::uint32_t> first_use(tree.positions.size(), mc::none);  // lowest rank using the vertex
    auto add_event = [&](const McNode& node, std::uint32_t rank, std::uint32_t pattern) {
        const Pattern& pt = patterns[pattern];
        event_rank_.push_back(rank);
        event_entry_.push_back(pt.at);
        event_first_id_.push_back(static_cast<std::uint32_t>(event_ids_.size()));
        if ((pt.used & ~node.crossings) != 0)
            throw Error(Error::Kind::format, "mcoctree: a node's triangles use a sub-edge it does not cross");
        const std::uint32_t* ids = tree.vertex_ids.data() + node.first_vertex;
        for (std::uint64_t cross = node.crossings; cross; cross &= cross - 1) {
            const std::uint32_t v = *ids++;
            if (!((pt.used >> std::countr_zero(cross)) & 1)) continue;
            event_ids_.push_back(v);
            first_use[v] = std::min(first_use[v], rank);
        }
    };
    const auto& bits = mc::slot_refinement();
    const std::size_t records = record_node.size();
    record_own_.resize(records);
    record_event_.resize(records + 1);
    event_rank_.reserve(records + records / 4);
    event_entry_.reserve(records + records / 4);
    std::pair<std::uint32_t, std::uint32_t> later[mc::neighbour_slots];  // (rank, refinement bits)
    std::uint32_t group = 0;
    for (std::size_t k = 0; k < records; ++k) {
        while (record_start_[group + 1] <= k) ++group;
        const std::uint32_t p = group;  // the parent's rank (0 for the root)
        const std::uint32_t i = record_node[k];
        const McNode& node = tree.nodes[i];
        record_own_[k] = node.priority;
        record_event_[k] = static_cast<std::uint32_t>(event_rank_.size());
        if (node.level == 0) {  // leaves have no finer neighbours
            add_event(node, p, entry(node.inside, 0));
            continue;
        }
        std::uint32_t refine = 0;
        int m = 0;
        for (int s = 0; s < mc::neighbour_slots; ++s) {
            const std::uint32_t nb = tree.neighbours[std::size_t(i) * mc::neighbour_slots + std::size_t(s)];
            if (nb == mc::none || nb >= n) continue;
            const std::uint32_t q = prio[nb];
            if (q <= p) refine |= bits[std::size_t(s)];
            else if (q < node.priority) later[m++] = {q, bits[std::size_t(s)]};
        }
        std::uint32_t current = entry(node.inside, refine);
        add_event(node, p, current);
        std::sort(later, later + m);
        for (int j = 0; j < m; ++j) {
            refine |= later[j].second;
            if (j + 1 < m && later[j + 1].first == later[j].first) continue;
            const std::uint32_t next = entry(node.inside, refine);
            if (next == current) continue;  // nothing new
            add_event(node, later[j].first, next);
            current = next;
        }
    }
    record_event_[records] = static_cast<std::uint32_t>(event_rank_.size());
    event_first_id_.push_back(static_cast<std::uint32_t>(event_ids_.size()));
    for (auto* v : {&event_rank_, &event_entry_, &event_first_id_, &event_ids_}) v->shrink_to_fit();
    pool_.shrink_to_fit();

    // Vertices renumbered by the rank that first uses them (ties in record order, so the ids a cut reads
    // go mostly forwards): the cut at rank R uses only vertices below prefix_ of R.
    const std::size_t vertex_count = tree.positions.size();
    // key = first rank, or expanded + 1 for never used; count[k] = vertices with a key below k
    auto key = [&](std::uint32_t f) { return f == mc::none ? expanded + 1 : std::min<std::size_t>(f, expanded); };
    std::vector<std::uint32_t> count(expanded + 3, 0);
    for (const std::uint32_t f : first_use) ++count[key(f) + 1];
    for (std::size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
    prefix_.resize(tree.cuts.empty() ? 1 : tree.cuts.size());
    for (std::size_t i = 0; i < prefix_.size(); ++i)
        prefix_[i] = count[std::min<std::size_t>(tree.cuts.empty() ? 0 : tree.cuts[i], expanded) + 1];
    std::vector<std::uint32_t> renumber(vertex_count, mc::none);
    for (const std::uint32_t v : event_ids_)
        if (renumber[v] == mc::none) renumber[v] = count[key(first_use[v])]++;
    for (std::size_t v = 0; v < vertex_count; ++v)  // never used: at the end
        if (renumber[v] == mc::none) renumber[v] = count[expanded + 1]++;
    for (std::uint32_t& v : event_ids_) v = renumber[v];
    bool identity = true;
    for (std::size_t v = 0; v < vertex_count && identity; ++v) identity = renumber[v] == v;
    if (!identity) {
        positions_.resize(vertex_count);
        normals_.resize(vertex_count);
        if (tree.has_colors()) colors_.resize(vertex_count);
        for (std::size_t v = 0; v < vertex_count; ++v) {
            positions_[renumber[v]] = tree.positions[v];
            normals_[renumber[v]] = tree.normals[v];
            if (tree.has_colors()) colors_[renumber[v]] = tree.colors[v];
        }
    }
    stamp_.assign(vertex_count, 0);
    remap_.resize(vertex_count);
}

McOctreeExtractor::~McOctreeExtractor() = default;

const McExtraction& McOctreeExtractor::extract(std::size_t priority) {
    const McOctree& tree = *tree_;
    if (priority > tree.max_priority())
        throw Error(Error::Kind::argument, "mcoctree: priority " + std::to_string(priority) + " is above the maximum " +
                                               std::to_string(tree.max_priority()));
    if (++generation_ == 0) {  // stamps wrapped: start over
        std::fill(stamp_.begin(), stamp_.end(), 0);
        generation_ = 1;
    }
    McExtraction& r = result_;
    r.priority = priority;
    r.active_nodes = r.transition_nodes = 0;
    Mesh& m = r.mesh;
    // Sized from the triangle table, but grown when needed: the table comes from a file and may lie.
    m.indices.resize(3 * std::min<std::uint64_t>(mc_triangles_at(tree, priority), 3 * tree.vertex_ids.size()));
    std::size_t used = 0;
    const std::uint32_t rank = tree.cuts.empty() ? 0 : tree.cuts[priority];
    const std::uint32_t gen = generation_;
    std::uint32_t* stamp = stamp_.data();
    std::uint32_t distinct = 0;

    // The cut: the records whose parent is expanded (the first record_start_[rank + 1]) and which are not
    // expanded themselves (own priority > rank). Records, events and vertex lists are read forwards.
    const std::uint32_t end = record_start_[std::min<std::size_t>(rank, record_start_.size() - 2) + 1];
    const std::uint32_t* own = record_own_.data();
    const std::uint32_t* first_event = record_event_.data();
    const std::uint32_t* event_rank = event_rank_.data();
    const std::uint32_t* event_entry = event_entry_.data();
    const std::uint32_t* event_first_id = event_first_id_.data();
    const std::uint32_t* event_ids = event_ids_.data();
    const std::uint8_t* pool = pool_.data();
    for (std::uint32_t k = 0; k < end; ++k) {
        if (own[k] <= rank) continue;
        ++r.active_nodes;
        // the last triangulation whose rank is reached (the first one always is: the parent's)
        std::uint32_t e = first_event[k];
        const std::uint32_t last = first_event[k + 1] - 1;
        while (e < last && event_rank[e + 1] <= rank) ++e;
        const std::uint8_t* entry = pool + event_entry[e];
        const int count = entry[0];
        r.transition_nodes += entry[1];
        if (count == 0) continue;
        const std::uint32_t* ids = event_ids + event_first_id[e];
        const std::uint32_t id_count = event_first_id[e + 1] - event_first_id[e];
        for (std::uint32_t j = 0; j < id_count; ++j) {
            const std::uint32_t v = ids[j];
            if (stamp[v] != gen) {
                stamp[v] = gen;
                ++distinct;
            }
        }
        if (used + std::size_t(3 * count) > m.indices.size())
            m.indices.resize(std::max(2 * m.indices.size(), used + std::size_t(3 * count)));
        std::uint32_t* out = m.indices.data() + used;
        const std::uint8_t* local = entry + 2;
        for (int t = 0; t < 3 * count; ++t) out[t] = ids[local[t]];
        used += std::size_t(3 * count);
    }
    m.indices.resize(used);

    // Every vertex of the cut is below the prefix; most of the prefix is the cut's (all of it where no
    // vertex stopped being used, e.g. under an open scan's retracting border): then the ids are the output
    // indices and the attributes one block copy.
    const std::uint32_t prefix = prefix_[std::min(priority, prefix_.size() - 1)];
    const bool colors = tree.has_colors();
    const Vec3f* pos = positions_.empty() ? tree.positions.data() : positions_.data();
    const Vec3f* nrm = normals_.empty() ? tree.normals.data() : normals_.data();
    const Vec4f* col = colors_.empty() ? tree.colors.data() : colors_.data();
    if (distinct == prefix) {
        m.positions.assign(pos, pos + prefix);
        m.normals.assign(nrm, nrm + prefix);
        if (colors) m.colors.assign(col, col + prefix);
        else m.colors.clear();
        return r;
    }
    m.positions.resize(distinct);
    m.normals.resize(distinct);
    if (colors) m.colors.resize(distinct);
    else m.colors.clear();
    std::uint32_t* remap = remap_.data();
    std::uint32_t next = 0;
    for (std::uint32_t v = 0; v < prefix; ++v) {
        if (stamp[v] != gen) continue;
        remap[v] = next;
        m.positions[next] = pos[v];
        m.normals[next] = nrm[v];
        if (colors) m.colors[next] = col[v];
        ++next;
    }
    for (std::uint32_t& v : m.indices) v = remap[v];
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
