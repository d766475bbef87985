// The marching-cube octree's signed distance field on the leaf lattice, kept in sparse 4x4x4 blocks, and
// the lattice cube sets of the build. Header only: the field's look-ups are the build's inner loops and
// stay inlinable there. Design and decisions (D1, D2): docs/mcoctree.md.
#pragma once

#include "mcoctree/mc_octree_internal.h"
#include "mcoctree/mc_points.h"
#include "mcoctree/mc_winding.h"
#include "parallel_for.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <thread>
#include <vector>

namespace lodforge::mc {

inline unsigned thread_count(unsigned requested) {
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    return requested ? requested : std::min(hw, 16u);
}

template <class F> void parallel_for(std::size_t n, unsigned threads, F&& f) {
    detail::parallel_for(n, threads, 4096, std::forward<F>(f));
}

// Lattice points grouped in 4x4x4 blocks, numbered in order of first use. Where the lattice is small
// enough (a root grid up to 2048 cubes, i.e. resolutions up to about 2000) a block is found by its
// position: a directory of tiles of 8x8x8 blocks (one entry per tile), each tile an array of its 512
// blocks' numbers, made when a block in it is first created (2 KB; only the tiles along the surface exist,
// about 1 MB on the dragon at 256) — no hashing, and the few KB of the directory stay in the cache.
// Elsewhere a block is found by one hash look-up behind a direct-mapped cache of recent blocks (16^3 of
// them, by their low coordinate bits), since the flood, the closing and the nodes' samples mostly touch
// blocks met just before.
class Blocks {
public:
    // `lattice`: lattice points per axis (0 = unknown: hashing only).
    explicit Blocks(std::size_t expected, std::uint32_t lattice = 0) : map_(expected) {
        const std::size_t n = (std::size_t(lattice) + 3) / 4, t = (n + tile - 1) / tile;
        if (lattice > 0 && t * t * t <= (std::size_t(1) << 19)) {  // a directory of 2 MB at most
            side_ = n;
            tiles_side_ = t;
            directory_.assign(t * t * t, 0);
        }
    }
    static std::uint32_t local(std::uint64_t key) {
        return std::uint32_t((key & 3) | ((key >> 17) & 3) << 2 | ((key >> 34) & 3) << 4);
    }
    // Block of `key`; `created` is set when the block is new (numbered size() - 1).
    std::uint32_t of(std::uint64_t key, bool& created) {
        const std::uint64_t bk = block_key(key);
        created = false;
        if (std::uint32_t* d = tiled(bk)) {  // block + 1, 0 = none
            if (*d == 0) *d = static_cast<std::uint32_t>(++count_), created = true;
            return *d - 1;
        }
        Cached& c = cache_[slot(bk)];
        if (c.key == bk) return c.block;
        std::uint32_t b = map_.find(bk);
        if (b == none) {
            b = static_cast<std::uint32_t>(count_++);
            map_.insert(bk, b);
            created = true;
        }
        c = {bk, b};
        return b;
    }
    std::size_t size() const { return count_; }
    struct Cached {
        std::uint64_t key = ~std::uint64_t(0);
        std::uint32_t block = 0;
    };
    static constexpr std::size_t cache_size = 4096;
    // Block of `key` or none, without creating one: safe on several threads at once while nobody creates
    // blocks, each with its own cache (cache_size entries).
    std::uint32_t find(std::uint64_t key, Cached* cache) const {
        const std::uint64_t bk = block_key(key);
        const std::size_t x = bk & mc::max_lattice, y = (bk >> 17) & mc::max_lattice, z = bk >> 34;
        if (x < side_ && y < side_ && z < side_) {
            const std::uint32_t t = directory_[tile_of(x, y, z)];
            return t == 0 ? none : tiles_[in_tile(t, x, y, z)] - 1;  // 0 - 1 = none
        }
        Cached& c = cache[slot(bk)];
        if (c.key == bk) return c.block;
        const std::uint32_t b = map_.find(bk);
        if (b != none) c = {bk, b};
        return b;
    }

private:
    static constexpr std::size_t tile = 8;  // blocks per axis of a tile
    static std::uint64_t block_key(std::uint64_t key) {
        return ((key & mc::max_lattice) >> 2) | (((key >> 17) & mc::max_lattice) >> 2) << 17 |
               (((key >> 34) & mc::max_lattice) >> 2) << 34;
    }
    std::size_t tile_of(std::size_t x, std::size_t y, std::size_t z) const {
        return x / tile + tiles_side_ * (y / tile + tiles_side_ * (z / tile));
    }
    static std::size_t in_tile(std::uint32_t t, std::size_t x, std::size_t y, std::size_t z) {
        return std::size_t(t - 1) * tile * tile * tile + x % tile + tile * (y % tile + tile * (z % tile));
    }
    // The tiled entry of a block (its tile made if needed), or nullptr where the block is hashed (no
    // tiles, or outside them).
    std::uint32_t* tiled(std::uint64_t bk) {
        const std::size_t x = bk & mc::max_lattice, y = (bk >> 17) & mc::max_lattice, z = bk >> 34;
        if (x >= side_ || y >= side_ || z >= side_) return nullptr;  // side_ is 0 without tiles
        std::uint32_t& t = directory_[tile_of(x, y, z)];
        if (t == 0) {
            tiles_.resize(tiles_.size() + tile * tile * tile, 0);
            t = static_cast<std::uint32_t>(tiles_.size() / (tile * tile * tile));
        }
        return &tiles_[in_tile(t, x, y, z)];
    }
    static std::size_t slot(std::uint64_t bk) { return (bk & 15) | ((bk >> 17) & 15) << 4 | ((bk >> 34) & 15) << 8; }
    std::size_t side_ = 0, tiles_side_ = 0;  // blocks and tiles per axis (0: no tiles)
    std::vector<std::uint32_t> directory_;   // per tile: its number + 1 in tiles_ (0 = none yet)
    std::vector<std::uint32_t> tiles_;       // per tile, per block: the block's number + 1 (0 = none)
    KeyMap map_;
    std::vector<Cached> cache_ = std::vector<Cached>(cache_size);
    std::size_t count_ = 0;
};

// A set of lattice cubes (by their lower corner) as bits of blocks.
class CubeSet {
public:
    CubeSet(std::size_t expected, std::uint32_t lattice) : blocks_(expected / 8 + 16, lattice) {}
    // True when `key` was not in the set; it is now.
    bool insert(std::uint64_t key) {
        bool created;
        const std::uint32_t b = blocks_.of(key, created);
        if (created) bits_.push_back(0);
        const std::uint64_t bit = std::uint64_t(1) << Blocks::local(key);
        if (bits_[b] & bit) return false;
        bits_[b] |= bit;
        return true;
    }

    // Whether `key` is in the set, without inserting: safe on several threads at once while nobody
    // inserts, each with its own cache of Blocks::cache_size entries.
    bool contains(std::uint64_t key, Blocks::Cached* cache) const {
        const std::uint32_t b = blocks_.find(key, cache);
        return b != none && (bits_[b] >> Blocks::local(key)) & 1u;
    }

private:
    Blocks blocks_;
    std::vector<std::uint64_t> bits_;
};

// f(cube) for each of the (up to) four leaf cubes around the leaf edge from lattice point `a` along
// `axis` (the cubes below the lattice's zero planes do not exist).
template <class F> void for_cubes_around(std::uint64_t a, int axis, F&& f) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int c = 0; c < 4; ++c) {
        const int du = c & 1, dv = c >> 1;
        if ((du && ((a >> (17 * u)) & mc::max_lattice) == 0) || (dv && ((a >> (17 * v)) & mc::max_lattice) == 0)) continue;
        f(a - std::uint64_t(du) * (std::uint64_t(1) << (17 * u)) - std::uint64_t(dv) * (std::uint64_t(1) << (17 * v)));
    }
}

// The signed distance field on the leaf lattice, evaluated on demand and kept, in a sparse grid of 4x4x4
// blocks (Blocks), so the 8 corners of a cube or the samples of a node mostly cost one look-up together.
class Field {
public:
    Field(const PointCloud& pc, const KdTree& tree, Vec3f origin, float h, std::uint32_t grid, unsigned threads)
        : pc_(pc), tree_(tree), origin_(origin), h_(h), grid_(grid), threads_(threads) {}

    // When set, the sign is the mesh's winding number instead of the nearest point's normal (D1).
    void sign_by_winding(const mc::WindingTree* winding) { winding_ = winding; }

    Vec3f world(std::uint64_t key) const {
        const auto x = float(key & mc::max_lattice), y = float((key >> 17) & mc::max_lattice),
                   z = float((key >> 34) & mc::max_lattice);
        return {origin_.x + x * h_, origin_.y + y * h_, origin_.z + z * h_};
    }
    // Evaluates every key not known yet (duplicates allowed), in parallel; `keys` is left holding the
    // evaluated keys. Duplicates and known keys are dropped through the blocks' bit masks (one look-up per
    // key, mostly the cached last block), not by sorting, and the rest is read back block by block from
    // those bits (blocks in order of first use), so each query's hint, the previous key's nearest point,
    // is mostly within 3 lattice steps: the closing's keys otherwise alternate between levels (on the dragon
    // at 256, 6 % fewer points pass a query's bound). The values do not depend on the order (D1).
    void evaluate(std::vector<std::uint64_t>& keys) {
        touched_.clear();
        for (const std::uint64_t k : keys) {
            const std::uint32_t b = block_of(k);
            const std::uint64_t bit = std::uint64_t(1) << local(k);
            if ((valid_[b] | pending_[b]) & bit) continue;
            if (!pending_[b]) touched_.push_back(b);
            pending_[b] |= bit;
        }
        // The values are written in place by the query threads (every block exists by now, and each value
        // has one writer), then the blocks' bits are settled: no second look-up per key.
        keys.clear();
        at_.clear();
        for (const std::uint32_t b : touched_) {
            for (std::uint64_t bits = pending_[b]; bits; bits &= bits - 1) {
                const auto l = static_cast<std::uint32_t>(std::countr_zero(bits));
                keys.push_back(block_key_[b] | pack(l & 3, (l >> 2) & 3, l >> 4));
                at_.push_back(b * 64 + l);
            }
        }
        parallel_for(keys.size(), threads_, [&](std::size_t b, std::size_t e) {
            std::uint32_t hint = none;  // the previous key's nearest point: the keys come block by block
            for (std::size_t i = b; i < e; ++i) {
                const std::uint32_t at = at_[i];
                query(keys[i], dist_[at], nearest_[at], hint);
                hint = nearest_[at];
            }
        });
        for (const std::uint32_t b : touched_) {
            valid_[b] |= pending_[b];
            pending_[b] = 0;
        }
        evaluated_ += keys.size();
    }
    // Scatters every point to the lattice points closer than `radius` cube sizes (D1, "Field by
    // scattering"): a lattice point that receives a point this way has its exact nearest point (every
    // point within the radius reached it; ties to the lowest index, points are taken in index order);
    // the others are left to the kd-tree. With two threads or more the lattice is cut at a block boundary
    // near the points' median x: each half is scattered by every point into a block set of its own (so
    // every lattice point is still written by one thread, in point order), and the halves' blocks are
    // then added to the field's. The values are the same either way; only the blocks' numbering differs,
    // which nothing reads.
    void scatter(float radius, unsigned threads) {
        const float r2 = (radius * h_) * (radius * h_);
        if (threads < 2 || pc_.points.size() < 20000) {
            struct Direct {  // the field's own blocks
                Field& field;
                std::vector<std::uint64_t>& pending;
                std::vector<float>& dist;
                std::vector<std::uint32_t>& nearest;
                std::uint32_t block_of(std::uint64_t key) { return field.block_of(key); }
            } direct{*this, pending_, dist_, nearest_};
            scatter_slab(r2, radius, 0, grid_ + 1, direct);
        } else {
            std::vector<float> xs;
            for (std::size_t i = 0; i < pc_.points.size(); i += 16) xs.push_back(pc_.points[i].x);
            std::nth_element(xs.begin(), xs.begin() + std::ptrdiff_t(xs.size() / 2), xs.end());
            const auto mid = static_cast<std::uint32_t>(std::clamp((xs[xs.size() / 2] - origin_.x) / h_, 0.f, float(grid_)));
            const std::uint32_t cut = mid & ~3u;  // a block boundary: no block spans both halves
            std::array<ScatterSlab, 2> slabs{ScatterSlab(grid_ + 1), ScatterSlab(grid_ + 1)};
            detail::run_beside(
                2, [&] { scatter_slab(r2, radius, 0, cut, slabs[0]); },
                [&] { scatter_slab(r2, radius, cut, grid_ + 1, slabs[1]); });
            for (const ScatterSlab& slab : slabs) {
                for (std::size_t sb = 0; sb < slab.pending.size(); ++sb) {
                    const std::uint64_t bits = slab.pending[sb];
                    if (!bits) continue;
                    const std::uint32_t b = block_of(slab.block_key[sb]);
                    for (std::uint64_t left = bits; left; left &= left - 1) {
                        const auto l = static_cast<std::uint32_t>(std::countr_zero(left));
                        dist_[b * 64 + l] = slab.dist[sb * 64 + l];
                        nearest_[b * 64 + l] = slab.nearest[sb * 64 + l];
                    }
                    pending_[b] |= bits;
                }
            }
        }
        // Each value has one writer. Signed by a winding number (a low-poly mesh, D1) a value costs a tree
        // walk, so the blocks are shared out; otherwise the loop is too cheap to split.
        auto finish_blocks = [&](std::size_t lo, std::size_t hi) {
            for (std::size_t b = lo; b < hi; ++b)
                for (std::uint64_t bits = pending_[b]; bits; bits &= bits - 1) {
                    const auto l = static_cast<std::uint32_t>(std::countr_zero(bits));
                    const std::size_t at = b * 64 + l;
                    finish(block_key_[b] | pack(l & 3, (l >> 2) & 3, l >> 4), dist_[at], nearest_[at], dist_[at], nearest_[at]);
                }
        };
        if (winding_) parallel_for(valid_.size(), threads_, finish_blocks);
        else finish_blocks(0, valid_.size());
        scattered_ = 0;
        for (std::uint32_t b = 0; b < valid_.size(); ++b) {
            scattered_ += std::size_t(std::popcount(pending_[b]));
            valid_[b] |= pending_[b];
            pending_[b] = 0;
        }
    }
    // Blocks of one half of the lattice during a two-thread scatter.
    struct ScatterSlab {
        explicit ScatterSlab(std::uint32_t lattice) : blocks(1 << 12, lattice) {}
        Blocks blocks;
        std::vector<std::uint64_t> pending, block_key;
        std::vector<float> dist;
        std::vector<std::uint32_t> nearest;
        std::uint32_t block_of(std::uint64_t key) {
            bool created;
            const std::uint32_t b = blocks.of(key, created);
            if (created) {
                pending.push_back(0);
                block_key.push_back(key & ~pack(3, 3, 3));
                dist.resize(dist.size() + 64);
                nearest.resize(nearest.size() + 64);
            }
            return b;
        }
    };
    // Every point's writes to the lattice points with x in [x_begin, x_end) within the radius, into `out`'s
    // blocks (the field itself or a ScatterSlab: block_of, pending, dist, nearest).
    template <class Out>
    void scatter_slab(float r2, float radius, std::uint32_t x_begin, std::uint32_t x_end, Out& out) const {
        const float inv = 1.f / h_;
        // Per point, the squared offsets along each axis to the lattice lines around it (the same float
        // operations as world() and distance2(), so a sum below is the query's squared distance exactly);
        // the candidates reach one lattice line beyond the radius on each side, the exact test decides.
        const int reach = static_cast<int>(std::ceil(radius)) + 1, width = 2 * reach + 1;  // lines c - reach .. c + reach
        std::vector<float> t2(3 * std::size_t(width));
        std::vector<std::uint32_t> first(3);
        for (std::uint32_t i = 0; i < pc_.points.size(); ++i) {
            const Vec3f p = pc_.points[i];
            for (int a = 0; a < 3; ++a) {
                const float rel = (p[a] - origin_[a]) * inv;
                const int c = std::clamp(static_cast<int>(rel), 0, int(grid_));
                const int lo = std::max(0, c - reach);
                first[std::size_t(a)] = std::uint32_t(lo);
                for (int k = 0; k < width; ++k) {
                    const int x = lo + k;
                    const float t = (origin_[a] + float(x) * h_) - p[a];
                    const bool in = a == 0 ? x >= int(x_begin) && x < int(x_end) : x <= int(grid_);
                    t2[std::size_t(a * width + k)] = in ? t * t : INFINITY;
                }
            }
            const float* tx = t2.data();
            const float* ty = tx + width;
            const float* tz = ty + width;
            for (int ix = 0; ix < width; ++ix) {
                if (!(tx[ix] < r2)) continue;
                for (int iy = 0; iy < width; ++iy) {
                    const float dxy2 = tx[ix] + ty[iy];
                    if (!(dxy2 < r2)) continue;
                    const std::uint32_t x = first[0] + std::uint32_t(ix), y = first[1] + std::uint32_t(iy);
                    std::uint32_t base = 0, b = 0, bz = none;
                    for (int iz = 0; iz < width; ++iz) {
                        const float d2 = dxy2 + tz[iz];
                        if (!(d2 < r2)) continue;
                        const std::uint32_t z = first[2] + std::uint32_t(iz);
                        if ((z >> 2) != bz) bz = z >> 2, b = out.block_of(pack(x, y, z)), base = b * 64 + local(pack(x, y, 0));
                        const std::uint32_t l = (z & 3) << 4;
                        const std::uint64_t bit = std::uint64_t(1) << (l + (base & 63));
                        const std::uint32_t at = base + l;
                        if ((out.pending[b] & bit) && !(d2 < out.dist[at])) continue;
                        out.pending[b] |= bit;
                        out.dist[at] = d2;
                        out.nearest[at] = i;
                    }
                }
            }
        }
    }
    std::size_t scattered() const { return scattered_; }
    // Global index of the value at `key` (evaluated now when unknown).
    std::uint32_t index(std::uint64_t key) {
        const std::uint32_t b = block_of(key);
        const std::uint32_t i = b * 64 + local(key);
        if (!(valid_[b] & (std::uint64_t(1) << local(key)))) {
            query(key, dist_[i], nearest_[i]);
            valid_[b] |= std::uint64_t(1) << local(key);
            ++evaluated_;
        }
        return i;
    }
    // Memo of the vertex on each leaf edge (none = not made yet), kept with the field's blocks:
    // neighbouring cubes share edges and read their memos from the same block.
    void clear_leaf_edge_vertices(unsigned threads) {
        parallel_for(edge_vertex_.size(), threads, [&](std::size_t b, std::size_t e) {
            std::fill(edge_vertex_.begin() + std::ptrdiff_t(b), edge_vertex_.begin() + std::ptrdiff_t(e), none);
        });
    }
    // Where the memo of the leaf edge (key, axis) lives: an index for leaf_edge_vertex_at, stable while
    // blocks are added; the peek form gives npos when the block does not exist (several threads at once).
    static constexpr std::size_t npos = ~std::size_t(0);
    std::size_t leaf_edge_slot(std::uint64_t key, int axis) {
        return std::size_t(block_of(key)) * 192 + local(key) * 3 + std::size_t(axis);
    }
    std::size_t peek_leaf_edge_slot(std::uint64_t key, int axis, Blocks::Cached* cache) const {
        const std::uint32_t b = blocks_.find(key, cache);
        return b == none ? npos : std::size_t(b) * 192 + local(key) * 3 + std::size_t(axis);
    }
    std::uint32_t& leaf_edge_vertex_at(std::size_t slot) { return edge_vertex_[slot]; }
    float dist(std::uint32_t i) const { return dist_[i]; }  // signed: < 0 inside
    std::uint32_t nearest(std::uint32_t i) const { return nearest_[i]; }
    bool inside(std::uint64_t key) { return dist_[index(key)] < 0; }
    // Inside (1), outside (0) or not evaluated yet (-1), without evaluating: safe on several threads at once
    // between evaluations, each with its own cache of Blocks::cache_size entries.
    int peek_inside(std::uint64_t key, Blocks::Cached* cache) const {
        const std::uint32_t b = blocks_.find(key, cache);
        if (b == none || !(valid_[b] & (std::uint64_t(1) << local(key)))) return -1;
        return dist_[b * 64 + local(key)] < 0;
    }
    // Index of the value at `key` if it is evaluated, else none (like peek_inside: several threads at once).
    std::uint32_t peek_index(std::uint64_t key, Blocks::Cached* cache) const {
        const std::uint32_t b = blocks_.find(key, cache);
        if (b == none || !(valid_[b] & (std::uint64_t(1) << local(key)))) return none;
        return b * 64 + local(key);
    }
    // The signed distance at `key` if it is evaluated (like peek_inside: several threads at once).
    bool peek_dist(std::uint64_t key, Blocks::Cached* cache, float& d) const {
        const std::uint32_t b = blocks_.find(key, cache);
        if (b == none || !(valid_[b] & (std::uint64_t(1) << local(key)))) return false;
        d = dist_[b * 64 + local(key)];
        return true;
    }
    std::size_t size() const { return evaluated_; }
    void reserve_blocks(std::size_t n) {
        valid_.reserve(n);
        pending_.reserve(n);
        dist_.reserve(64 * n);
        nearest_.reserve(64 * n);
        edge_vertex_.reserve(192 * n);
        block_key_.reserve(n);
    }

private:
    static std::uint32_t local(std::uint64_t key) { return Blocks::local(key); }
    std::uint32_t block_of(std::uint64_t key) {
        bool created;
        const std::uint32_t b = blocks_.of(key, created);
        if (created) {
            valid_.push_back(0);
            pending_.push_back(0);
            dist_.resize(dist_.size() + 64);
            nearest_.resize(nearest_.size() + 64);
            edge_vertex_.resize(edge_vertex_.size() + 192, none);
            block_key_.push_back(key & ~pack(3, 3, 3));
        }
        return b;
    }
    // Squared distance as nanoflann's L2_Simple_Adaptor computes it (same order of operations).
    float distance2(const float q[3], std::uint32_t i) const {
        float r = 0;
        for (int a = 0; a < 3; ++a) {
            const float t = q[a] - pc_.points[i][a];
            r += t * t;
        }
        return r;
    }
    // `hint` (a point near the key, or none) bounds the search: the kd-tree then prunes from its first
    // leaf on. The bound sits strictly above the hint's distance, so every point at the minimum distance
    // is still visited and the result is the field's nearest point (ties to the lowest index, D1).
    void query(std::uint64_t key, float& d, std::uint32_t& nearest, std::uint32_t hint = none) const {
        const Vec3f v = world(key);
        const float q[3] = {v.x, v.y, v.z};
        LowestNearest rs;
        if (hint != none) rs.bound = distance2(q, hint) * (1 + 1e-4f) + 1e-30f;
        tree_.findNeighbors(rs, q, nanoflann::SearchParams());
        if (rs.idx == none) rs.idx = hint, rs.best = distance2(q, hint);  // nothing below the bound (rounding)
        finish(key, rs.best, rs.idx, d, nearest);
    }
    // Signed distance from the squared distance to the nearest point.
    void finish(std::uint64_t key, float d2, std::uint32_t idx, float& d, std::uint32_t& nearest) const {
        const Vec3f diff = world(key) - pc_.points[idx];
        const float dist = std::sqrt(d2);
        // A corner on the tangent plane counts as outside, so every corner gets exactly one sign. So does
        // every point of the grid's outer boundary: a zero set that would run out of the grid (a bridge
        // across a scan hole, an open scan without band) closes inside it instead.
        const auto x = std::uint32_t(key & mc::max_lattice), y = std::uint32_t((key >> 17) & mc::max_lattice),
                   z = std::uint32_t((key >> 34) & mc::max_lattice);
        const bool boundary = x == 0 || y == 0 || z == 0 || x >= grid_ || y >= grid_ || z >= grid_;
        // beta 1.5: the Duck's and Spot's cage's trees at 128 are the same as at 2 (the usual choice), for
        // two thirds of the time (at 1.0 the Duck's changed).
        const bool inside = winding_ ? mc::winding_number(*winding_, world(key), 1.5) > 0.5 : dot(diff, pc_.normals[idx]) < 0;
        d = !boundary && inside ? -dist : dist;
        nearest = idx;
    }
    const mc::WindingTree* winding_ = nullptr;
    const PointCloud& pc_;
    const KdTree& tree_;
    Vec3f origin_;
    float h_;
    std::uint32_t grid_;
    unsigned threads_;
    Blocks blocks_{1 << 12, grid_ + 1};
    std::vector<std::uint64_t> valid_;    // per block: which of its 64 values are evaluated
    std::vector<std::uint64_t> pending_;  // per block: queued in the current evaluate()
    std::vector<float> dist_;
    std::vector<std::uint32_t> nearest_;
    std::vector<std::uint32_t> edge_vertex_;  // per block: 64 points x 3 axes
    std::vector<std::uint64_t> block_key_;    // per block: its lowest lattice point
    std::size_t scattered_ = 0;
    std::vector<std::uint32_t> at_;  // evaluate(): each key's value index
    std::vector<std::uint32_t> touched_;  // blocks with pending keys, in order of first use
    std::size_t evaluated_ = 0;
};

}  // namespace lodforge::mc
