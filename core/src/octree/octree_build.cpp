// Adaptive octree construction on disk and bottom-up node simplification.
//
// Bade, Daman, Sunar, Tan, "Out-of-Core Simplification with Appearance Preservation for Computer
// Game Applications" (Universiti Teknologi Malaysia report, 2006, §3.4 and §3.5.3):
// triangles of the soup stream into an adaptive octree, a node splits while it holds more than max_tri
// triangles and lies above max_depth,
// each triangle lives in exactly one node (no clipping, no replication); leaves are simplified first and
// every coarser node from its children's output, up to the root. Differences, argued in docs/octree.md:
// the root is a cube around the bounding box (the document centres it on the mean vertex, which can
// leave triangles outside); a node whose triangles fit in the working memory is finished entirely in
// memory (its whole subtree: split, simplify, write), and only larger nodes are split by streaming over
// temporary files, so a triangle is rewritten log8(input / budget) times instead of once per level; the
// node quadric is the sum of the children's (Lindstrom's OoCS accumulation, SIGGRAPH 2000), so coarse
// representatives see the input triangles, not the already simplified fans.
#include "lodforge/octree/octree_build.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"
#include "lodforge/io/mesh_validate.h"
#include "lodforge/io/temp_directory.h"

#include "octree/octree_format.h"
#include "octree/ooc_internal.h"
#include "parallel_for.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iterator>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <system_error>
#include <thread>

namespace lodforge {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// What a finished node hands to its parent.
struct NodeResult {
    NodeMesh mesh;        // the node's simplified mesh
    NodeQuadric quadric;  // of every input triangle under it
    float error = 0;
    int height = 0;
    Bounds bounds;
    std::uint64_t triangles = 0;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> chords;  // free for the parent (sorted)
    explicit NodeResult(std::size_t dimension) : quadric(dimension) {}
};

// Triangles on disk: file regions of fixed-size records, read in order (a node split on two threads has
// one region from each thread).
struct TriangleRegion {
    std::string path;
    std::uint64_t offset = 0;
    std::uint64_t count = 0;
    bool owned = true;  // delete when consumed
};
struct TriangleFile {
    std::vector<TriangleRegion> regions;
    std::uint64_t count = 0;
};

// A streaming split takes two threads from this many triangles on (below it a thread costs more than
// the half it saves).
constexpr std::uint64_t kTwoThreadSplit = 16384;

// Root cube: centred on the bounding box, side = longest extent, grown by a relative margin so that
// float rounding can never put a vertex (hence a centroid) outside it.
void root_cube(const Bounds& b, float root_min[3], float& root_size) {
    const Vec3f c = b.center();
    const Vec3f s = b.size();
    double side = std::max({s.x, s.y, s.z});
    const double mag = std::max({std::fabs(b.min.x), std::fabs(b.min.y), std::fabs(b.min.z), std::fabs(b.max.x),
                                 std::fabs(b.max.y), std::fabs(b.max.z), 1e-30f});
    side = side * (1 + 1e-4) + mag * 1e-5;
    if (!(side > 0)) side = 1;
    const double cc[3] = {c.x, c.y, c.z};
    for (int a = 0; a < 3; ++a) root_min[a] = static_cast<float>(cc[a] - side / 2);
    root_size = static_cast<float>(side);
    // Enlarge until the float cube really encloses the float bounds.
    const float lo[3] = {b.min.x, b.min.y, b.min.z}, hi[3] = {b.max.x, b.max.y, b.max.z};
    for (int iter = 0; iter < 64; ++iter) {
        bool ok = true;
        for (int a = 0; a < 3; ++a) {
            if (root_min[a] > lo[a]) root_min[a] = std::nextafter(lo[a], -INFINITY), ok = false;
            if (root_min[a] + root_size <= hi[a]) root_size = std::nextafter(root_size * 1.0001f, INFINITY), ok = false;
        }
        if (ok) break;
    }
}

// Triangles a subtree may hold to be finished in memory: 40 % of the budget at record + 16 bytes each.
std::uint64_t in_memory_limit(std::size_t memory_bytes, const VertexLayout& layout) {
    return static_cast<std::uint64_t>(0.4 * static_cast<double>(memory_bytes)) / (soup_triangle_bytes(layout) + 16);
}

class Builder {
public:
    Builder(const OctreeBuildParams& p, SoupResult& soup, const std::string& scratch, AtomicFile& asset,
            Progress* progress)
        : p_(p), soup_(soup), scratch_(scratch), asset_(asset), progress_(progress), layout_(soup.layout),
          corner_(soup_corner_bytes(layout_)), tri_bytes_(soup_triangle_bytes(layout_)) {
        root_cube(soup.bounds, root_min_, root_size_);
        frame_.origin = {root_min_[0], root_min_[1], root_min_[2]};
        frame_.scale = root_size_;
        frame_.layout = layout_;
        frame_.weights = p.weights;
        wedge_ = soup.wedge_texcoords;
        uv_at_ = layout_.texcoord_offset();
        in_memory_limit_ = in_memory_limit(p.memory_bytes, layout_);
    }

    void run(OctreeBuildResult& result) {
        const std::vector<std::uint8_t> lead = ooc::asset_lead();
        write(lead.data(), lead.size());
        nodes_.emplace_back();
        OctreeNode& root = nodes_[0];
        root.parent = ~0u;
        std::copy(root_min_, root_min_ + 3, root.cell_min);
        root.cell_size = root_size_;
        if (!soup_.memory.empty()) {
            // The soup was kept in memory (it fits the in-memory share of the budget): no file to read.
            const std::size_t count = soup_.memory.size() / tri_bytes_;
            process_loaded(0, soup_.memory.data(), count, 0);
        } else if (soup_.root_split) {
            // The soup pass already wrote the root's octant files (SoupParams::root_split): the split
            // this builder would stream next, so the tree is the same.
            ++split_passes_;
            std::array<TriangleFile, 8> octants;
            for (int o = 0; o < 8; ++o) {
                octants[o].count = soup_.octant_counts[o];
                for (const SoupRegion& r : soup_.octants[o]) octants[o].regions.push_back({r.path, r.offset, r.count, true});
            }
            process_children(0, octants, 0);
        } else {
            process_file(0, {{{soup_.path, 64, soup_.triangles, true}}, soup_.triangles}, 0);
        }
        // The index (header fields and node table), then the footer that locates it.
        OctreeHeader h;
        h.layout = layout_;
        h.wedge_texcoords = wedge_;
        h.input_vertices = soup_.vertices;
        h.input_triangles = soup_.triangles;
        h.max_triangles = static_cast<std::uint32_t>(std::min<std::size_t>(p_.max_triangles, 0xffffffffu));
        h.max_depth = static_cast<std::uint32_t>(p_.max_depth);
        h.bounds = soup_.bounds;
        std::copy(root_min_, root_min_ + 3, h.root_min);
        h.root_size = root_size_;
        h.weights.normal = p_.weights.normal;
        h.weights.color = p_.weights.color;
        h.weights.texcoord = p_.weights.texcoord_sets.empty() ? p_.weights.texcoord : p_.weights.texcoord_sets[0];
        const std::uint64_t index_offset = offset_;
        const std::vector<std::uint8_t> index = encode_octree_index(h, nodes_);
        write(index.data(), index.size());
        write(&index_offset, sizeof index_offset);
        write(ooc::kAssetEndMagic, sizeof ooc::kAssetEndMagic);
        result.split_passes = split_passes_;
        result.closed_components = closed_components_;
        result.degenerate_triangles = degenerate_;
        result.oversized_leaves = oversized_;
    }
    double simplify_seconds() const { return simplify_seconds_; }

private:
    void write(const void* data, std::size_t bytes) {
        asset_.stream().write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
        if (!asset_.stream())
            throw_error(Error::Kind::io, asset_.target_path(), "write failed (disk full or I/O error)");
        offset_ += bytes;
    }
    // Wedge UVs split a vertex by its texcoord: the key is the input index with a 31-bit hash of the
    // u v bits above it (bit 63 stays clear for representatives), so every node derives the same key for
    // the same wedge and a UV seam becomes a pair of input border edges (docs/octree.md).
    static std::uint64_t wedge_key(std::uint32_t vid, const float* uv) {
        std::uint32_t bits[2];
        std::memcpy(bits, uv, sizeof bits);
        const std::uint64_t h = ooc::mix64(std::uint64_t{bits[0]} << 32 | bits[1]) & 0x7fffffffu;
        return h << 32 | vid;
    }
    // Per-face materials split a vertex the same way: the material's hash goes into the same bits, so a
    // material border is kept at every level like a UV seam.
    static std::uint64_t material_key(std::uint64_t key, float material) {
        const std::uint64_t h = ooc::mix64(static_cast<std::uint64_t>(material) + 0x9e3779b97f4a7c15ull) & 0x7fffffffu;
        return ((key >> 32 ^ h) & 0x7fffffffu) << 32 | (key & 0xffffffffu);
    }
    int octant(const std::byte* tri, const double mid[3]) const { return ooc::centroid_octant(tri, corner_, mid); }
    void cell_mid(std::uint32_t id, double mid[3]) const {
        const OctreeNode& d = nodes_[id];
        for (int a = 0; a < 3; ++a) mid[a] = static_cast<double>(d.cell_min[a]) + 0.5 * d.cell_size;
    }
    // For every triangle of a subtree held in memory (indexed as in `base`, whose ids are < count), its
    // octant at each level from node `id` down to max_depth, 3 bits per level: one read of each record
    // instead of one per level (plan's reads of scattered records were its cost). The cells are derived
    // with the float arithmetic of add_children and the midpoints as in cell_mid, so every choice is the
    // one `octant` makes at that node.
    std::vector<std::uint64_t> octant_paths(std::uint32_t id, const std::byte* base, const std::uint32_t* tris,
                                            std::size_t count, int depth) const {
        std::vector<std::uint64_t> paths(count, 0);
        const int levels = path_levels(count, depth);
        const OctreeNode& root = nodes_[id];
        auto compute = [&](std::size_t from, std::size_t to) {
            for (std::size_t i = from; i < to; ++i) {
                const std::byte* tri = base + std::size_t{tris[i]} * tri_bytes_;
                double c[3];
                ooc::centroid(tri, corner_, c);
                float cmin[3] = {root.cell_min[0], root.cell_min[1], root.cell_min[2]};
                float size = root.cell_size;
                std::uint64_t path = 0;
                for (int l = 0; l < levels; ++l) {
                    const float half = size * 0.5f;
                    unsigned o = 0;
                    for (int a = 0; a < 3; ++a) {  // branch-free: the side is a coin toss for the predictor
                        const bool upper = c[a] >= static_cast<double>(cmin[a]) + 0.5 * size;
                        cmin[a] = cmin[a] + (upper ? half : 0.f);
                        o |= static_cast<unsigned>(upper) << a;
                    }
                    size = half;
                    path |= std::uint64_t{o} << (3 * l);
                }
                paths[tris[i]] = path;
            }
        };
        // Independent per triangle: large subtrees take both threads.
        detail::parallel_for(count, p_.threads >= 2 ? 2u : 1u, 65536, compute);
        return paths;
    }

    // Levels octant_paths precomputes: a surface's triangles split about fourfold per level, so
    // log4(count / max_triangles) + 2 levels cover nearly every subtree; plan computes any deeper level
    // from the records. At most max_depth - depth ≤ 20 (60 bits).
    int path_levels(std::size_t count, int depth) const {
        const double ratio = static_cast<double>(count) / static_cast<double>(std::max<std::size_t>(p_.max_triangles, 1));
        const int expected = ratio > 1 ? static_cast<int>(std::ceil(std::log(ratio) / std::log(4.0))) + 2 : 1;
        return std::clamp(std::min(expected, p_.max_depth - depth), 0, 20);
    }

    // Appends the non-empty octants as contiguous children of `id`; returns child id per octant.
    std::array<std::uint32_t, 8> add_children(std::uint32_t id, const std::array<std::uint64_t, 8>& counts) {
        std::array<std::uint32_t, 8> ids{};
        ids.fill(~0u);
        const std::uint32_t first = static_cast<std::uint32_t>(nodes_.size());
        nodes_[id].first_child = first;
        for (int o = 0; o < 8; ++o) {
            if (!counts[o]) continue;
            nodes_[id].child_mask |= static_cast<std::uint8_t>(1u << o);
            OctreeNode c;
            const OctreeNode& d = nodes_[id];
            c.parent = id;
            c.depth = static_cast<std::uint8_t>(d.depth + 1);
            c.cell_size = d.cell_size * 0.5f;
            for (int a = 0; a < 3; ++a) c.cell_min[a] = d.cell_min[a] + ((o >> a) & 1 ? c.cell_size : 0.f);
            ids[o] = static_cast<std::uint32_t>(nodes_.size());
            nodes_.push_back(c);
        }
        return ids;
    }
    bool is_leaf(std::uint64_t count, int depth) const {
        return count <= p_.max_triangles || depth >= p_.max_depth;
    }

    // The subtree of `id` whose `count` triangles are all in `data`.
    NodeResult process_loaded(std::uint32_t id, const std::byte* data, std::size_t count, int depth) {
        std::vector<std::uint32_t> order(count);
        for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
        std::vector<std::uint32_t> scratch(order.size());
        return process_memory(id, data, order.data(), order.size(), scratch.data(), depth);
    }

    NodeResult process_file(std::uint32_t id, const TriangleFile& in, int depth) {
        if (is_leaf(in.count, depth) || in.count <= in_memory_limit_) {
            // One buffer for every subtree loaded (the subtree is finished before the next is read), grown
            // to the largest, never zero-filled: fresh pages for each would cost a fault and a clear each.
            const std::size_t bytes = static_cast<std::size_t>(in.count) * tri_bytes_;
            if (bytes > load_bytes_) {
                load_buffer_.reset();
                load_buffer_.reset(new std::byte[bytes]);
                load_bytes_ = bytes;
            }
            std::size_t at = 0;
            for (const TriangleRegion& r : in.regions) {
                ooc::File f(r.path, O_RDONLY);
                f.read_at(load_buffer_.get() + at, static_cast<std::size_t>(r.count) * tri_bytes_, r.offset);
                at += static_cast<std::size_t>(r.count) * tri_bytes_;
            }
            remove_owned(in);
            return process_loaded(id, load_buffer_.get(), static_cast<std::size_t>(in.count), depth);
        }
        // Split by streaming: one read of the node's triangles, eight buffered child files per thread.
        // With two threads, each takes one half of the node's triangles (in file order) and writes its
        // own eight files; child o is then the first thread's file o followed by the second's, which
        // is the order one thread writes, so the tree and the asset do not depend on the thread count.
        ++split_passes_;
        // The split's buffers take the loaded subtrees' share of the budget.
        load_buffer_.reset();
        load_bytes_ = 0;
        double mid[3];
        cell_mid(id, mid);
        const int workers = p_.threads >= 2 && in.count >= kTwoThreadSplit ? 2 : 1;
        // The same memory as one thread: buffers and chunk are shared out.
        const std::size_t buffer = std::clamp<std::size_t>(p_.memory_bytes / 32 / workers, 64 << 10, 8 << 20);
        const std::uint64_t chunk = std::max<std::uint64_t>(1, (p_.memory_bytes / 8 / workers) / tri_bytes_);
        struct Part {
            std::array<std::string, 8> paths;
            std::array<std::uint64_t, 8> counts{};
        };
        std::array<Part, 2> parts;
        std::atomic<bool> stop{false};
        // Worker w: triangles [first, last) of the node, in order, into its eight files.
        auto split_part = [&](int w, std::uint64_t first, std::uint64_t last) {
            std::array<std::unique_ptr<ooc::SequentialWriter>, 8> out;
            std::vector<std::byte> data;
            std::uint64_t region_first = 0;  // node index of the region's first triangle
            for (const TriangleRegion& r : in.regions) {
                const std::uint64_t lo = std::max(first, region_first), hi = std::min(last, region_first + r.count);
                if (lo < hi) {
                    ooc::File f(r.path, O_RDONLY);
                    for (std::uint64_t t0 = lo; t0 < hi;) {
                        if (w == 0) check_progress(progress_, fraction(), "octree: splitting");
                        else if (stop.load(std::memory_order_relaxed)) return;
                        const std::uint64_t n = std::min(chunk, hi - t0);
                        data.resize(static_cast<std::size_t>(n) * tri_bytes_);
                        f.read_at(data.data(), data.size(), r.offset + (t0 - region_first) * tri_bytes_);
                        for (std::size_t t = 0; t < n; ++t) {
                            const std::byte* tri = data.data() + t * tri_bytes_;
                            const int o = octant(tri, mid);
                            if (!out[o])
                                out[o] = std::make_unique<ooc::SequentialWriter>(
                                    (fs::path(scratch_) / ("node" + std::to_string(id) + "-" + std::to_string(o) +
                                                           (w ? "b" : ""))).string(), buffer);
                            out[o]->write(tri, tri_bytes_);
                            ++parts[w].counts[o];
                        }
                        t0 += n;
                    }
                }
                region_first += r.count;
            }
            for (int o = 0; o < 8; ++o)
                if (out[o]) {
                    parts[w].paths[o] = out[o]->path();
                    out[o]->close();
                }
        };
        // The helper never polls progress; an error on either side stops both and is rethrown here.
        const std::uint64_t half = workers == 2 ? in.count / 2 : in.count;
        ooc::run_workers(workers, stop, [&](int w) { split_part(w, w ? half : 0, w ? in.count : half); });
        remove_owned(in);
        std::array<TriangleFile, 8> octants;
        for (int o = 0; o < 8; ++o)
            for (const Part& part : parts)
                if (part.counts[o]) {
                    octants[o].regions.push_back({part.paths[o], 0, part.counts[o], true});
                    octants[o].count += part.counts[o];
                }
        return process_children(id, octants, depth);
    }
    // Node `id` split into its octants' triangle files: its children's subtrees, then itself.
    NodeResult process_children(std::uint32_t id, const std::array<TriangleFile, 8>& octants, int depth) {
        std::array<std::uint64_t, 8> counts{};
        for (int o = 0; o < 8; ++o) counts[o] = octants[o].count;
        const std::array<std::uint32_t, 8> ids = add_children(id, counts);
        std::vector<NodeResult> children;
        for (int o = 0; o < 8; ++o)
            if (counts[o]) children.push_back(process_file(ids[o], octants[o], depth + 1));
        return finish_inner(id, children);
    }
    static void remove_owned(const TriangleFile& in) {
        for (const TriangleRegion& r : in.regions)
            if (r.owned) remove_file(r.path);
    }

    // What computing one node yields besides its NodeResult: the encoded chunks to append to the asset
    // (raw leaf triangles, then the simplified mesh) and the counters, applied when it is committed.
    struct NodeOutput {
        std::vector<std::uint8_t> raw, mesh;
        std::uint64_t leaf_triangles = 0;  // raw triangles (leaves), for progress and oversized leaves
        std::uint64_t closed_components = 0, degenerate = 0;
        double simplify_seconds = 0;
    };

    // Appends a computed node's chunks to the asset (in the serial post-order, so the asset does not
    // depend on the thread count or the budget) and applies its counters.
    void commit(std::uint32_t id, NodeOutput& out) {
        OctreeNode& d = nodes_[id];
        if (!out.raw.empty()) {
            d.raw_offset = offset_;
            d.raw_bytes = out.raw.size();
            d.raw_crc = binary::checksum(out.raw.data(), out.raw.size());
            write(out.raw.data(), out.raw.size());
        }
        if (!out.mesh.empty()) {
            d.mesh_offset = offset_;
            d.mesh_bytes = out.mesh.size();
            d.mesh_crc = binary::checksum(out.mesh.data(), out.mesh.size());
            write(out.mesh.data(), out.mesh.size());
        }
        out.raw = {};
        out.mesh = {};
        if (out.leaf_triangles > p_.max_triangles) ++oversized_;
        done_triangles_ += out.leaf_triangles;
        closed_components_ += out.closed_components;
        degenerate_ += out.degenerate;
        simplify_seconds_ += out.simplify_seconds;
    }

    // One node of a subtree held in memory, in the serial post-order (children before parents).
    struct Task {
        std::uint32_t id = 0;
        const std::uint32_t* tris = nullptr;  // a leaf's triangles
        std::size_t count = 0;
        std::vector<std::size_t> children;    // task indices (inner nodes)
        std::size_t parent = ~std::size_t{0};
    };

    // Splits a subtree held in memory down to its leaves (counting sorts by octant), fixing every node id
    // in the same order as a serial depth-first build, before any node is simplified: representative
    // keys contain node ids, so the ids must not depend on which thread finishes first.
    // `paths[t]`: triangle t's octant at every level below the subtree's root, 3 bits each (octant_paths).
    std::size_t plan(std::vector<Task>& tasks, std::uint32_t id, const std::byte* base, const std::uint64_t* paths, int levels,
                     int level, std::uint32_t* tris, std::size_t count, std::uint32_t* scratch, int depth) {
        if (is_leaf(count, depth)) {
            Task t;
            t.id = id;
            t.tris = tris;
            t.count = count;
            tasks.push_back(std::move(t));
            return tasks.size() - 1;
        }
        std::array<std::uint64_t, 8> counts{};
        // The octant of every triangle, precomputed (paths) or, below the precomputed levels, from its record.
        std::vector<std::uint8_t> deep;
        auto octant_of = [&](std::size_t i) -> unsigned {
            return level < levels ? static_cast<unsigned>((paths[tris[i]] >> (3 * level)) & 7) : deep[i];
        };
        if (level >= levels) {
            double mid[3];
            cell_mid(id, mid);
            deep.resize(count);
            for (std::size_t i = 0; i < count; ++i)
                deep[i] = static_cast<std::uint8_t>(octant(base + std::size_t{tris[i]} * tri_bytes_, mid));
        }
        for (std::size_t i = 0; i < count; ++i) ++counts[octant_of(i)];
        // Counting sort of the triangle ids by octant (through scratch).
        std::array<std::size_t, 8> start{};
        for (int o = 1; o < 8; ++o) start[o] = start[o - 1] + counts[o - 1];
        {
            std::array<std::size_t, 8> fill = start;
            for (std::size_t i = 0; i < count; ++i) scratch[fill[octant_of(i)]++] = tris[i];
            std::copy(scratch, scratch + count, tris);
        }
        const std::array<std::uint32_t, 8> ids = add_children(id, counts);
        std::vector<std::size_t> children;
        for (int o = 0; o < 8; ++o)
            if (counts[o])
                children.push_back(plan(tasks, ids[o], base, paths, levels, level + 1, tris + start[o], counts[o],
                                        scratch + start[o], depth + 1));
        Task t;
        t.id = id;
        t.children = std::move(children);
        tasks.push_back(std::move(t));
        const std::size_t self = tasks.size() - 1;
        for (std::size_t c : tasks[self].children) tasks[c].parent = self;
        return self;
    }

    // Builds, simplifies and writes a subtree held in memory. Its nodes are computed by two threads
    // (leaves are independent, an inner node waits for its children), always the lowest ready task
    // first, so finished nodes rarely wait long to be committed; the main thread commits in the serial
    // post-order and alone reports progress, polls cancel and writes.
    NodeResult process_memory(std::uint32_t id, const std::byte* base, std::uint32_t* tris, std::size_t count,
                              std::uint32_t* scratch, int depth) {
        std::vector<Task> tasks;
        {
            const bool leaf = is_leaf(count, depth);
            const std::vector<std::uint64_t> paths = leaf ? std::vector<std::uint64_t>() : octant_paths(id, base, tris, count, depth);
            plan(tasks, id, base, paths.data(), leaf ? 0 : path_levels(count, depth), 0, tris, count, scratch, depth);
        }
        // The node operator needs the input's border and odd edges; their sort overlapped the work so far.
        soup_.wait_edges();
        const std::size_t n = tasks.size();
        std::vector<std::optional<NodeResult>> results(n);
        std::vector<NodeOutput> outputs(n);
        auto compute = [&](std::size_t i) {
            Task& t = tasks[i];
            if (t.children.empty()) {
                results[i] = compute_leaf(t.id, base, t.tris, t.count, outputs[i]);
            } else {
                std::vector<NodeResult> kids;
                kids.reserve(t.children.size());
                for (std::size_t c : t.children) {
                    kids.push_back(std::move(*results[c]));
                    results[c].reset();
                }
                results[i] = compute_inner(t.id, kids, outputs[i]);
            }
        };
        if (n == 1 || p_.threads <= 1) {
            for (std::size_t i = 0; i < n; ++i) {
                check_progress(progress_, fraction(), "octree: simplifying");
                compute(i);
                commit(tasks[i].id, outputs[i]);
            }
        } else {
            std::mutex mutex;
            std::condition_variable changed;
            std::set<std::size_t> ready;
            std::vector<std::size_t> waiting(n, 0);
            std::vector<std::uint8_t> done(n, 0);
            for (std::size_t i = 0; i < n; ++i) {
                waiting[i] = tasks[i].children.size();
                if (!waiting[i]) ready.insert(i);
            }
            bool stop = false;
            std::exception_ptr helper_error;
            // Takes the lowest ready task, or returns n when none is ready (main) or all are taken (helper).
            auto take = [&](std::unique_lock<std::mutex>& lock, bool main) {
                for (;;) {
                    if (stop) return n;
                    if (!ready.empty()) {
                        const std::size_t i = *ready.begin();
                        ready.erase(ready.begin());
                        return i;
                    }
                    if (main) return n;
                    changed.wait(lock);
                }
            };
            auto finish = [&](std::size_t i) {
                std::lock_guard lock(mutex);
                done[i] = 1;
                const std::size_t parent = tasks[i].parent;
                if (parent != ~std::size_t{0} && --waiting[parent] == 0) ready.insert(parent);
                changed.notify_all();
            };
            std::thread helper([&] {
                try {
                    for (;;) {
                        std::size_t i;
                        {
                            std::unique_lock lock(mutex);
                            i = take(lock, false);
                        }
                        if (i == n) return;
                        compute(i);
                        finish(i);
                    }
                } catch (...) {
                    std::lock_guard lock(mutex);
                    helper_error = std::current_exception();
                    stop = true;
                    changed.notify_all();
                }
            });
            auto halt = [&] {
                {
                    std::lock_guard lock(mutex);
                    stop = true;
                }
                changed.notify_all();
                helper.join();
            };
            try {
                for (std::size_t next = 0; next < n;) {
                    check_progress(progress_, fraction(), "octree: simplifying");
                    std::size_t i = n;
                    {
                        std::unique_lock lock(mutex);
                        if (helper_error) std::rethrow_exception(helper_error);
                        if (done[next]) {
                            lock.unlock();
                            commit(tasks[next].id, outputs[next]);
                            ++next;
                            continue;
                        }
                        i = take(lock, true);
                        if (i == n) {
                            changed.wait(lock, [&] { return done[next] || !ready.empty() || helper_error; });
                            continue;
                        }
                    }
                    compute(i);
                    finish(i);
                }
            } catch (...) {
                halt();
                throw;
            }
            halt();
        }
        return std::move(*results[n - 1]);
    }

    NodeResult compute_leaf(std::uint32_t id, const std::byte* base, const std::uint32_t* tris, std::size_t count,
                            NodeOutput& out) {
        const std::size_t f = layout_.floats();
        NodeResult r(frame_.attribute_dimension());
        NodeMesh raw;
        raw.layout = layout_;
        raw.indices.reserve(3 * count);
        raw.keys.reserve(count);
        raw.vertices.reserve(count * f);
        ooc::FlatMap map(count);
        for (std::size_t i = 0; i < count; ++i) {
            const std::byte* tri = base + std::size_t{tris[i]} * tri_bytes_;
            const float* v[3];
            for (int k = 0; k < 3; ++k) {
                const std::byte* c = tri + static_cast<std::size_t>(k) * corner_;
                std::uint32_t vid;
                std::memcpy(&vid, c, 4);
                v[k] = reinterpret_cast<const float*>(c + 4);
                std::uint64_t key = wedge_ ? wedge_key(vid, v[k] + uv_at_) : vid;
                if (layout_.material) key = material_key(key, v[k][layout_.material_offset()]);
                bool inserted = false;
                std::uint32_t& local = map.find_or_insert(key, static_cast<std::uint32_t>(raw.keys.size()), inserted);
                if (inserted) {
                    raw.keys.push_back(key);
                    raw.vertices.insert(raw.vertices.end(), v[k], v[k] + f);
                    r.bounds.add({v[k][0], v[k][1], v[k][2]});
                }
                raw.indices.push_back(local);
            }
            r.quadric.add_triangle(frame_, v[0], v[1], v[2]);
        }
        r.triangles = count;
        nodes_[id].raw_triangles = static_cast<std::uint32_t>(count);
        if (count) out.raw = encode_node_mesh(raw);
        out.leaf_triangles = count;
        simplify_into(id, raw, r, out);
        return r;
    }

    NodeResult compute_inner(std::uint32_t id, std::vector<NodeResult>& children, NodeOutput& out) {
        NodeResult r(frame_.attribute_dimension());
        std::vector<const NodeMesh*> parts;
        for (NodeResult& c : children) {
            r.quadric.add(c.quadric);
            r.error = std::max(r.error, c.error);
            r.height = std::max(r.height, c.height + 1);
            if (!c.bounds.empty()) {
                r.bounds.add(c.bounds.min);
                r.bounds.add(c.bounds.max);
            }
            r.triangles += c.triangles;
            parts.push_back(&c.mesh);
        }
        NodeMesh merged = merge_node_meshes(parts);
        for (NodeResult& c : children) {
            c.mesh = NodeMesh();  // the parent's input is the merged copy
            r.chords.insert(r.chords.end(), c.chords.begin(), c.chords.end());
            c.chords = {};
        }
        std::sort(r.chords.begin(), r.chords.end());
        r.chords.erase(std::unique(r.chords.begin(), r.chords.end()), r.chords.end());
        simplify_into(id, merged, r, out);
        return r;
    }

    NodeResult finish_inner(std::uint32_t id, std::vector<NodeResult>& children) {
        check_progress(progress_, fraction(), "octree: simplifying");
        NodeOutput out;
        NodeResult r = compute_inner(id, children, out);
        commit(id, out);
        return r;
    }

    // Runs the operator and fills the node's table entry (except the chunk offsets, set by commit).
    // Touches only nodes_[id] and `out`, so different nodes may run on different threads.
    void simplify_into(std::uint32_t id, const NodeMesh& input, NodeResult& r, NodeOutput& out) {
        NodeSimplifyStats st;
        OctreeNode& d = nodes_[id];
        const Clock::time_point t0 = Clock::now();
        NodeBorderEdges border;
        border.input = &soup_.border_edges;
        border.chords = &r.chords;
        border.keep_ratio = p_.level_ratio;
        border.alone = id == 0;
        border.alone_triangles = p_.coarsest_triangles;
        r.mesh = simplify_node(input, r.quadric, frame_, d.cell_min, d.cell_size, kRepresentativeKey | id,
                               &soup_.odd_non_manifold_edges, &st, &border);
        if (!st.chords.empty()) {
            std::vector<std::pair<std::uint64_t, std::uint64_t>> all;
            all.reserve(r.chords.size() + st.chords.size());
            std::merge(r.chords.begin(), r.chords.end(), st.chords.begin(), st.chords.end(), std::back_inserter(all));
            all.erase(std::unique(all.begin(), all.end()), all.end());
            r.chords.swap(all);
        }
        out.simplify_seconds += seconds_since(t0);
        out.closed_components += st.closed_components;
        if (d.is_leaf()) out.degenerate += st.degenerate_dropped;
        r.error = std::max(r.error, static_cast<float>(st.error));
        if (r.mesh.triangle_count()) out.mesh = encode_node_mesh(r.mesh);
        d.mesh_triangles = static_cast<std::uint32_t>(r.mesh.triangle_count());
        d.height = static_cast<std::uint8_t>(r.height);
        d.error = r.error;
        d.subtree_triangles = r.triangles;
        d.flags = st.closed_components ? 1 : 0;
        if (!r.bounds.empty()) {
            d.bounds_min[0] = r.bounds.min.x;
            d.bounds_min[1] = r.bounds.min.y;
            d.bounds_min[2] = r.bounds.min.z;
            d.bounds_max[0] = r.bounds.max.x;
            d.bounds_max[1] = r.bounds.max.y;
            d.bounds_max[2] = r.bounds.max.z;
        }
    }

    double fraction() const {
        return soup_.triangles ? static_cast<double>(done_triangles_) / static_cast<double>(soup_.triangles) : 0.0;
    }
    static void remove_file(const std::string& path) {
        std::error_code ignored;
        fs::remove(path, ignored);
    }

    const OctreeBuildParams& p_;
    SoupResult& soup_;
    std::string scratch_;
    AtomicFile& asset_;
    Progress* progress_;
    VertexLayout layout_;
    std::size_t corner_, tri_bytes_;
    float root_min_[3] = {0, 0, 0};
    float root_size_ = 1;
    QuadricFrame frame_;
    bool wedge_ = false;
    std::size_t uv_at_ = 0;
    std::uint64_t in_memory_limit_ = 0;
    std::unique_ptr<std::byte[]> load_buffer_;  // the subtree held in memory (process_file)
    std::size_t load_bytes_ = 0;
    std::vector<OctreeNode> nodes_;
    std::uint64_t offset_ = 0;
    std::uint64_t done_triangles_ = 0;
    std::uint64_t split_passes_ = 0, closed_components_ = 0, degenerate_ = 0;
    std::size_t oversized_ = 0;
    double simplify_seconds_ = 0;
};

}  // namespace

namespace {

OctreeBuildResult build_octree_with_scratch(const std::string& input_ply, const std::string& asset_path,
                                            const OctreeBuildParams& params, Progress* progress,
                                            OctreeBuildStats* stats) {
    if (params.max_triangles < 1) throw Error(Error::Kind::argument, "octree: max triangles per leaf must be at least 1");
    if (params.max_depth < 0 || params.max_depth > 20)
        throw Error(Error::Kind::argument, "octree: max depth must be in [0, 20], got " + std::to_string(params.max_depth));
    if (params.memory_bytes < (std::size_t{4} << 20)) throw Error(Error::Kind::argument, "octree: the memory budget must be at least 4 MB");
    if (params.threads < 1 || params.threads > 2) throw Error(Error::Kind::argument, "octree: threads must be 1 or 2");
    if (params.level_ratio != 0 && !(params.level_ratio >= 0.05 && params.level_ratio <= 0.95))
        throw Error(Error::Kind::argument, "octree: the level ratio must be 0 or in [0.05, 0.95], got " +
                                               std::to_string(params.level_ratio));
    OctreeBuildResult result;
    OctreeBuildStats local_stats;
    OctreeBuildStats& times = stats ? *stats : local_stats;
    times = {};
    {
        AtomicFile asset(asset_path);
        TempDirectory scratch(params.temp_dir.empty() ? TempDirectory::beside(asset_path) : params.temp_dir);
        const Clock::time_point t0 = Clock::now();
        SoupParams sp;
        sp.memory_bytes = params.memory_bytes;
        sp.threads = params.threads;
        sp.background_edges = true;
        // A soup the builder would read whole into memory anyway stays there (no write, no read back):
        // 30 % of the budget in records is within the builder's in-memory share, 40 % of the budget
        // at record + 16 bytes per triangle, for every record size (≥ 48 bytes).
        sp.memory_soup_bytes = static_cast<std::size_t>(0.3 * static_cast<double>(params.memory_bytes));
        // An external soup whose root the builder would split by streaming is written straight into the
        // root's octant files (one write and two reads of the whole soup fewer).
        sp.root_split = [&params](const Bounds& bounds, std::uint64_t triangles, const VertexLayout& layout) {
            SoupRootSplit split;
            if (triangles <= params.max_triangles || params.max_depth <= 0 ||
                triangles <= in_memory_limit(params.memory_bytes, layout))
                return split;
            float min[3], size;
            root_cube(bounds, min, size);
            split.split = true;
            for (int a = 0; a < 3; ++a) split.mid[a] = static_cast<double>(min[a]) + 0.5 * size;
            return split;
        };
        result.soup = convert_to_soup(input_ply, scratch.file("soup"), sp, progress);
        // A background edge sort ends before the temporary directory goes, whatever happens.
        struct EndEdgeJob {
            SoupResult& soup;
            ~EndEdgeJob() { soup.edge_job.reset(); }
        } end_edge_job{result.soup};
        check_extent(input_ply, result.soup.bounds);
        times.soup_seconds = seconds_since(t0);
        const Clock::time_point t1 = Clock::now();
        Builder b(params, result.soup, scratch.path(), asset, progress);
        b.run(result);
        times.simplify_seconds = b.simplify_seconds();
        result.soup.wait_edges();
        std::vector<std::byte>().swap(result.soup.memory);
        check_progress(progress, 1.0, "octree: simplifying");
        asset.commit();
        times.build_seconds = seconds_since(t1);
    }
    OctreeStore store(asset_path, 0);
    result.stats = store.stats();
    if (result.oversized_leaves)
        result.warnings.push_back(std::to_string(result.oversized_leaves) +
                                  " leaf node(s) at the maximum depth hold more than max-triangles");
    return result;
}

}  // namespace

OctreeBuildResult build_octree(const std::string& input_ply, const std::string& asset_path,
                               const OctreeBuildParams& params, Progress* progress, OctreeBuildStats* stats) {
    try {
        return build_octree_with_scratch(input_ply, asset_path, params, progress, stats);
    } catch (const Error& e) {
        throw without_temporary_names(e, asset_path);
    }
}

}  // namespace lodforge
