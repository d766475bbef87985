// Indexed PLY → triangle soup within a memory budget.
//
// Follows the data-processing stage of Bade, Daman, Sunar, Tan, "Out-of-Core Simplification with
// Appearance Preservation for Computer Game Applications" (Universiti Teknologi Malaysia report,
// 2006, §3.3 and §4.2):
// dereference every triangle's corner indices against the vertex file by external sorting, so each
// soup triangle carries its vertices' full records (Lindstrom, "Out-of-Core Simplification of Large
// Polygonal Models", SIGGRAPH 2000, and Chiang/Silva's external-memory dereferencing). The document
// sorts three times, once per corner k. Here the sort keys are dense integers whose range is known
// from the header (vertex index in [0, V), corner index in [0, 3T)), so each sort is a single
// distribution pass into buckets sized to fit the budget, with direct placement inside a bucket:
//   pass 1  read the PLY: vertex records → vertex file, corner refs (vertex, corner) → bucket of its
//           vertex range;
//   pass 2  per vertex range: load the range, dereference its refs → bucket of the corner's range;
//   pass 3  per corner range: place every corner at its slot, write the completed triangles.
// Every byte is written to temporary files twice and read twice, whatever the input size (a merge sort
// needs log_k passes per sort, three sorts in the document). When the vertex table fits in half the
// budget, pass 1 alone does it (vertices kept in memory, faces dereferenced as they stream by).
#include "lodforge/octree/ooc_soup.h"

#include "lodforge/error.h"
#include "lodforge/io/atomic_file.h"
#include "lodforge/io/mesh_validate.h"
#include "lodforge/io/ply.h"

#include "io/ply_ascii_split.h"
#include "octree/ooc_internal.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <span>
#include <string_view>
#include <thread>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <limits>
#include <memory>
#include <system_error>

namespace lodforge {
namespace fs = std::filesystem;
using ooc::File;
using ooc::SequentialWriter;
using ply_detail::AsciiSegment;
using ply_detail::parse_ascii_in_two;
using ply_detail::Unit;

namespace {

constexpr char kSoupMagic[8] = {'L', 'F', 'S', 'O', 'U', 'P', '0', '1'};
constexpr std::uint32_t kSoupVersion = 1;
constexpr std::size_t kSoupHeaderBytes = 64;
constexpr std::uint32_t kWedgeFlag = 8;  // texcoords are per face corner (wedges), docs/octree.md

struct SoupHeader {
    char magic[8];
    std::uint32_t version;
    std::uint32_t layout;
    std::uint64_t triangles;
    std::uint64_t vertices;
    float bounds[6];
    std::uint8_t pad[8];
};
static_assert(sizeof(SoupHeader) == kSoupHeaderBytes);

// Fixed-size records distributed into buckets; each bucket is a list of blocks in one spill file, so
// hundreds of buckets cost hundreds of small buffers, not hundreds of open files.
class BucketSpill {
public:
    BucketSpill(const std::string& path, std::size_t buckets, std::size_t record_bytes, std::size_t buffer_bytes)
        : file_(path, O_RDWR | O_CREAT | O_TRUNC), record_(record_bytes),
          capacity_(std::max<std::size_t>(1, buffer_bytes / record_bytes) * record_bytes), buffers_(buckets),
          used_(buckets, 0), blocks_(buckets) {}
    ~BucketSpill() {
        file_.close();
        std::error_code ignored;
        fs::remove(file_.path(), ignored);
    }
    // Bytes: the record size when known at compile time (a copy of a known size is a move or two, not
    // a call: the edge keys and corner references go through here tens of millions of times).
    template <std::size_t Bytes = 0>
    void add(std::size_t bucket, const void* record) {
        std::vector<char>& b = buffers_[bucket];
        if (b.empty()) b.resize(capacity_);
        std::size_t& used = used_[bucket];
        std::memcpy(b.data() + used, record, Bytes ? Bytes : record_);
        used += record_;
        if (used >= capacity_) spill(bucket);
    }
    void finish() {
        for (std::size_t i = 0; i < buffers_.size(); ++i) {
            spill(i);
            std::vector<char>().swap(buffers_[i]);
        }
    }
    std::uint64_t bytes() const { return end_; }
    // Calls f(data, bytes) for each block of the bucket, in order; `tmp` is the read buffer.
    template <class F>
    void for_each_block(std::size_t bucket, std::vector<char>& tmp, F&& f) const {
        for (const auto& [offset, length] : blocks_[bucket]) {
            tmp.resize(length);
            file_.read_at(tmp.data(), length, offset);
            f(tmp.data(), length);
        }
    }

private:
    void spill(std::size_t bucket) {
        std::size_t& used = used_[bucket];
        if (used == 0) return;
        file_.write_at(buffers_[bucket].data(), used, end_);
        blocks_[bucket].emplace_back(end_, used);
        end_ += used;
        used = 0;
    }
    File file_;
    std::size_t record_;
    std::size_t capacity_;
    std::vector<std::vector<char>> buffers_;
    std::vector<std::size_t> used_;
    std::vector<std::vector<std::pair<std::uint64_t, std::size_t>>> blocks_;
    std::uint64_t end_ = 0;
};

// Reads the vertex element in chunks and hands out packed records (layout.floats() floats each).
class VertexChunks {
public:
    VertexChunks(const VertexLayout& layout, std::size_t chunk) : layout_(layout), p_(chunk) {
        if (layout.normals) n_.resize(chunk);
        if (layout.colors) c_.resize(chunk);
        if (layout.texcoords) t_.resize(chunk);
        packed_.resize(chunk * layout.floats());
    }
    // Reads the next chunk; returns the count (records in packed()).
    std::size_t next(PlyReader& reader, std::size_t max = std::numeric_limits<std::size_t>::max()) {
        const std::uint64_t first = reader.vertex_count() - reader.remaining();
        const std::size_t n = reader.read_vertices(std::span(p_).first(std::min(max, p_.size())), n_, c_, t_);
        // The checks read_mesh's validation makes, so a file `info` and `convert` refuse is refused here too.
        auto part = [n](const auto& v) {
            using T = typename std::decay_t<decltype(v)>::value_type;
            return v.empty() ? std::span<const T>{} : std::span<const T>(v).first(n);
        };
        check_vertex_chunk(reader.path(), static_cast<std::size_t>(first), part(p_), part(n_), part(c_), part(t_));
        const std::size_t f = layout_.floats();
        for (std::size_t i = 0; i < n; ++i) {
            float* r = &packed_[i * f];
            r[0] = p_[i].x;
            r[1] = p_[i].y;
            r[2] = p_[i].z;
            std::size_t j = 3;
            if (layout_.normals) {
                r[j] = n_[i].x;
                r[j + 1] = n_[i].y;
                r[j + 2] = n_[i].z;
                j += 3;
            }
            if (layout_.colors) {
                r[j] = c_[i].x;
                r[j + 1] = c_[i].y;
                r[j + 2] = c_[i].z;
                r[j + 3] = c_[i].w;
                j += 4;
            }
            if (layout_.texcoords) {
                r[j] = t_[i].x;
                r[j + 1] = t_[i].y;
            }
        }
        return n;
    }
    const float* packed() const { return packed_.data(); }

private:
    VertexLayout layout_;
    std::vector<Vec3f> p_, n_;
    std::vector<Vec4f> c_;
    std::vector<Vec2f> t_;
    std::vector<float> packed_;
};

// Finds the input's odd non-manifold edges (used by 3, 5, ... non-degenerate triangles; the only edges
// whose uses the node operator cannot drop in cancelling pairs, docs/octree.md) within the budget:
// edge keys are distributed by hash into buckets that fit in memory twice over, and each bucket is
// radix-sorted and its runs counted (sequential memory traffic; a hash table of tens of millions of
// edges is all cache misses). Only the (usually tiny) result stays resident.
class EdgeCounter {
public:
    EdgeCounter(const std::string& path, std::uint64_t vertices, std::uint64_t expected_edges, std::size_t budget, bool enabled)
        : enabled_(enabled), shift_(std::max<int>(1, static_cast<int>(std::bit_width(vertices)))),
          // When every key fits in 15 % of the budget they stay in memory, in buckets by their top bits
          // (up to 512: a bucket of the dragon is ~40 KB, so its radix sort runs in the cache and needs 9
          // bits fewer, one pass fewer; a hash spread hundreds of MB over two buckets sorted out of cache).
          in_memory_(expected_edges * 8 <= static_cast<std::uint64_t>(0.15 * budget)),
          top_bits_(in_memory_ ? std::min(9, 2 * shift_) : 0),
          buckets_(in_memory_ ? std::size_t{1} << top_bits_ : static_cast<std::size_t>(std::max<std::uint64_t>(
              2, (expected_edges * 16 + static_cast<std::uint64_t>(0.15 * budget) - 1) / static_cast<std::uint64_t>(0.15 * budget)))) {
        if (!enabled_) return;
        if (in_memory_) {
            resident_.resize(buckets_);
            const std::uint64_t each = expected_edges / buckets_;
            for (auto& b : resident_) b.reserve(static_cast<std::size_t>(each + each / 4 + 16));
        } else {
            spill_.emplace(path, buckets_, 8,
                           std::clamp<std::size_t>(static_cast<std::size_t>(0.1 * budget) / buckets_, 4096, std::size_t{1} << 20));
        }
    }
    void add_triangle(const std::uint32_t* v) {
        if (!enabled_ || v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) return;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = v[k], b = v[(k + 1) % 3];
            // Packed to 2 × bit_width(V) bits so the radix sort needs as few passes as possible.
            const std::uint64_t key = a < b ? (std::uint64_t{a} << shift_ | b) : (std::uint64_t{b} << shift_ | a);
            if (in_memory_) resident_[static_cast<std::size_t>(key >> (2 * shift_ - top_bits_))].push_back(key);
            // Bucket by the hash's top 32 bits scaled to the bucket count (a multiply, not a division);
            // which bucket a key lands in does not change the sorted result.
            else spill_->add<8>(static_cast<std::size_t>((ooc::mix64(key) >> 32) * buckets_ >> 32), &key);
        }
    }
    // The odd non-manifold edges; `border` receives the edges used exactly once. Both sorted.
    std::vector<std::uint64_t> odd_non_manifold(Progress* progress, double from, double to, std::vector<std::uint64_t>& border) {
        std::vector<std::uint64_t> out;
        border.clear();
        if (!enabled_) return out;
        if (spill_) spill_->finish();
        // Two threads take alternate buckets (each bucket with its sort buffer fits in 15 % of the
        // budget, so both together stay within the 30 % the single-threaded version used).
        struct Part {
            std::vector<std::uint64_t> odd, border;
        } parts[2];
        std::atomic<bool> stop{false};
        auto work = [&](int t) {
            std::vector<std::uint64_t> keys, tmp_keys;
            std::vector<char> tmp;
            for (std::size_t b = static_cast<std::size_t>(t); b < buckets_ && !stop; b += 2) {
                if (t == 0) check_progress(progress, from + (to - from) * static_cast<double>(b) / buckets_, "soup: counting edges");
                keys.clear();
                if (in_memory_) {
                    keys.swap(resident_[b]);
                } else {
                    spill_->for_each_block(b, tmp, [&](const char* data, std::size_t bytes) {
                        const std::size_t at = keys.size();
                        keys.resize(at + bytes / 8);
                        std::memcpy(&keys[at], data, bytes);
                    });
                }
                radix_sort(keys, tmp_keys, 2 * shift_ - top_bits_);  // a resident bucket shares its top bits
                for (std::size_t i = 0; i < keys.size();) {
                    std::size_t j = i + 1;
                    while (j < keys.size() && keys[j] == keys[i]) ++j;
                    const std::size_t c = j - i;
                    const std::uint64_t edge = (keys[i] >> shift_) << 32 | (keys[i] & ((std::uint64_t{1} << shift_) - 1));
                    if (c == 1) parts[t].border.push_back(edge);
                    else if (c >= 3 && (c & 1u)) parts[t].odd.push_back(edge);
                    i = j;
                }
            }
        };
        ooc::run_workers(2, stop, work);
        for (Part& p : parts) {
            out.insert(out.end(), p.odd.begin(), p.odd.end());
            border.insert(border.end(), p.border.begin(), p.border.end());
        }
        std::sort(out.begin(), out.end());
        std::sort(border.begin(), border.end());
        return out;
    }

private:
    // Radix sort. Digits of at most 11 bits: 2 048 counters and write streams stay in the L1 cache and
    // the store buffers, where 16-bit digits (65 536 scattered write streams) miss on nearly every store.
    // `bits`: the keys' width (2 × bit_width(V), known up front: no pass to find the largest key). More
    // keys than the L2 cache holds are first split by their top bits (one pass, up to 10 bits), and each
    // part, a few thousand keys, is then sorted by the rest in the cache: one pass over memory instead of
    // every digit's pass missing the cache.
    static void radix_sort(std::vector<std::uint64_t>& a, std::vector<std::uint64_t>& tmp, int bits) {
        if (bits <= 0 || a.size() < 2) return;
        tmp.resize(a.size());
        constexpr std::size_t kInCache = std::size_t{1} << 15;  // keys (256 KB)
        // Parts of about 4 096 keys: smaller ones would pay more for their digits' counters (up to
        // 4 × 2 048, cleared and summed per part) than for their keys (the 16 MB budget's buckets of
        // 150 K keys split 1 024 ways gave parts of 150 keys and spent most of the sort on counters).
        const int top = std::clamp(static_cast<int>(std::bit_width(a.size())) - 12, 1, 10);
        if (a.size() <= kInCache || bits <= 2 * top) {
            if (lsd_sort(a.data(), tmp.data(), a.size(), bits) != a.data()) a.swap(tmp);
            return;
        }
        const int low = bits - top;
        std::vector<std::size_t> start((std::size_t{1} << top) + 1, 0);
        for (std::uint64_t k : a) ++start[(k >> low) + 1];
        for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
        {
            std::vector<std::size_t> fill(start.begin(), start.end() - 1);
            for (std::uint64_t k : a) tmp[fill[k >> low]++] = k;
        }
        for (std::size_t d = 0; d + 1 < start.size(); ++d) {
            const std::size_t n = start[d + 1] - start[d];
            std::uint64_t* part = tmp.data() + start[d];
            const std::uint64_t* sorted = lsd_sort(part, a.data() + start[d], n, low);
            if (sorted != part) std::memcpy(part, sorted, n * 8);
        }
        a.swap(tmp);
    }
    // LSD passes over the low `bits` bits of a[0, n), buffer b; returns a or b, whichever holds the result.
    static std::uint64_t* lsd_sort(std::uint64_t* a, std::uint64_t* b, std::size_t n, int bits) {
        if (bits <= 0 || n < 2) return a;
        const int passes = (bits + 10) / 11;
        const int digit = (bits + passes - 1) / passes;
        const std::uint64_t mask = (std::uint64_t{1} << digit) - 1;
        // Every digit's histogram in one read of the keys.
        const std::size_t radix = std::size_t{1} << digit;
        std::vector<std::size_t> counts(static_cast<std::size_t>(passes) * radix, 0);
        for (std::size_t i = 0; i < n; ++i)
            for (int p = 0; p < passes; ++p) ++counts[static_cast<std::size_t>(p) * radix + ((a[i] >> (p * digit)) & mask)];
        for (int p = 0, shift = 0; p < passes; ++p, shift += digit) {
            const std::span<std::size_t> count(counts.data() + static_cast<std::size_t>(p) * radix, radix);
            std::size_t sum = 0;
            for (std::size_t& c : count) {
                const std::size_t k = c;
                c = sum;
                sum += k;
            }
            for (std::size_t i = 0; i < n; ++i) b[count[(a[i] >> shift) & mask]++] = a[i];
            std::swap(a, b);
        }
        return a;
    }
    bool enabled_;
    int shift_;
    bool in_memory_;
    int top_bits_;  // resident buckets: the keys' top bits that pick the bucket
    std::size_t buckets_;
    std::vector<std::vector<std::uint64_t>> resident_;  // in memory: the keys of each bucket
    std::optional<BucketSpill> spill_;                  // otherwise: spilled to disk
};

// Runs an EdgeCounter on a second thread, fed the face chunks in file order (so the spill, and
// everything after it, is the same as single-threaded), at most two chunks queued. The counter's
// radix keys cost about as much as parsing, so overlapping the two is the cheapest use of a second core.
class EdgeWorker {
public:
    EdgeWorker(EdgeCounter& counter, bool enabled) : counter_(counter), enabled_(enabled) {
        if (enabled_) thread_ = std::thread([this] { run(); });
    }
    ~EdgeWorker() { stop(); }
    EdgeWorker(const EdgeWorker&) = delete;
    EdgeWorker& operator=(const EdgeWorker&) = delete;

    void push(const std::vector<std::uint32_t>& indices) {
        if (!enabled_) return;
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [&] { return queue_.size() < 2 || error_; });
        if (error_) std::rethrow_exception(error_);
        queue_.push_back(indices);
        changed_.notify_all();
    }
    // Waits for the queue to drain; rethrows what the counter threw.
    void finish() {
        stop();
        if (error_) std::rethrow_exception(error_);
    }

private:
    void stop() {
        if (!thread_.joinable()) return;
        {
            std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        changed_.notify_all();
        thread_.join();
    }
    void run() {
        for (;;) {
            std::vector<std::uint32_t> chunk;
            {
                std::unique_lock lock(mutex_);
                changed_.wait(lock, [&] { return !queue_.empty() || stopping_; });
                if (queue_.empty()) return;
                chunk = std::move(queue_.front());
                queue_.pop_front();
            }
            changed_.notify_all();
            try {
                for (std::size_t t = 0; t + 2 < chunk.size(); t += 3) counter_.add_triangle(&chunk[t]);
            } catch (...) {
                std::lock_guard lock(mutex_);
                error_ = std::current_exception();
                queue_.clear();
                changed_.notify_all();
                return;
            }
        }
    }
    EdgeCounter& counter_;
    bool enabled_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<std::vector<std::uint32_t>> queue_;
    bool stopping_ = false;
    std::exception_ptr error_;
    std::thread thread_;
};

void write_header(File& f, const SoupResult& r) {
    SoupHeader h{};
    std::memcpy(h.magic, kSoupMagic, 8);
    h.version = kSoupVersion;
    h.layout = r.layout.flags() | (r.wedge_texcoords ? kWedgeFlag : 0u);
    h.triangles = r.triangles;
    h.vertices = r.vertices;
    const float b[6] = {r.bounds.min.x, r.bounds.min.y, r.bounds.min.z, r.bounds.max.x, r.bounds.max.y, r.bounds.max.z};
    std::memcpy(h.bounds, b, sizeof b);
    f.write_at(&h, sizeof h, 0);
}

// Writes the soup file; or, given `memory_cap`, keeps the records in memory while they fit in it (the
// octree then takes them without a write and a read of the file) and falls back to the file, written
// from the start, the moment they do not.
class SoupWriter {
public:
    SoupWriter(const std::string& path, const VertexLayout& layout, std::size_t memory_cap = 0)
        : path_(path), corner_(soup_corner_bytes(layout)), cap_(memory_cap) {
        if (cap_ == 0) open();
    }
    // Appends a corner: vertex id + its record; bounds grow by its position.
    void corner(std::uint32_t id, const float* record) {
        if (!out_ && memory_.size() + corner_ > cap_) spill();
        if (out_) {
            out_->write(&id, 4);
            out_->write(record, corner_ - 4);
        } else {
            const std::size_t at = memory_.size();
            memory_.resize(at + corner_);
            std::memcpy(memory_.data() + at, &id, 4);
            std::memcpy(memory_.data() + at + 4, record, corner_ - 4);
        }
        grow(record);
    }
    void raw(const char* corners, std::size_t bytes) {
        if (!out_) spill();
        out_->write(corners, bytes);
        for (std::size_t o = 0; o < bytes; o += corner_) {
            float p[3];
            std::memcpy(p, corners + o + 4, sizeof p);
            grow(p);
        }
    }
    void finish(SoupResult& r) {
        r.bounds = Bounds{};
        if (lo_[0] <= hi_[0]) {
            r.bounds.add({lo_[0], lo_[1], lo_[2]});
            r.bounds.add({hi_[0], hi_[1], hi_[2]});
        }
        if (!out_) {
            r.memory = std::move(memory_);
            r.kept_in_memory = true;
            return;
        }
        out_->close();
        File f(r.path, O_WRONLY);
        write_header(f, r);
    }
    std::uint64_t bytes() const { return out_ ? out_->offset() : memory_.size(); }
    void reserve(std::uint64_t bytes) {
        if (!out_) memory_.reserve(static_cast<std::size_t>(bytes));
    }

private:
    void open() {
        out_.emplace(path_, 1 << 20);
        const char zero[kSoupHeaderBytes] = {};
        out_->write(zero, sizeof zero);
    }
    void spill() {
        open();
        out_->write(memory_.data(), memory_.size());
        std::vector<std::byte>().swap(memory_);
    }

private:
    // Positions are finite (the reader refuses NaN), so plain min/max suffice.
    void grow(const float* p) {
        for (int a = 0; a < 3; ++a) {
            lo_[a] = std::min(lo_[a], p[a]);
            hi_[a] = std::max(hi_[a], p[a]);
        }
    }
    std::string path_;
    std::optional<SequentialWriter> out_;
    std::vector<std::byte> memory_;
    std::size_t corner_;
    std::size_t cap_;
    float lo_[3] = {INFINITY, INFINITY, INFINITY};
    float hi_[3] = {-INFINITY, -INFINITY, -INFINITY};
};

// The root's eight octant files (SoupParams::root_split): each triangle goes to the file of its
// centroid's octant, in the order given; `suffix` tells apart the files of different threads.
class OctantFiles {
public:
    OctantFiles(const fs::path& dir, const std::string& suffix, const SoupRootSplit& split, std::size_t corner, std::size_t buffer)
        : dir_(dir), suffix_(suffix), mid_{split.mid[0], split.mid[1], split.mid[2]}, corner_(corner), buffer_(buffer) {}
    // Appends n triangles; octants[t] (when given) receives each one's octant.
    void add(const std::byte* tris, std::size_t n, std::uint8_t* octants = nullptr) {
        const std::size_t tb = 3 * corner_;
        for (std::size_t t = 0; t < n; ++t) {
            const std::byte* tri = tris + t * tb;
            const int o = ooc::centroid_octant(tri, corner_, mid_);
            if (!files_[o]) files_[o].emplace(path(dir_, o, suffix_), buffer_);
            files_[o]->write(tri, tb);
            ++counts_[o];
            if (octants) octants[t] = static_cast<std::uint8_t>(o);
        }
    }
    std::uint64_t offset(int o) const { return files_[o] ? files_[o]->offset() : 0; }
    std::uint64_t count(int o) const { return counts_[o]; }
    std::uint64_t bytes() const {
        std::uint64_t b = 0;
        for (int o = 0; o < 8; ++o) b += offset(o);
        return b;
    }
    void close() {
        for (auto& f : files_)
            if (f) f->close();
    }
    static std::string path(const fs::path& dir, int o, const std::string& suffix) {
        return (dir / ("root-" + std::to_string(o) + suffix)).string();
    }
    // Removes every file this class may have written in `dir` (threads' suffixes "" and "b").
    static void remove_all(const fs::path& dir) {
        std::error_code ignored;
        for (const char* suffix : {"", "b"})
            for (int o = 0; o < 8; ++o) fs::remove(path(dir, o, suffix), ignored);
    }

private:
    fs::path dir_;
    std::string suffix_;
    double mid_[3];
    std::size_t corner_, buffer_;
    std::array<std::optional<SequentialWriter>, 8> files_;
    std::array<std::uint64_t, 8> counts_{};
};

// Used-vertex bounds as the soup header has them (SoupWriter's min/max of the corners' positions).
struct Box {
    float lo[3] = {INFINITY, INFINITY, INFINITY};
    float hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    void add(const float* p) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    void add(const Box& b) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], b.lo[a]);
            hi[a] = std::max(hi[a], b.hi[a]);
        }
    }
    Bounds bounds() const {
        Bounds r;
        if (lo[0] <= hi[0]) {
            r.add({lo[0], lo[1], lo[2]});
            r.add({hi[0], hi[1], hi[2]});
        }
        return r;
    }
};

std::size_t element_index(const PlyHeader& h, bool faces) {
    for (std::size_t i = 0; i < h.elements.size(); ++i) {
        const std::string& n = h.elements[i].name;
        if (faces ? (n == "face" || n == "tristrips") : n == "vertex") return i;
    }
    return h.elements.size();
}

void check_triangle_count(const std::string& path, std::uint64_t triangles) {
    if (triangles >= (std::uint64_t{1} << 61))
        throw_error(Error::Kind::unsupported, path, "too many triangles for the out-of-core builder");
}

}  // namespace

// ---- background edge sort ----------------------------------------------------------------------------

struct SoupEdgeJob {
    std::thread thread;
    std::exception_ptr error;
    std::vector<std::uint64_t> odd, border;
    ~SoupEdgeJob() {
        if (thread.joinable()) thread.join();
    }
};

void SoupResult::wait_edges() {
    if (!edge_job) return;
    const std::shared_ptr<SoupEdgeJob> job = std::move(edge_job);
    edge_job.reset();
    job->thread.join();
    if (job->error) std::rethrow_exception(job->error);
    odd_non_manifold_edges = std::move(job->odd);
    border_edges = std::move(job->border);
}

// ---- conversion ---------------------------------------------------------------------------------------

namespace {

// Vertices duplicated at one position (UV or normal seams stored as split vertices, common in PLY and
// OBJ exports) make an interior edge look like two border edges by index. Those are not free: each side
// may lie in another node, and shrinking them separately would open the seam. So an index border edge
// counts as a border only when no other index border edge joins the same two positions (docs/octree.md,
// "Coarse levels").
struct SeamUse {
    std::array<float, 6> ends;  // the two positions, smaller first
    std::uint64_t edge;
    bool operator<(const SeamUse& o) const { return ends < o.ends; }
};

SeamUse seam_use(const float* pa_in, const float* pb_in, std::uint64_t edge) {
    std::array<float, 3> pa, pb;
    std::memcpy(pa.data(), pa_in, 12);
    std::memcpy(pb.data(), pb_in, 12);
    if (pb < pa) std::swap(pa, pb);
    return {{pa[0], pa[1], pa[2], pb[0], pb[1], pb[2]}, edge};
}

// Removes from r.border_edges every edge whose two positions another use shares.
void remove_seams(SoupResult& r, std::vector<SeamUse>& uses) {
    std::sort(uses.begin(), uses.end());
    std::vector<std::uint64_t> seams;
    for (std::size_t i = 0; i < uses.size();) {
        std::size_t j = i + 1;
        while (j < uses.size() && uses[j].ends == uses[i].ends) ++j;
        if (j - i > 1)
            for (std::size_t k = i; k < j; ++k) seams.push_back(uses[k].edge);
        i = j;
    }
    if (seams.empty()) return;
    std::sort(seams.begin(), seams.end());
    std::vector<std::uint64_t> kept;
    kept.reserve(r.border_edges.size() - std::min(seams.size(), r.border_edges.size()));
    std::set_difference(r.border_edges.begin(), r.border_edges.end(), seams.begin(), seams.end(), std::back_inserter(kept));
    r.border_edges.swap(kept);
}

// In-memory path: the vertex table is still resident, so the border edges' positions are looked up
// directly (no pass over the soup). A border edge is used by exactly one non-degenerate triangle, and a
// degenerate one (a, a, b) reaches it too: it is a use as well, as in the soup pass below.
void drop_seam_borders(SoupResult& r, const float* vertices, std::size_t floats, const std::vector<std::uint64_t>& degenerate_uses) {
    if (r.border_edges.empty()) return;
    std::vector<SeamUse> uses;
    uses.reserve(r.border_edges.size());
    auto add = [&](std::uint64_t edge) {
        const std::size_t a = static_cast<std::size_t>(edge >> 32), b = static_cast<std::size_t>(edge & 0xffffffffu);
        uses.push_back(seam_use(vertices + a * floats, vertices + b * floats, edge));
    };
    for (std::uint64_t edge : r.border_edges) add(edge);
    for (std::uint64_t edge : degenerate_uses)
        if (std::binary_search(r.border_edges.begin(), r.border_edges.end(), edge)) add(edge);
    remove_seams(r, uses);
}

// External path: the border edges' uses are found in the assembled triangles (a pass over the soup, or
// the assembly pass itself when it splits the root), touching only the (few) border edges; a bit filter
// over the vertex ids skips the binary search for almost every other edge.
class SeamFinder {
public:
    SeamFinder(const std::vector<std::uint64_t>& border, std::uint64_t vertices, std::size_t budget)
        : border_(border), bits_(std::bit_floor(std::clamp<std::uint64_t>(vertices, 64, std::uint64_t{budget} / 16 * 8))),
          filter_(static_cast<std::size_t>(bits_ / 64), 0) {
        for (std::uint64_t e : border_)
            for (std::uint64_t v : {e >> 32, e & 0xffffffffu}) filter_[bit(v) >> 6] |= std::uint64_t{1} << (bit(v) & 63);
    }
    // Appends to `uses` the border-edge uses of n soup triangles of `corner` bytes per corner.
    void add(const std::byte* tris, std::size_t n, std::size_t corner, std::vector<SeamUse>& uses) const {
        if (border_.empty()) return;
        for (std::size_t t = 0; t < n; ++t) {
            const std::byte* tri = tris + t * 3 * corner;
            for (int k = 0; k < 3; ++k) {
                const std::byte* ca = tri + k * corner;
                const std::byte* cb = tri + ((k + 1) % 3) * corner;
                std::uint32_t a, b;
                std::memcpy(&a, ca, 4);
                std::memcpy(&b, cb, 4);
                if (a == b || !marked(a) || !marked(b)) continue;
                const std::uint64_t edge = a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a);
                if (!std::binary_search(border_.begin(), border_.end(), edge)) continue;
                uses.push_back(seam_use(reinterpret_cast<const float*>(ca + 4), reinterpret_cast<const float*>(cb + 4), edge));
            }
        }
    }

private:
    std::uint64_t bit(std::uint64_t v) const { return v & (bits_ - 1); }
    bool marked(std::uint32_t v) const { return (filter_[bit(v) >> 6] >> (bit(v) & 63)) & 1u; }
    const std::vector<std::uint64_t>& border_;
    std::uint64_t bits_;
    std::vector<std::uint64_t> filter_;
};

void drop_seam_borders(SoupResult& r, std::size_t budget) {
    if (r.border_edges.empty()) return;
    std::vector<SeamUse> uses;
    uses.reserve(r.border_edges.size());
    const SeamFinder finder(r.border_edges, r.vertices, budget);
    SoupReader reader(r.path);
    const std::size_t corner = soup_corner_bytes(reader.layout());
    std::vector<std::byte> block;
    while (const std::size_t n = reader.read(1 << 14, block)) finder.add(block.data(), n, corner, uses);
    remove_seams(r, uses);
}


// ---- External passes on two threads ---------------------------------------------------------------

// Hands the right to write on in index order between the workers of run_workers.
class Turn {
public:
    // Waits until it is item i's turn; false when the workers are being stopped.
    bool wait(std::size_t i, const std::atomic<bool>& stop) {
        std::unique_lock lock(mutex_);
        while (next_ != i) {
            if (stop) return false;
            changed_.wait_for(lock, std::chrono::milliseconds(10));
        }
        return true;
    }
    void done() {
        {
            std::lock_guard lock(mutex_);
            ++next_;
        }
        changed_.notify_all();
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::size_t next_ = 0;
};

}  // namespace


SoupResult convert_to_soup(const std::string& ply_path, const std::string& soup_path, const SoupParams& params,
                           Progress* progress) {
    if (params.memory_bytes < (std::size_t{4} << 20))
        throw Error(Error::Kind::argument, "soup: the memory budget must be at least 4 MB");
    PlyReader reader(ply_path);
    const PlyHeader& header = reader.header();
    const PlyVertexAttributes attrs = reader.vertex_attributes();
    SoupResult r;
    r.path = soup_path;
    r.wedge_texcoords = reader.has_corner_texcoords();
    r.layout = {attrs.normals, attrs.colors, attrs.texcoords || r.wedge_texcoords, reader.has_texnumbers()};
    r.vertices = reader.vertex_count();
    if (r.vertices == 0) throw_error(Error::Kind::invalid, ply_path, "no vertices");
    if (r.vertices >= 0xffffffffull)
        throw_error(Error::Kind::unsupported, ply_path, "more than 2^32-2 vertices");
    const std::size_t face_element = element_index(header, true);
    if (face_element == header.elements.size()) throw_error(Error::Kind::invalid, ply_path, "no faces (a point cloud)");
    const VertexLayout& L = r.layout;
    const std::size_t floats = L.floats();
    const std::size_t vrec = 4 * floats;
    const std::size_t corner = soup_corner_bytes(L);
    const std::size_t budget = params.memory_bytes;
    const std::uint64_t file_size = std::max<std::uint64_t>(reader.file_size(), 1);
    const bool vertices_first = element_index(header, false) < face_element;
    r.external = !(vertices_first && static_cast<double>(r.vertices) * vrec <= 0.5 * static_cast<double>(budget));
    constexpr std::size_t kVertexChunk = 16384;
    constexpr std::size_t kFaceChunk = 32768;
    VertexChunks chunks(L, kVertexChunk);
    PlyFaceChunk faces;
    // A wedge (face-corner) texcoord replaces the vertex's; a face with an empty list keeps the vertex's
    // own u v (zero when the vertex element has none).
    const std::size_t uv_at = L.texcoord_offset();
    std::vector<float> wedge(floats);
    auto set_wedge = [&](float* record, const Vec2f& uv) {
        if (!std::isnan(uv.x)) {
            record[uv_at] = uv.x;
            record[uv_at + 1] = uv.y;
        }
    };
    // A face's material index goes into every corner record (a float, exact below 2^24).
    const std::size_t material_at = L.material_offset();
    auto set_material = [&](float* record, std::int64_t texnumber) {
        record[material_at] = static_cast<float>(std::clamp<std::int64_t>(texnumber, 0, std::int64_t{1} << 24));
    };
    const bool per_corner = r.wedge_texcoords || L.material;  // corner records differ from the vertex's

    const std::uint64_t expected_edges = 3 * std::max<std::uint64_t>(header.elements[face_element].count, 1);
    const std::string edges_path = (fs::path(soup_path).parent_path() / "edges.tmp").string();
    if (!r.external) {
        std::vector<float> vertices(static_cast<std::size_t>(r.vertices) * floats);
        // The records stay in memory when asked and when they fit beside the vertex table in 60 % of the
        // budget (with the edge sort's 30 %, still within it).
        const double room = 0.6 * static_cast<double>(budget) - static_cast<double>(vertices.size()) * 4;
        // Not even tried when the header's face count (as triangles) already exceeds it; polygons that
        // fan into more triangles than expected spill to the file.
        std::size_t cap = room > 0 ? std::min<std::size_t>(params.memory_soup_bytes, static_cast<std::size_t>(room)) : 0;
        const std::uint64_t expected_bytes = expected_edges * corner;  // expected_edges = 3 × faces
        if (expected_bytes > cap) cap = 0;
        // A root split (SoupParams::root_split) needs the bounds of the used vertices before the faces
        // stream by: it is made with the bounds of all the vertices and the header's face count, each
        // triangle's octant noted, and kept when the used bounds and the final count give the same answer
        // (nearly always: every vertex is used); otherwise the octant files are merged back into the soup
        // in triangle order, by the notes.
        const fs::path dir = fs::path(soup_path).parent_path();
        std::uint64_t loaded = 0;  // vertices read
        std::optional<SoupWriter> soup_file;
        std::optional<OctantFiles> octant_files;
        SoupRootSplit guess;
        Box all, used;
        std::vector<std::uint8_t> octant_of;  // per triangle, while the split may still be undone
        std::vector<std::byte> tris;          // one face chunk's triangle records
        auto start_soup = [&] {
            if (octant_files || soup_file) return;
            if (params.root_split && cap == 0) {
                for (std::uint64_t i = 0; i < loaded; ++i) all.add(&vertices[static_cast<std::size_t>(i) * floats]);
                guess = params.root_split(all.bounds(), header.elements[face_element].count, L);
            }
            if (guess.split) {
                octant_files.emplace(dir, "", guess, corner, std::clamp<std::size_t>(budget / 32, 64 << 10, 8 << 20));
                octant_of.reserve(static_cast<std::size_t>(header.elements[face_element].count));
            } else {
                soup_file.emplace(soup_path, L, cap);
                soup_file->reserve(expected_bytes);
            }
        };
        auto edges = std::make_unique<EdgeCounter>(edges_path, r.vertices, expected_edges, budget, params.count_edges);
        EdgeWorker edge_worker(*edges, params.count_edges);
        std::vector<std::uint64_t> degenerate_uses;  // edges of triangles with a repeated vertex
        auto take_faces = [&](const PlyFaceChunk& fc) {
            r.skipped_faces += fc.skipped_faces;
            edge_worker.push(fc.indices);
            for (std::size_t t = 0; t + 2 < fc.indices.size(); t += 3) {
                const std::uint32_t* v = &fc.indices[t];
                if (v[0] != v[1] && v[1] != v[2] && v[0] != v[2]) continue;
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t a = v[k], b = v[(k + 1) % 3];
                    if (a != b) degenerate_uses.push_back(a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a));
                }
            }
            start_soup();
            if (octant_files) {
                const std::size_t n = fc.triangle_count();
                tris.resize(n * 3 * corner);
                for (std::size_t c = 0; c < 3 * n; ++c) {
                    const std::uint32_t id = fc.indices[c];
                    std::byte* at = tris.data() + c * corner;
                    std::memcpy(at, &id, 4);
                    std::memcpy(at + 4, &vertices[static_cast<std::size_t>(id) * floats], vrec);
                    if (r.wedge_texcoords) set_wedge(reinterpret_cast<float*>(at + 4), fc.corner_texcoords[c]);
                    if (L.material) set_material(reinterpret_cast<float*>(at + 4), fc.texnumbers[c / 3]);
                    used.add(reinterpret_cast<const float*>(at + 4));
                }
                const std::size_t at = octant_of.size();
                octant_of.resize(at + n);
                octant_files->add(tris.data(), n, octant_of.data() + at);
            } else if (per_corner) {
                for (std::size_t c = 0; c < fc.indices.size(); ++c) {
                    const std::uint32_t id = fc.indices[c];
                    std::memcpy(wedge.data(), &vertices[static_cast<std::size_t>(id) * floats], vrec);
                    if (r.wedge_texcoords) set_wedge(wedge.data(), fc.corner_texcoords[c]);
                    if (L.material) set_material(wedge.data(), fc.texnumbers[c / 3]);
                    soup_file->corner(id, wedge.data());
                }
            } else {
                for (std::uint32_t id : fc.indices) soup_file->corner(id, &vertices[static_cast<std::size_t>(id) * floats]);
            }
            r.triangles += fc.triangle_count();
        };
        // ASCII elements are parsed on two threads (see parse_ascii_in_two); the rest of the element, if
        // the helper stops early, and binary files go through the single-reader loop.
        const bool split_ascii = params.threads >= 2 && header.format == PlyEncoding::ascii;
        const std::size_t segment_bytes = std::clamp<std::size_t>(budget / 32, 64 << 10, 512 << 10);
        std::size_t split_element = header.elements.size();  // the element last split
        auto parse_vertices = [&](PlyReader& rd, const AsciiSegment& s, Unit&) {
            VertexChunks own(L, kVertexChunk);
            for (std::uint64_t done = 0; done < s.count;) {
                const std::size_t n = own.next(rd, static_cast<std::size_t>(std::min<std::uint64_t>(kVertexChunk, s.count - done)));
                if (n == 0) break;
                std::memcpy(&vertices[static_cast<std::size_t>(s.first + done) * floats], own.packed(), n * vrec);
                done += n;
            }
        };
        auto parse_faces = [&](PlyReader& rd, const AsciiSegment& s, PlyFaceChunk& chunk) {
            for (std::uint64_t done = 0; done < s.count;) {
                const std::size_t n = rd.read_faces(static_cast<std::size_t>(s.count - done), chunk);
                if (n == 0) break;
                done += n;
            }
        };
        try {
            while (const PlyElement* e = reader.current_element()) {
                check_progress(progress, static_cast<double>(reader.position()) / file_size, "soup: reading");
                const std::size_t el = static_cast<std::size_t>(e - header.elements.data());
                if (split_ascii && el != split_element && (reader.at_vertices() || reader.at_faces())) {
                    split_element = el;
                    if (reader.at_vertices()) {
                        parse_ascii_in_two<Unit>(reader, ply_path, segment_bytes, parse_vertices, [&](Unit&, const AsciiSegment& s) {
                            loaded = s.first + s.count;
                            check_progress(progress, static_cast<double>(s.end) / file_size, "soup: reading");
                        });
                    } else {
                        parse_ascii_in_two<PlyFaceChunk>(reader, ply_path, segment_bytes, parse_faces,
                                                         [&](PlyFaceChunk& chunk, const AsciiSegment& s) {
                            take_faces(chunk);
                            check_progress(progress, static_cast<double>(s.end) / file_size, "soup: reading");
                        });
                    }
                } else if (reader.at_vertices()) {
                    const std::size_t n = chunks.next(reader);
                    std::memcpy(&vertices[loaded * floats], chunks.packed(), n * vrec);
                    loaded += n;
                } else if (reader.at_faces()) {
                    faces.clear();
                    reader.read_faces(kFaceChunk, faces);
                    take_faces(faces);
                } else {
                    reader.skip_element();
                }
            }
            check_triangle_count(ply_path, r.triangles);
            if (r.triangles == 0) throw_error(Error::Kind::invalid, ply_path, "no triangles");
            if (octant_files) {
                octant_files->close();
                const Bounds bounds = used.bounds(), guessed = all.bounds();
                const SoupRootSplit now = params.root_split(bounds, r.triangles, L);
                r.temp_bytes_peak = octant_files->bytes();
                if (now.split && now.mid == guess.mid && bounds.min == guessed.min && bounds.max == guessed.max) {
                    r.root_split = true;
                    r.bounds = bounds;
                    for (int o = 0; o < 8; ++o)
                        if (octant_files->count(o)) {
                            r.octants[o].push_back({OctantFiles::path(dir, o, ""), 0, octant_files->count(o)});
                            r.octant_counts[o] = octant_files->count(o);
                        }
                } else {
                    // Undo the split: the soup in triangle order, each record taken from its octant's file.
                    check_progress(progress, 1.0, "soup: reading");
                    SoupWriter merged(soup_path, L);
                    const std::size_t tb = 3 * corner, block = 4096;
                    struct Source {
                        std::optional<File> file;
                        std::vector<char> data;
                        std::uint64_t read = 0;  // triangles read from the file
                        std::size_t at = 0;      // next triangle in data
                    };
                    std::array<Source, 8> in;
                    for (std::uint8_t o : octant_of) {
                        Source& src = in[o];
                        if (src.at * tb == src.data.size()) {
                            if (!src.file) src.file.emplace(OctantFiles::path(dir, o, ""), O_RDONLY);
                            const std::uint64_t n = std::min<std::uint64_t>(block, octant_files->count(o) - src.read);
                            src.data.resize(static_cast<std::size_t>(n) * tb);
                            src.file->read_at(src.data.data(), src.data.size(), src.read * tb);
                            src.read += n;
                            src.at = 0;
                        }
                        merged.raw(src.data.data() + src.at * tb, tb);
                        ++src.at;
                    }
                    merged.finish(r);
                    OctantFiles::remove_all(dir);
                }
                octant_files.reset();
                std::vector<std::uint8_t>().swap(octant_of);
            } else {
                soup_file->finish(r);
                r.temp_bytes_peak = soup_file->bytes();
            }
            edge_worker.finish();
            if (params.background_edges && params.count_edges) {
                // The counter, the vertex table and the degenerate uses move to the job, which frees them.
                auto job = std::make_shared<SoupEdgeJob>();
                job->thread = std::thread([job = job.get(), counter = std::move(edges), table = std::move(vertices),
                                           degenerate = std::move(degenerate_uses), floats]() mutable {
                    try {
                        SoupResult part;
                        part.odd_non_manifold_edges = counter->odd_non_manifold(nullptr, 0, 1, part.border_edges);
                        counter.reset();
                        drop_seam_borders(part, table.data(), floats, degenerate);
                        job->odd = std::move(part.odd_non_manifold_edges);
                        job->border = std::move(part.border_edges);
                    } catch (...) {
                        job->error = std::current_exception();
                    }
                });
                r.edge_job = std::move(job);
            } else {
                r.odd_non_manifold_edges = edges->odd_non_manifold(progress, 0.9, 1.0, r.border_edges);
                edges.reset();
                drop_seam_borders(r, vertices.data(), floats, degenerate_uses);
                std::vector<float>().swap(vertices);
            }
        } catch (...) {
            std::error_code ignored;
            fs::remove(soup_path, ignored);
            OctantFiles::remove_all(dir);
            throw;
        }
        check_progress(progress, 1.0, "soup: reading");
        return r;
    }

    // External path. Memory: 40% of the budget for the resident range of each pass, 25% for buffers.
    r.passes = 3;
    const fs::path dir = fs::path(soup_path).parent_path();
    const std::string vertex_path = (dir / "vertices.tmp").string();
    const std::string refs_path = (dir / "refs.tmp").string();
    const std::string corners_path = (dir / "corners.tmp").string();
    const std::string corners2_path = (dir / "corners2.tmp").string();
    // Passes 2 and 3 on two threads: the order of the placed corners inside a corner range does not
    // matter (pass 3 puts each at its slot), so each thread dereferences every second vertex range
    // into a spill of its own, then assembles every second corner range, written in order. Each
    // thread holds half of the resident share, so the memory is that of one.
    const int workers = params.threads >= 2 ? 2 : 1;
    struct Cleanup {
        std::vector<std::string> paths;
        ~Cleanup() {
            std::error_code ignored;
            for (const std::string& p : paths) fs::remove(p, ignored);
        }
    } cleanup{{vertex_path, refs_path, corners_path, corners2_path, edges_path}};
    try {
        // Vertex ranges of at most 40 % of the budget per thread, as many per thread (the threads take
        // alternate ranges: 7 ranges at 64 MB on the 13.9M input left one thread idle a quarter of pass 2).
        const std::uint64_t widest = std::max<std::uint64_t>(1024, static_cast<std::uint64_t>(0.4 * budget) / workers / vrec);
        const std::uint64_t rounds = (r.vertices + widest * workers - 1) / (widest * workers);
        const std::uint64_t range = std::max<std::uint64_t>(1, (r.vertices + rounds * workers - 1) / (rounds * workers));
        const std::size_t ranges = static_cast<std::size_t>((r.vertices + range - 1) / range);
        // vertex, corner[, wedge u v][, material]
        const std::size_t material_ref = r.wedge_texcoords ? 20 : 12;
        const std::size_t ref_bytes = material_ref + (L.material ? 4 : 0);
        auto buffer_for = [&](std::size_t buckets) {
            return std::clamp<std::size_t>(static_cast<std::size_t>(0.25 * budget) / std::max<std::size_t>(buckets, 1),
                                           4096, std::size_t{1} << 20);
        };
        // Pass 1.
        std::uint64_t tail = 0;
        {
            SequentialWriter vertex_file(vertex_path, 1 << 20);
            BucketSpill refs(refs_path, ranges, ref_bytes, buffer_for(ranges));
            EdgeCounter edges(edges_path, r.vertices, expected_edges, budget, params.count_edges);
            EdgeWorker edge_worker(edges, params.count_edges);
            while (reader.current_element()) {
                check_progress(progress, 0.5 * static_cast<double>(reader.position()) / file_size, "soup: reading");
                if (reader.at_vertices()) {
                    const std::size_t n = chunks.next(reader);
                    vertex_file.write(chunks.packed(), n * vrec);
                } else if (reader.at_faces()) {
                    faces.clear();
                    reader.read_faces(kFaceChunk, faces);
                    r.skipped_faces += faces.skipped_faces;
                    edge_worker.push(faces.indices);
                    char rec[24];
                    for (std::size_t c = 0; c < faces.indices.size(); ++c) {
                        const std::uint32_t id = faces.indices[c];
                        std::memcpy(rec, &id, 4);
                        std::memcpy(rec + 4, &tail, 8);
                        if (r.wedge_texcoords) std::memcpy(rec + 12, &faces.corner_texcoords[c], 8);
                        if (L.material) {
                            const std::int64_t m = faces.texnumbers[c / 3];
                            std::memcpy(rec + material_ref, &m, 4);  // low half (little endian), set_material clamps
                        }
                        if (L.material) refs.add(id / range, rec);
                        else if (r.wedge_texcoords) refs.add<20>(id / range, rec);
                        else refs.add<12>(id / range, rec);
                        ++tail;
                    }
                } else {
                    reader.skip_element();
                }
            }
            vertex_file.close();
            refs.finish();
            edge_worker.finish();
            r.triangles = tail / 3;
            check_triangle_count(ply_path, r.triangles);
            if (r.triangles == 0) throw_error(Error::Kind::invalid, ply_path, "no triangles");
            r.odd_non_manifold_edges = edges.odd_non_manifold(progress, 0.5, 0.55, r.border_edges);

            // Pass 2. A placed corner is its slot inside its corner range (u32) and its soup corner.
            const std::uint64_t chunk_corners = std::clamp<std::uint64_t>(
                static_cast<std::uint64_t>(0.4 * budget) / workers / corner / 3 * 3, 3, 0xffffffffull / 3 * 3);
            const std::size_t chunks_out = static_cast<std::size_t>((tail + chunk_corners - 1) / chunk_corners);
            const std::size_t placed_bytes = 4 + corner;
            std::vector<std::unique_ptr<BucketSpill>> placed;
            for (int w = 0; w < workers; ++w)
                placed.push_back(std::make_unique<BucketSpill>(w ? corners2_path : corners_path, chunks_out, placed_bytes,
                                                               buffer_for(chunks_out * workers)));
            // The bounds of the used vertices (what the soup's header gets), for the root split; the
            // dereference sees every corner.
            const bool ask_split = static_cast<bool>(params.root_split);
            std::array<Box, 2> boxes;
            std::atomic<bool> stop{false};
            ooc::run_workers(workers, stop, [&](int w) {
                File vertices(vertex_path, O_RDONLY);
                std::vector<float> resident;
                std::vector<char> tmp;
                std::vector<char> rec(placed_bytes);
                Box& box = boxes[static_cast<std::size_t>(w)];
                for (std::size_t b = static_cast<std::size_t>(w); b < ranges; b += workers) {
                    if (w == 0) check_progress(progress, 0.5 + 0.3 * static_cast<double>(b) / ranges, "soup: dereferencing");
                    else if (stop) return;
                    const std::uint64_t first = b * range;
                    const std::uint64_t count = std::min<std::uint64_t>(range, r.vertices - first);
                    resident.resize(static_cast<std::size_t>(count) * floats);
                    vertices.read_at(resident.data(), resident.size() * 4, first * vrec);
                    refs.for_each_block(b, tmp, [&](const char* data, std::size_t bytes) {
                        for (std::size_t o = 0; o < bytes; o += ref_bytes) {
                            std::uint32_t id;
                            std::uint64_t c;
                            std::memcpy(&id, data + o, 4);
                            std::memcpy(&c, data + o + 4, 8);
                            const std::uint64_t chunk = c / chunk_corners;
                            const auto slot = static_cast<std::uint32_t>(c - chunk * chunk_corners);
                            const float* v = &resident[static_cast<std::size_t>(id - first) * floats];
                            std::memcpy(rec.data(), &slot, 4);
                            std::memcpy(rec.data() + 4, &id, 4);
                            std::memcpy(rec.data() + 8, v, vrec);
                            if (ask_split) box.add(v);
                            if (r.wedge_texcoords) {
                                Vec2f uv;
                                std::memcpy(&uv, data + o + 12, 8);
                                float* record = reinterpret_cast<float*>(rec.data() + 8);
                                set_wedge(record, uv);
                            }
                            if (L.material) {
                                std::int32_t m;
                                std::memcpy(&m, data + o + material_ref, 4);
                                set_material(reinterpret_cast<float*>(rec.data() + 8), m);
                            }
                            placed[static_cast<std::size_t>(w)]->add(static_cast<std::size_t>(chunk), rec.data());
                        }
                    });
                }
            });
            std::uint64_t placed_total = 0;
            for (auto& p : placed) {
                p->finish();
                placed_total += p->bytes();
            }
            r.temp_bytes_peak = vertex_file.offset() + refs.bytes() + placed_total;
            {
                std::error_code ignored;
                fs::remove(vertex_path, ignored);
            }
            SoupRootSplit root;
            if (ask_split) {
                boxes[0].add(boxes[1]);
                const Bounds bounds = boxes[0].bounds();
                root = params.root_split(bounds, r.triangles, L);
                if (root.split) r.bounds = bounds;
            }

            // Pass 3. Each thread assembles every second corner range. Without a root split they are
            // written to the soup in order, the turn passing between the threads; with one, each thread
            // writes the triangles of its ranges into eight octant files of its own (no turn), and
            // octant o is the list of every range's run of it, in range order: the soup order.
            std::optional<SoupWriter> out;
            if (!root.split) out.emplace(soup_path, L);
            Turn turn;
            const SeamFinder seams(r.border_edges, r.vertices, budget);
            std::array<std::vector<SeamUse>, 2> seam_uses;
            // Per range and octant, the run its thread wrote: (byte offset, triangles).
            std::vector<std::array<std::pair<std::uint64_t, std::uint64_t>, 8>> runs(root.split ? chunks_out : 0);
            std::array<std::uint64_t, 2> octant_bytes{};
            const std::size_t octant_buffer = std::clamp<std::size_t>(budget / 32 / workers, 64 << 10, 8 << 20);
            const std::size_t tri = 3 * corner;
            ooc::run_workers(workers, stop, [&](int w) {
                // Every corner of a range is placed exactly once, so the slots need no zero fill.
                const std::unique_ptr<char[]> slot_memory(new char[static_cast<std::size_t>(std::min<std::uint64_t>(chunk_corners, tail)) * corner]);
                std::vector<char> tmp;
                OctantFiles files(dir, w ? "b" : "", root, corner, octant_buffer);
                for (std::size_t s = static_cast<std::size_t>(w); s < chunks_out; s += workers) {
                    if (w == 0) check_progress(progress, 0.8 + 0.2 * static_cast<double>(s) / chunks_out, "soup: assembling");
                    else if (stop) return;
                    const std::uint64_t first = s * chunk_corners;
                    const std::uint64_t count = std::min<std::uint64_t>(chunk_corners, tail - first);
                    const std::span<char> slots(slot_memory.get(), static_cast<std::size_t>(count) * corner);
                    for (const auto& p : placed)
                        p->for_each_block(s, tmp, [&](const char* data, std::size_t bytes) {
                            for (std::size_t o = 0; o < bytes; o += placed_bytes) {
                                std::uint32_t slot;
                                std::memcpy(&slot, data + o, 4);
                                std::memcpy(&slots[std::size_t{slot} * corner], data + o + 4, corner);
                            }
                        });
                    if (!root.split) {
                        if (!turn.wait(s, stop)) return;
                        out->raw(slots.data(), slots.size());
                        turn.done();
                        continue;
                    }
                    const auto* tris = reinterpret_cast<const std::byte*>(slots.data());
                    const std::size_t n = slots.size() / tri;
                    seams.add(tris, n, corner, seam_uses[static_cast<std::size_t>(w)]);
                    auto& run = runs[s];
                    for (int o = 0; o < 8; ++o) run[o] = {files.offset(o), files.count(o)};
                    files.add(tris, n);
                    for (int o = 0; o < 8; ++o) run[o].second = files.count(o) - run[o].second;
                }
                octant_bytes[static_cast<std::size_t>(w)] = files.bytes();
                files.close();
            });
            if (!root.split) {
                out->finish(r);
                drop_seam_borders(r, budget);
                r.temp_bytes_peak = std::max(r.temp_bytes_peak, refs.bytes() + placed_total + out->bytes());
            } else {
                r.root_split = true;
                for (std::size_t s = 0; s < chunks_out; ++s)
                    for (int o = 0; o < 8; ++o) {
                        const auto [offset, count] = runs[s][o];
                        if (!count) continue;
                        const std::string path = OctantFiles::path(dir, o, s % static_cast<std::size_t>(workers) ? "b" : "");
                        std::vector<SoupRegion>& list = r.octants[o];
                        // One thread's consecutive runs of a file are one region.
                        if (!list.empty() && list.back().path == path &&
                            list.back().offset + list.back().count * tri == offset)
                            list.back().count += count;
                        else
                            list.push_back({path, offset, count});
                        r.octant_counts[o] += count;
                    }
                if (!r.border_edges.empty()) {
                    std::vector<SeamUse>& uses = seam_uses[0];
                    uses.insert(uses.end(), seam_uses[1].begin(), seam_uses[1].end());
                    remove_seams(r, uses);
                }
                r.temp_bytes_peak = std::max(r.temp_bytes_peak, refs.bytes() + placed_total + octant_bytes[0] + octant_bytes[1]);
            }
        }
    } catch (...) {
        std::error_code ignored;
        fs::remove(soup_path, ignored);
        OctantFiles::remove_all(dir);
        throw;
    }
    check_progress(progress, 1.0, "soup: assembling");
    return r;
}

// ---- reader -------------------------------------------------------------------------------------------

SoupReader::SoupReader(const std::string& path) : path_(path) {
    File f(path, O_RDONLY);
    SoupHeader h{};
    if (f.size() < sizeof h) throw_error(Error::Kind::format, path, "not a triangle soup (too short)");
    f.read_at(&h, sizeof h, 0);
    if (std::memcmp(h.magic, kSoupMagic, 8) != 0 || h.version != kSoupVersion)
        throw_error(Error::Kind::format, path, "not a triangle soup of version 1");
    layout_ = VertexLayout::from_flags(h.layout);
    wedge_texcoords_ = (h.layout & kWedgeFlag) != 0;
    triangles_ = h.triangles;
    vertices_ = h.vertices;
    bounds_.add({h.bounds[0], h.bounds[1], h.bounds[2]});
    bounds_.add({h.bounds[3], h.bounds[4], h.bounds[5]});
    if (f.size() != kSoupHeaderBytes + triangles_ * soup_triangle_bytes(layout_))
        throw_error(Error::Kind::format, path, "truncated triangle soup");
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw_error(Error::Kind::io, path, std::string("cannot open: ") + std::strerror(errno));
}

SoupReader::~SoupReader() {
    if (fd_ >= 0) ::close(fd_);
}

std::size_t SoupReader::read(std::size_t max_triangles, std::vector<std::byte>& out) {
    const std::uint64_t n = std::min<std::uint64_t>(max_triangles, triangles_ - next_);
    const std::size_t tb = soup_triangle_bytes(layout_);
    out.resize(static_cast<std::size_t>(n) * tb);
    if (n == 0) return 0;
    std::uint64_t offset = kSoupHeaderBytes + next_ * tb;
    std::size_t done = 0;
    while (done < out.size()) {
        const ssize_t got = ::pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw_error(Error::Kind::io, path_, std::string("read failed: ") + std::strerror(errno));
        if (got == 0) throw_error(Error::Kind::format, path_, "truncated triangle soup");
        done += static_cast<std::size_t>(got);
    }
    next_ += n;
    return static_cast<std::size_t>(n);
}

}  // namespace lodforge
