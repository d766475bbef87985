// Triangle strips: vertex cache order, then greedy strip growth along that order.
//
// Forsyth, "Linear-speed vertex cache optimisation", 2006 (the triangle order and its scoring).
// Evans, Skiena, Varshney, "Optimizing triangle strips for fast rendering", IEEE Vis 1996 (greedy growth
//   from low-degree triangles, swaps as an extra index).
// Kapoulkine, meshoptimizer src/stripifier.cpp (growing strips along a cache-optimised order, the
//   "a b a c" swap chosen when the default exit edge leads nowhere).
// Ramos et al., "LODStrips", 2008 (why the individual strips are kept).
// StripOrder::cache takes its order from meshoptimizer's meshopt_optimizeVertexCacheStrip (Kapoulkine,
//   src/vcacheoptimizer.cpp; Forsyth's algorithm with score tables tuned for strips).

#include "lodforge/strips/stripify.h"

#include "lodforge/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <meshoptimizer.h>

namespace lodforge {

namespace {

constexpr std::uint32_t no_triangle = std::numeric_limits<std::uint32_t>::max();

// Triangles around each vertex (compressed rows).
struct VertexTriangles {
    std::vector<std::uint32_t> offsets;  // vertex_count + 1
    std::vector<std::uint32_t> list;

    VertexTriangles(std::span<const std::uint32_t> tri, std::size_t vertex_count) : offsets(vertex_count + 1, 0) {
        for (std::uint32_t v : tri) ++offsets[v + 1];
        for (std::size_t v = 0; v < vertex_count; ++v) offsets[v + 1] += offsets[v];
        list.resize(tri.size());
        std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::size_t i = 0; i < tri.size(); ++i) list[fill[tri[i]]++] = std::uint32_t(i / 3);
    }
    std::span<const std::uint32_t> of(std::uint32_t v) const {
        return {list.data() + offsets[v], list.data() + offsets[v + 1]};
    }
};

// ---------------------------------------------------------------------------------------------------------
// Forsyth's order: repeatedly emit the live triangle with the best sum of vertex scores, where a vertex
// scores by its position in a simulated LRU cache and by how few live triangles it has left.

constexpr float kCacheDecayPower = 1.5f;
// Forsyth uses 0.75 (below a vertex at position 3) to avoid strip-like orders; for strips we want them.
constexpr float kLastTriScore = 3.0f;
constexpr float kValenceBoostScale = 2.0f;
constexpr float kValenceBoostPower = 0.5f;

struct ScoreTables {
    std::vector<float> cache;    // by cache position
    std::vector<float> valence;  // by live triangle count

    explicit ScoreTables(std::size_t cache_size) : cache(cache_size), valence(64) {
        for (std::size_t i = 0; i < cache_size; ++i) {
            if (i < 3) {
                cache[i] = kLastTriScore;
            } else {
                const float scaler = 1.0f / float(cache_size - 3);
                cache[i] = std::pow(1.0f - float(i - 3) * scaler, kCacheDecayPower);
            }
        }
        valence[0] = 0;
        for (std::size_t i = 1; i < valence.size(); ++i) {
            valence[i] = kValenceBoostScale * std::pow(float(i), -kValenceBoostPower);
        }
    }
    float score(int cache_position, std::uint32_t live) const {
        if (live == 0) return -1.0f;
        float s = cache_position >= 0 ? cache[std::size_t(cache_position)] : 0.0f;
        s += live < valence.size() ? valence[live] : kValenceBoostScale * std::pow(float(live), -kValenceBoostPower);
        return s;
    }
};

// Beyond this the modelled cache changes nothing measurable and would only cost time and memory.
constexpr std::size_t kMaxModelledCache = 64;

// Returns the triangle order: order[k] = input triangle drawn k-th.
std::vector<std::uint32_t> forsyth_order(std::span<const std::uint32_t> tri, std::size_t vertex_count,
                                         std::size_t requested_cache_size, Progress* progress) {
    const std::size_t cache_size = std::min(requested_cache_size, kMaxModelledCache);
    const std::size_t tri_count = tri.size() / 3;
    std::vector<std::uint32_t> order;
    order.reserve(tri_count);
    if (tri_count == 0) return order;

    VertexTriangles adj(tri, vertex_count);
    // Live triangles of v are adj.list[offsets[v], offsets[v] + live[v]) (emitted ones swapped to the end).
    std::vector<std::uint32_t> live(vertex_count);
    for (std::size_t v = 0; v < vertex_count; ++v) live[v] = adj.offsets[v + 1] - adj.offsets[v];
    std::vector<int> cache_pos(vertex_count, -1);
    const ScoreTables tables(cache_size);
    std::vector<float> vscore(vertex_count);
    for (std::size_t v = 0; v < vertex_count; ++v) vscore[v] = tables.score(-1, live[v]);
    std::vector<std::uint8_t> emitted(tri_count, 0);

    std::vector<std::uint32_t> cache, next_cache;
    cache.reserve(cache_size + 3);
    next_cache.reserve(cache_size + 3);
    std::size_t scan = 0;  // input-order fallback when the cache has no live triangle
    std::uint32_t best = 0;
    for (std::size_t k = 0; k < tri_count; ++k) {
        if ((k & 0xFFFF) == 0) check_progress(progress, 0.5 * double(k) / double(tri_count), "stripify: cache order");
        if (best == no_triangle) {
            while (emitted[scan]) ++scan;
            best = std::uint32_t(scan);
        }
        const std::uint32_t t = best;
        order.push_back(t);
        emitted[t] = 1;

        next_cache.clear();
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = tri[3 * t + std::size_t(c)];
            // remove t from v's live triangles
            std::uint32_t* begin = adj.list.data() + adj.offsets[v];
            std::uint32_t* end = begin + live[v];
            std::uint32_t* it = std::find(begin, end, t);
            std::swap(*it, *(end - 1));
            --live[v];
            next_cache.push_back(v);
        }
        for (std::uint32_t v : cache) {
            if (v != next_cache[0] && v != next_cache[1] && v != next_cache[2]) next_cache.push_back(v);
        }
        // Vertices pushed out of the modelled cache lose their cache score.
        for (std::size_t i = cache_size; i < next_cache.size(); ++i) cache_pos[next_cache[i]] = -1;
        if (next_cache.size() > cache_size) next_cache.resize(cache_size);
        for (std::size_t i = 0; i < next_cache.size(); ++i) cache_pos[next_cache[i]] = int(i);

        // Rescore the vertices whose cache position or live count changed, then pick the best live triangle
        // around the cache; triangles elsewhere are only needed when the cache runs dry (input order).
        for (std::uint32_t v : cache) {
            if (cache_pos[v] < 0) vscore[v] = tables.score(-1, live[v]);
        }
        for (std::uint32_t v : next_cache) vscore[v] = tables.score(cache_pos[v], live[v]);
        std::swap(cache, next_cache);

        best = no_triangle;
        float best_score = -std::numeric_limits<float>::infinity();
        for (std::uint32_t v : cache) {
            const std::uint32_t* lt = adj.list.data() + adj.offsets[v];
            for (std::uint32_t i = 0; i < live[v]; ++i) {
                const std::uint32_t* tv = &tri[3 * std::size_t(lt[i])];
                const float score = vscore[tv[0]] + vscore[tv[1]] + vscore[tv[2]];
                if (score > best_score) {
                    best_score = score;
                    best = lt[i];
                }
            }
        }
    }
    return order;
}

// ---------------------------------------------------------------------------------------------------------
// Strip growth over triangles in drawing-order rank (tri[3r..3r+2] is the triangle of rank r).

class StripBuilder {
public:
    StripBuilder(std::span<const std::uint32_t> tri, std::size_t vertex_count, std::size_t window)
        : tri_(tri), adj_(tri, vertex_count), used_(tri.size() / 3, 0), stamp_(tri.size() / 3, 0),
          window_(window) {}

    // Grows every strip; calls progress with the fraction of triangles stripped.
    std::vector<std::vector<std::uint32_t>> run(std::size_t& swaps, Progress* progress) {
        std::vector<std::vector<std::uint32_t>> strips;
        const std::size_t count = used_.size();
        std::size_t done = 0, next_report = 0;
        while (true) {
            while (frontier_ < count && used_[frontier_]) ++frontier_;
            if (frontier_ == count) break;
            if (done >= next_report) {
                check_progress(progress, 0.5 + 0.5 * double(done) / double(count), "stripify: strips");
                next_report = done + 0x4000;
            }
            slide_limit(kCandidates);
            const std::uint32_t start = pick_start();

            Trial best;
            for (int rotation = 0; rotation < 3; ++rotation) {
                Trial trial = grow(start, rotation);
                if (rotation == 0 || trial.triangles.size() > best.triangles.size() ||
                    (trial.triangles.size() == best.triangles.size() && trial.swaps < best.swaps)) {
                    best = std::move(trial);
                }
            }
            for (std::uint32_t t : best.triangles) used_[t] = 1;
            done += best.triangles.size();
            swaps += best.swaps;
            strips.push_back(std::move(best.indices));
        }
        return strips;
    }

private:
    // How many of the first unstripped triangles compete to start the next strip.
    static constexpr int kCandidates = 4;

    struct Trial {
        std::vector<std::uint32_t> indices;
        std::vector<std::uint32_t> triangles;
        std::size_t swaps = 0;
    };

    bool available(std::uint32_t t) const { return t < limit_ && !used_[t] && stamp_[t] != trial_; }

    // The lowest-rank available triangle with directed edge e0 -> e1; its third vertex in `third`.
    std::uint32_t find(std::uint32_t e0, std::uint32_t e1, std::uint32_t* third = nullptr) const {
        std::uint32_t found = no_triangle;
        for (std::uint32_t t : adj_.of(e0)) {
            if (t >= found || !available(t)) continue;
            const std::uint32_t* v = &tri_[3 * std::size_t(t)];
            for (int c = 0; c < 3; ++c) {
                if (v[c] == e0 && v[(c + 1) % 3] == e1) {
                    found = t;
                    if (third) *third = v[(c + 2) % 3];
                }
            }
        }
        return found;
    }

    int open_edges(std::uint32_t t) const {
        const std::uint32_t* v = &tri_[3 * std::size_t(t)];
        int n = 0;
        for (int c = 0; c < 3; ++c) n += find(v[(c + 1) % 3], v[c]) != no_triangle;
        return n;
    }

    // Among the first few unstripped triangles of the order, the one with the fewest open neighbours
    // (strips started at dead ends leave fewer isolated triangles behind).
    std::uint32_t pick_start() {
        ++trial_;
        std::uint32_t best = no_triangle;
        int best_open = 4;
        int seen = 0;
        for (std::size_t t = frontier_; t < limit_ && seen < kCandidates; ++t) {
            if (used_[t]) continue;
            ++seen;
            const int open = open_edges(std::uint32_t(t));
            if (open < best_open) {
                best_open = open;
                best = std::uint32_t(t);
            }
        }
        return best;
    }

    // The strip may take triangles of rank < frontier + window + (triangles it holds): a window of
    // `window` unstripped triangles that slides as the strip consumes the order.
    void slide_limit(std::size_t taken) {
        limit_ = window_ == 0 ? used_.size() : std::min(used_.size(), frontier_ + window_ + taken);
    }

    // Strip from triangle t starting with its vertex `rotation`; triangles claimed with a fresh stamp.
    Trial grow(std::uint32_t t, int rotation) {
        ++trial_;
        slide_limit(1);
        Trial s;
        const std::uint32_t* v = &tri_[3 * std::size_t(t)];
        s.indices = {v[rotation], v[(rotation + 1) % 3], v[(rotation + 2) % 3]};
        s.triangles.push_back(t);
        stamp_[t] = trial_;
        while (true) {
            const std::size_t n = s.indices.size();
            const std::uint32_t x = s.indices[n - 2], y = s.indices[n - 1];
            const bool even = (n - 2) % 2 == 0;  // position of the next triangle
            std::uint32_t w = 0;
            const std::uint32_t next = even ? find(x, y, &w) : find(y, x, &w);
            if (next == no_triangle) break;
            stamp_[next] = trial_;
            s.triangles.push_back(next);
            slide_limit(s.triangles.size());
            // Default exit edge after w: (y, w) at the following position; the swap "x y x w" exits (x, w).
            const bool default_open = even ? find(w, y) != no_triangle : find(y, w) != no_triangle;
            if (!default_open && (even ? find(x, w) : find(w, x)) != no_triangle) {
                s.indices.push_back(x);
                ++s.swaps;
            }
            s.indices.push_back(w);
        }
        return s;
    }

    std::span<const std::uint32_t> tri_;
    VertexTriangles adj_;
    std::vector<std::uint8_t> used_;
    std::vector<std::uint32_t> stamp_;
    std::size_t window_;
    std::size_t frontier_ = 0;
    std::size_t limit_ = 0;
    std::uint32_t trial_ = 0;
};

void join_strips(StripifyResult& r) {
    std::size_t total = 0;
    for (const auto& s : r.strips) total += s.size() + 3;
    r.indices.reserve(total);
    for (const auto& s : r.strips) {
        if (!r.indices.empty()) {
            if (r.join == StripJoin::restart) {
                r.indices.push_back(restart_index);
            } else {
                // "... y y u u v w": every triangle across the join repeats an index. An odd prefix would
                // put the next strip on an odd position and flip its winding: repeat y once more.
                const std::uint32_t y = r.indices.back();
                r.indices.push_back(y);
                if (r.indices.size() % 2 == 0) r.indices.push_back(y);
                r.indices.push_back(s.front());
            }
        }
        r.indices.insert(r.indices.end(), s.begin(), s.end());
    }
}

}  // namespace

std::vector<std::uint32_t> optimize_vertex_cache(std::span<const std::uint32_t> indices, std::size_t vertex_count,
                                                 std::size_t cache_size) {
    if (indices.size() % 3 != 0) {
        throw Error(Error::Kind::argument, "optimize_vertex_cache: index count " + std::to_string(indices.size()) +
                                               " is not a multiple of 3");
    }
    if (cache_size < 3) throw Error(Error::Kind::argument, "optimize_vertex_cache: cache size must be at least 3");
    for (std::size_t i = 0; i < indices.size(); ++i) {
        if (indices[i] >= vertex_count) {
            throw Error(Error::Kind::argument, "optimize_vertex_cache: index " + std::to_string(indices[i]) +
                                                   " at position " + std::to_string(i) + " is out of range");
        }
    }
    const std::vector<std::uint32_t> order = forsyth_order(indices, vertex_count, cache_size, nullptr);
    std::vector<std::uint32_t> out;
    out.reserve(indices.size());
    for (std::uint32_t t : order) out.insert(out.end(), indices.begin() + 3 * t, indices.begin() + 3 * t + 3);
    return out;
}

StripifyResult stripify(std::span<const std::uint32_t> indices, std::size_t vertex_count,
                        const StripifyParams& params, Progress* progress) {
    if (indices.size() % 3 != 0) {
        throw Error(Error::Kind::argument,
                    "stripify: index count " + std::to_string(indices.size()) + " is not a multiple of 3");
    }
    if (params.cache_size < 3) throw Error(Error::Kind::argument, "stripify: cache size must be at least 3");
    if (vertex_count >= restart_index) {
        throw Error(Error::Kind::argument, "stripify: " + std::to_string(vertex_count) +
                                               " vertices leave no room for the restart index");
    }
    StripifyResult r;
    r.join = params.join;

    // Drop degenerate triangles; check indices.
    std::vector<std::uint32_t> tri;
    tri.reserve(indices.size());
    for (std::size_t i = 0; i < indices.size(); i += 3) {
        const std::uint32_t a = indices[i], b = indices[i + 1], c = indices[i + 2];
        for (std::size_t k = 0; k < 3; ++k) {
            if (indices[i + k] >= vertex_count) {
                throw Error(Error::Kind::argument, "stripify: triangle " + std::to_string(i / 3) + " has index " +
                                                       std::to_string(indices[i + k]) + ", vertex count is " +
                                                       std::to_string(vertex_count));
            }
        }
        if (a == b || b == c || a == c) {
            ++r.degenerate_dropped;
            continue;
        }
        tri.insert(tri.end(), {a, b, c});
    }
    r.triangles = tri.size() / 3;

    if (params.optimize_cache && params.order == StripOrder::cache && !tri.empty()) {
        check_progress(progress, 0.0, "stripify: cache order");
        std::vector<std::uint32_t> ordered(tri.size());
        meshopt_optimizeVertexCacheStrip(ordered.data(), tri.data(), tri.size(), vertex_count);
        tri = std::move(ordered);
    } else if (params.optimize_cache) {
        const std::vector<std::uint32_t> order = forsyth_order(tri, vertex_count, params.cache_size, progress);
        std::vector<std::uint32_t> ordered;
        ordered.reserve(tri.size());
        for (std::uint32_t t : order) ordered.insert(ordered.end(), tri.begin() + 3 * t, tri.begin() + 3 * t + 3);
        tri = std::move(ordered);
    }

    // meshopt's order runs off in strips less than ours: a strip must look further ahead to stay long, and
    // 5 keeps ACMR16 and ACMR32 below meshopt_stripify's on that order (docs/stripify.md, window sweep).
    const std::size_t window = params.window != default_window ? params.window
                               : params.optimize_cache && params.order == StripOrder::cache ? 5 : 1;
    StripBuilder builder(tri, vertex_count, window);
    r.strips = builder.run(r.swaps, progress);
    join_strips(r);
    const Primitive primitive = r.join == StripJoin::restart ? Primitive::strip_restart : Primitive::strip_degenerate;
    r.indices_per_triangle = r.triangles ? double(r.indices.size()) / double(r.triangles) : 0.0;
    r.acmr = acmr(r.indices, vertex_count, params.cache_size, primitive);
    check_progress(progress, 1.0, "stripify: strips");
    return r;
}

StripifyResult stripify(const Mesh& mesh, const StripifyParams& params, Progress* progress) {
    return stripify(mesh.indices, mesh.vertex_count(), params, progress);
}

}  // namespace lodforge
