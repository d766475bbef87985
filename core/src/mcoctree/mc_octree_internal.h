// Shared by the mc_octree_*.cpp files: the refinement of a node at a priority, and a small open-addressing
// hash map for lattice keys (the build touches millions of them; std::unordered_map is several times slower).
#pragma once

#include "lodforge/mcoctree/mc_octree.h"
#include "mcoctree/mc_tables.h"

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

namespace lodforge::mc {

constexpr std::uint32_t none = UINT32_MAX;

// The refinement each neighbour slot brings when that neighbour is expanded: a face neighbour splits the
// shared face and its four edges, an edge neighbour the shared edge (the edges of a face neighbour's face
// include the edges it shares with the node, so OR-ing the slots is the whole rule).
inline const std::array<std::uint32_t, neighbour_slots>& slot_refinement() {
    static const std::array<std::uint32_t, neighbour_slots> table = [] {
        std::array<std::uint32_t, neighbour_slots> t{};
        for (int f = 0; f < 6; ++f) t[std::size_t(f)] = face_bit(f) | face_edges_mask(f);
        for (int e = 0; e < full_edges; ++e) t[std::size_t(6 + e)] = 1u << e;
        return t;
    }();
    return table;
}

// Which edges and faces of `node` are shared with nodes one level finer when the nodes whose priority is
// <= `expanded_up_to` are expanded (a same-level neighbour that is expanded has finer children there).
// `priority` is the per-node priority (McNode::priority, or a dense copy of it).
template <class PriorityOf>
inline std::uint32_t refine_mask(const McOctree& tree, std::uint32_t node, std::uint64_t expanded_up_to,
                                 const PriorityOf& priority) {
    const std::uint32_t* nb = &tree.neighbours[std::size_t(node) * neighbour_slots];
    const auto& bits = slot_refinement();
    std::uint32_t refine = 0;
    for (int s = 0; s < neighbour_slots; ++s)
        if (nb[s] != none && priority(nb[s]) <= expanded_up_to) refine |= bits[std::size_t(s)];
    return refine;
}
inline std::uint32_t refine_mask(const McOctree& tree, std::uint32_t node, std::uint64_t expanded_up_to) {
    if (tree.nodes[node].level == 0) return 0;
    return refine_mask(tree, node, expanded_up_to, [&](std::uint32_t n) { return tree.nodes[n].priority; });
}

// The child of `n` in octant `octant`, or none (children are stored contiguously in octant order). The
// rank among the children comes from a table: on a baseline x86-64 build std::popcount is a library call,
// and the numbering's heap asks this about a hundred times a step.
inline std::uint32_t child_index(const McNode& n, int octant) {
    static constexpr std::array<std::uint8_t, 256> bits = [] {
        std::array<std::uint8_t, 256> t{};
        for (unsigned m = 0; m < 256; ++m) t[m] = static_cast<std::uint8_t>((m & 1) + t[m >> 1]);
        return t;
    }();
    if (!(n.child_mask & (1u << octant))) return none;
    return n.first_child + bits[n.child_mask & ((1u << octant) - 1)];
}

inline std::uint32_t sub_edge_vertex(const McOctree& tree, const McNode& n, int sub_edge) {
    const std::uint64_t below = n.crossings & ((std::uint64_t(1) << sub_edge) - 1);
    return tree.vertex_ids[n.first_vertex + static_cast<std::uint32_t>(std::popcount(below))];
}


// Keys: lattice points packed 17 bits per axis (plus, for edges, axis and level above bit 51).
inline std::uint64_t pack(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return std::uint64_t(x) | (std::uint64_t(y) << 17) | (std::uint64_t(z) << 34);
}
constexpr std::uint32_t max_lattice = (1u << 17) - 1;

class KeyMap {
public:
    static constexpr std::uint64_t empty_key = ~std::uint64_t(0);
    explicit KeyMap(std::size_t expected = 1024) { rehash(std::bit_ceil(expected * 2 + 16)); }
    // Value for key, or none.
    std::uint32_t find(std::uint64_t key) const {
        for (std::size_t i = slot(key);; i = (i + 1) & mask_) {
            if (slots_[i].key == key) return slots_[i].value;
            if (slots_[i].key == empty_key) return none;
        }
    }
    // Inserts when absent; returns the stored value.
    std::uint32_t insert(std::uint64_t key, std::uint32_t value) {
        if ((size_ + 1) * 2 > slots_.size()) rehash(slots_.size() * 2);
        for (std::size_t i = slot(key);; i = (i + 1) & mask_) {
            if (slots_[i].key == key) return slots_[i].value;
            if (slots_[i].key == empty_key) {
                slots_[i] = {key, value};
                ++size_;
                return value;
            }
        }
    }
    std::size_t size() const { return size_; }

private:
    // Key and value side by side: a look-up costs one cache miss, not two (the build's look-ups are
    // random and the tables far larger than the caches).
    struct Slot {
        std::uint64_t key;
        std::uint32_t value;
    };
    std::size_t slot(std::uint64_t key) const {
        key ^= key >> 33;
        key *= 0xff51afd7ed558ccdULL;
        key ^= key >> 33;
        return static_cast<std::size_t>(key) & mask_;
    }
    void rehash(std::size_t capacity) {
        std::vector<Slot> old = std::move(slots_);
        slots_.assign(capacity, Slot{empty_key, 0});
        mask_ = capacity - 1;
        size_ = 0;
        for (const Slot& s : old)
            if (s.key != empty_key) insert(s.key, s.value);
    }
    std::vector<Slot> slots_;
    std::size_t mask_ = 0, size_ = 0;
};

// Triangulations of refined nodes, computed once per (samples, refinement) pair met: the seams then cost a
// table look-up like every other node. Not thread-safe (one per extractor).
class SeamCache {
public:
    // Sub-edge triples and their count for `inside` with `refine` (refine != 0).
    const std::uint8_t* get(std::uint32_t inside, std::uint32_t refine, int& count) {
        const std::uint64_t key = std::uint64_t(inside & 0x7ffffff) | (std::uint64_t(refine) << 27);
        std::uint32_t at = map_.find(key);
        if (at == none) {
            std::uint8_t buf[3 * max_triangles];
            const int n = triangulate(inside, refine, buf);
            at = static_cast<std::uint32_t>(data_.size());
            data_.push_back(static_cast<std::uint8_t>(n));
            data_.insert(data_.end(), buf, buf + 3 * n);
            map_.insert(key, at);
        }
        count = data_[at];
        return data_.data() + at + 1;
    }

private:
    KeyMap map_{1 << 12};
    std::vector<std::uint8_t> data_;
};

inline int node_triangle_count(const McOctree& tree, std::uint32_t node, std::uint32_t refine, SeamCache& cache) {
    const McNode& n = tree.nodes[node];
    if (refine == 0) return case_table().count[corner_config(n.inside)];
    int count = 0;
    cache.get(n.inside, refine, count);
    return count;
}

// Numbers the internal nodes by priority and fills order, cuts and triangle_counts (mc_octree_priority.cpp).
// `level_maps[l]` maps packed node coordinates at level l to node indices. Returns the number of cuts of
// the expansion sequence that are not priority levels (a later cut has fewer triangles). The seams'
// triangle counts are computed on `threads` threads; the result does not depend on it.
std::size_t number_mc_octree(McOctree& tree, const std::vector<KeyMap>& level_maps, unsigned threads,
                             Progress* progress);

}  // namespace lodforge::mc
