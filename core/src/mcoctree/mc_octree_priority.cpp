// Priority numbering of the marching-cube octree and the exact triangle count of every priority.
//
// Hasup Lee, "Efficient Level-of-Detail Model Generation of 3D Objects using Prioritized Marching Cube
// Octree" (doctoral thesis, KAIST, 2007, §5.2 and §5.4.3): repeatedly expand the node with the largest
// area difference among those whose neighbours are all present, so that neighbouring nodes never differ
// by more than one level (the 2:1 rule). The printed loop rescans a sorted list from its head and never
// removes the chosen node; here a binary heap holds the expandable nodes and every node counts how many
// coarser neighbours still stand in its way, so the whole numbering is O(n log n).
// Decisions (docs/mcoctree.md): the neighbourhood is all 26 cubes (faces, edges, corners); the key is the
// magnitude of the area difference, a negative difference being as much a change of shape as a positive
// one; ties go to the node stored first. The triangle count of every priority is simulated here, with the
// same seam triangulation the extraction uses, so the budget inverse is exact.
#include "lodforge/error.h"
#include "mcoctree/mc_octree_internal.h"
#include "parallel_for.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <queue>
#include <thread>

namespace lodforge::mc {
namespace {

struct Entry {
    float key;
    std::uint32_t node;
    bool operator<(const Entry& o) const { return key < o.key || (key == o.key && node > o.node); }
};

}  // namespace

std::size_t number_mc_octree(McOctree& tree, const std::vector<KeyMap>& maps, unsigned threads, Progress* progress) {
    const std::size_t n = tree.nodes.size();
    const std::uint32_t grid = 1u << tree.levels;
    std::vector<std::uint8_t> blockers(n, 0);
    std::vector<std::uint32_t> triangles(n, 0);
    std::priority_queue<Entry> heap;
    tree.order.clear();
    tree.triangle_counts.clear();
    tree.cuts.clear();
    // sequence[k] = triangles after the first k expansions (the node granularity, before choosing levels)
    std::vector<std::uint64_t> sequence;
    sequence.reserve(n / 2 + 1);
    for (McNode& node : tree.nodes) node.priority = none;
    // Dense copy of the priorities: the seam masks read 18 neighbours' priorities per node, and a 4-byte
    // array keeps those reads in cache where the 40-byte node records do not.
    std::vector<std::uint32_t> prio(n, none);
    // Each node's seam mask (refine_mask at the current rank), kept up to date as its same-level
    // neighbours are expanded instead of re-reading its 18 neighbours' priorities at every change.
    std::vector<std::uint32_t> refine(n, 0);
    const auto& slot_bits = slot_refinement();

    // offset (dx, dy, dz) -> neighbour slot for faces and edges; corners (-1) go through the level's map
    int slot_of[27];
    for (int& s : slot_of) s = -1;
    for (int s = 0; s < neighbour_slots; ++s) {
        const auto o = neighbour_offset(s);
        slot_of[(o[0] + 1) + 3 * (o[1] + 1) + 9 * (o[2] + 1)] = s;
    }
    auto find = [&](std::uint32_t node, int dx, int dy, int dz) -> std::uint32_t {
        const int s = slot_of[(dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)];
        const std::uint32_t* nb = &tree.neighbours[std::size_t(node) * neighbour_slots];
        if (s >= 0) return nb[s];
        // A corner neighbour is the face neighbour of an edge neighbour, when one of the three exists
        // (two table reads instead of a hash look-up in a large map).
        const int paths[3][2] = {{slot_of[(dx + 1) + 3 * (dy + 1) + 9], slot_of[13 + 9 * dz]},
                                 {slot_of[(dx + 1) + 3 + 9 * (dz + 1)], slot_of[13 + 3 * dy]},
                                 {slot_of[1 + 3 * (dy + 1) + 9 * (dz + 1)], slot_of[13 + dx]}};
        for (const auto& path : paths)
            if (nb[path[0]] != none) return tree.neighbours[std::size_t(nb[path[0]]) * neighbour_slots + std::size_t(path[1])];
        const McNode& a = tree.nodes[node];
        const std::int64_t size = std::int64_t(grid >> a.level);
        const std::int64_t x = std::int64_t(a.x) + dx, y = std::int64_t(a.y) + dy, z = std::int64_t(a.z) + dz;
        if (x < 0 || y < 0 || z < 0 || x >= size || y >= size || z >= size) return none;
        return maps[a.level].find(pack(std::uint32_t(x), std::uint32_t(y), std::uint32_t(z)));
    };
    SeamCache seams;
    auto push = [&](std::uint32_t node) {
        if (tree.nodes[node].level > 0) heap.push({std::fabs(tree.metric[node]), node});
    };
    auto child = [](const McNode& p, int octant) { return child_index(p, octant); };

    // The order depends on the metric and the blockers only; the triangle counts of the seams a step
    // gives its neighbours are recorded as (node, seam mask) changes, counted apart (each thread with its
    // own cache of triangulations) and replayed in order for the exact totals. The counting overlaps the
    // heap, which is serial by nature: a second thread counts the changes recorded so far, chunk by
    // chunk, and this one takes the chunks left when the heap is done.
    std::size_t numbered = 0, internal = 0;
    for (const McNode& node : tree.nodes) internal += node.level > 0;
    // A step changes the seams of at most its 18 face and edge neighbours: reserved once, so the counting
    // thread can read what is published while the heap appends (only the touched pages are resident).
    const std::size_t max_changes = 18 * internal + 1;
    std::vector<std::uint64_t> changes;  // node | seam mask << 32
    changes.reserve(max_changes);
    const std::uint64_t* const change_data = changes.data();
    const std::unique_ptr<std::uint32_t[]> counts(new std::uint32_t[max_changes]);
    std::vector<std::uint32_t> changes_end;  // per step: end of its changes
    changes_end.reserve(internal + 1);
    constexpr std::size_t chunk = 2048;
    std::atomic<std::size_t> published{0}, next_chunk{0};
    std::atomic<bool> heap_done{false};
    // Counts the next whole published chunk (or, once the heap is done, the next one at all); false when
    // there is none now.
    auto count_chunk = [&](SeamCache& cache) {
        const bool done = heap_done.load(std::memory_order_acquire);
        const std::size_t avail = published.load(std::memory_order_acquire);
        std::size_t c = next_chunk.load(std::memory_order_relaxed);
        for (;;) {
            const std::size_t b = c * chunk;
            if (b >= avail || (!done && b + chunk > avail)) return false;
            if (next_chunk.compare_exchange_weak(c, c + 1, std::memory_order_relaxed)) break;
        }
        const std::size_t b = c * chunk, e = std::min(avail, b + chunk);
        for (std::size_t i = b; i < e; ++i)
            counts[i] = static_cast<std::uint32_t>(node_triangle_count(
                tree, static_cast<std::uint32_t>(change_data[i]), static_cast<std::uint32_t>(change_data[i] >> 32), cache));
        return true;
    };
    auto run_heap = [&] {
        push(0);
        while (!heap.empty()) {
            const std::uint32_t x = heap.top().node;
            heap.pop();
            McNode& node = tree.nodes[x];
            node.priority = static_cast<std::uint32_t>(++numbered);
            prio[x] = node.priority;
            tree.order.push_back(x);
            if ((numbered & 0x3fff) == 0)
                check_progress(progress, 0.8 + 0.2 * double(numbered) / double(internal), "mcoctree: priorities");

            // x's 26 neighbours, looked up once (the children and the seams below all read them)
            std::uint32_t around[27];
            for (int d = 0; d < 27; ++d)
                around[d] = d == 13 ? none : find(x, d % 3 - 1, (d / 3) % 3 - 1, d / 9 - 1);
            auto near = [&](int dx, int dy, int dz) { return around[(dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)]; };
            // Children become present; each waits for the unexpanded coarse nodes it touches.
            for (int o = 0; o < 8; ++o) {
                const std::uint32_t c = child(node, o);
                if (c == none) continue;
                std::uint8_t count = 0;
                for (int d = 1; d < 8; ++d) {
                    const int dx = (d & 1) ? ((o & 1) ? 1 : -1) : 0, dy = (d & 2) ? ((o & 2) ? 1 : -1) : 0,
                              dz = (d & 4) ? ((o & 4) ? 1 : -1) : 0;
                    const std::uint32_t m = near(dx, dy, dz);
                    if (m != none && prio[m] == none) ++count;
                }
                blockers[c] = count;
                // No same-level neighbour of c is expanded yet (each touches x, which blocked it until now):
                // its count is its own triangulation's, taken in the replay.
                if (count == 0) push(c);
            }
            // Neighbours: children of expanded ones stop waiting for x; present ones get a seam with x's children.
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        if (dx == 0 && dy == 0 && dz == 0) continue;
                        const std::uint32_t m = near(dx, dy, dz);
                        if (m == none) continue;
                        const McNode& nb = tree.nodes[m];
                        if (prio[m] != none) {
                            for (int o = 0; o < 8; ++o) {
                                // child o of the neighbour touches x when, per axis, it lies on x's side
                                const int ox = o & 1, oy = (o >> 1) & 1, oz = (o >> 2) & 1;
                                const bool touches = (dx == 0 || (dx < 0) == (ox == 1)) && (dy == 0 || (dy < 0) == (oy == 1)) &&
                                                     (dz == 0 || (dz < 0) == (oz == 1));
                                if (!touches) continue;
                                const std::uint32_t c = child(nb, o);
                                if (c == none) continue;
                                if (blockers[c] > 0 && --blockers[c] == 0) push(c);
                            }
                        } else if (nb.parent == none || prio[nb.parent] != none) {
                            const bool shares_edge = (dx == 0) + (dy == 0) + (dz == 0) >= 1;
                            if (!shares_edge || nb.level == 0) continue;
                            refine[m] |= slot_bits[std::size_t(slot_of[(1 - dx) + 3 * (1 - dy) + 9 * (1 - dz)])];
                            changes.push_back(std::uint64_t(m) | std::uint64_t(refine[m]) << 32);
                        }
                    }
            changes_end.push_back(static_cast<std::uint32_t>(changes.size()));
            published.store(changes.size(), std::memory_order_release);
        }
    };
    detail::run_beside(
        std::max(1u, threads),
        [&] {
            // The heap, then the chunks left; `heap_done` also when the heap throws (cancelled), so the
            // counting thread ends.
            struct Done {
                std::atomic<bool>& flag;
                ~Done() { flag.store(true, std::memory_order_release); }
            };
            {
                Done done{heap_done};
                run_heap();
            }
            SeamCache cache;
            while (count_chunk(cache)) {
            }
        },
        [&] {
            SeamCache cache;
            for (;;) {
                if (count_chunk(cache)) continue;
                if (heap_done.load(std::memory_order_acquire) &&
                    next_chunk.load(std::memory_order_relaxed) * chunk >= published.load(std::memory_order_acquire))
                    return;
                std::this_thread::sleep_for(std::chrono::microseconds(100));
            }
        });
    if (numbered != internal)
        throw Error(Error::Kind::invalid, "mcoctree: priority numbering stopped early (" + std::to_string(numbered) +
                                              " of " + std::to_string(internal) + " nodes)");

    // The replay: every cut's exact count, in order.
    std::uint64_t total = node_triangle_count(tree, 0, 0, seams);
    triangles[0] = static_cast<std::uint32_t>(total);
    sequence.push_back(total);
    for (std::size_t k = 0, i = 0; k < tree.order.size(); ++k) {
        const McNode& node = tree.nodes[tree.order[k]];
        total -= triangles[tree.order[k]];
        for (int o = 0; o < 8; ++o) {
            const std::uint32_t c = child(node, o);
            if (c == none) continue;
            triangles[c] = static_cast<std::uint32_t>(node_triangle_count(tree, c, 0, seams));
            total += triangles[c];
        }
        for (; i < changes_end[k]; ++i) {
            const auto m = static_cast<std::uint32_t>(changes[i]);
            total = total - triangles[m] + counts[i];
            triangles[m] = counts[i];
        }
        sequence.push_back(total);
    }
    // Priority levels (docs/mcoctree.md, D10): a longest subsequence of the cuts along which the triangle
    // count never decreases, ending with the last cut (every leaf). Patience sorting, O(n log n); only cuts
    // with at most the last cut's count can precede it.
    const std::size_t last = sequence.size() - 1;
    std::vector<std::uint32_t> tails, before(sequence.size(), none);  // tails[l]: best end of a chain of l + 1
    for (std::size_t k = 0; k < last; ++k) {
        if (sequence[k] > sequence[last]) continue;
        const auto at = std::upper_bound(tails.begin(), tails.end(), sequence[k],
                                         [&](std::uint64_t v, std::uint32_t t) { return v < sequence[t]; });
        before[k] = at == tails.begin() ? none : *(at - 1);
        if (at == tails.end()) tails.push_back(static_cast<std::uint32_t>(k));
        else *at = static_cast<std::uint32_t>(k);
    }
    std::vector<std::uint32_t> chain = {static_cast<std::uint32_t>(last)};
    for (std::uint32_t k = tails.empty() ? none : tails.back(); k != none; k = before[k]) chain.push_back(k);
    std::reverse(chain.begin(), chain.end());
    for (const std::uint32_t k : chain) {
        tree.cuts.push_back(k);
        tree.triangle_counts.push_back(sequence[k]);
    }
    return sequence.size() - tree.cuts.size();
}

}  // namespace lodforge::mc
