// The .mco file: a built marching-cube octree, versioned, little-endian, checksummed (docs/mcoctree.md,
// "File format"). The reader checks the checksum, every count against the file size before allocating,
// and then every structural invariant (validate_mc_octree), so a corrupt or lying file is an Error.
#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"
#include "lodforge/io/input_file.h"
#include "mcoctree/mc_octree_internal.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>

namespace lodforge {

namespace {

constexpr char magic[8] = {'L', 'F', 'M', 'C', 'O', '\r', '\n', '\x1a'};
constexpr std::uint32_t version = 2;  // 2: priority levels (cuts), non-decreasing triangle table
constexpr std::size_t node_bytes = 40;

std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
    return h;
}

class Writer {
public:
    template <class T> void put(const T& v) {
        const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
        buf.insert(buf.end(), p, p + sizeof(T));
    }
    template <class T> void put_array(const std::vector<T>& v) {
        const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
        buf.insert(buf.end(), p, p + v.size() * sizeof(T));
    }
    std::vector<std::uint8_t> buf;
};

class Reader {
public:
    Reader(const std::vector<std::uint8_t>& b, const std::string& f) : buf(b), file(f) {}
    template <class T> T get(const char* what) {
        need(sizeof(T), what);
        T v;
        std::memcpy(&v, buf.data() + pos, sizeof(T));
        pos += sizeof(T);
        return v;
    }
    template <class T> void get_array(std::vector<T>& v, std::uint64_t count, const char* what) {
        if (count > (buf.size() - pos) / sizeof(T)) truncated(what);
        v.resize(static_cast<std::size_t>(count));
        std::memcpy(v.data(), buf.data() + pos, v.size() * sizeof(T));
        pos += v.size() * sizeof(T);
    }
    void need(std::size_t n, const char* what) {
        if (buf.size() - pos < n) truncated(what);
    }
    [[noreturn]] void truncated(const char* what) {
        throw_error(Error::Kind::format, file, std::string("truncated: the file ends inside the ") + what +
                                                   " (byte " + std::to_string(pos) + ")");
    }
    const std::vector<std::uint8_t>& buf;
    const std::string& file;
    std::size_t pos = 0;
};

[[noreturn]] void bad(const std::string& file, const std::string& what) {
    throw_error(Error::Kind::format, file, "corrupt marching-cube octree: " + what);
}

}  // namespace

void validate_mc_octree(const McOctree& t, const std::string& file) {
    const std::size_t n = t.nodes.size();
    if (n == 0) bad(file, "no nodes");
    if (t.levels == 0 || t.levels > 17) bad(file, "root level " + std::to_string(t.levels) + " out of range");
    if (!(t.cube_size > 0) || !std::isfinite(t.cube_size) || !is_finite(t.origin)) bad(file, "bad cube size or origin");
    const std::size_t v = t.positions.size();
    if (t.normals.size() != v || (!t.colors.empty() && t.colors.size() != v)) bad(file, "vertex arrays differ in length");
    for (std::size_t i = 0; i < v; ++i)
        if (!is_finite(t.positions[i]) || !is_finite(t.normals[i])) bad(file, "vertex " + std::to_string(i) + " is not finite");
    for (std::uint32_t id : t.vertex_ids)
        if (id >= v) bad(file, "vertex index " + std::to_string(id) + " out of range");
    if (t.neighbours.size() != n * mc::neighbour_slots) bad(file, "neighbour table size");
    if (t.metric.size() != n) bad(file, "metric table size");
    const McNode& root = t.nodes[0];
    if (root.level != t.levels || root.parent != mc::none || root.x || root.y || root.z) bad(file, "bad root node");
    const auto& subs = mc::sub_edges();
    std::size_t internal = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const McNode& a = t.nodes[i];
        const std::string at = "node " + std::to_string(i);
        if (a.level > t.levels) bad(file, at + ": level out of range");
        const std::uint32_t size = 1u << (t.levels - a.level);
        if (a.x >= size || a.y >= size || a.z >= size) bad(file, at + ": position outside the root");
        std::uint64_t expect = 0;
        const int count = a.level == 0 ? mc::full_edges : mc::sub_edge_count;
        if (a.inside >> 27) bad(file, at + ": sample mask");
        for (int e = 0; e < count; ++e)
            if (((a.inside >> subs[e].a) & 1u) != ((a.inside >> subs[e].b) & 1u)) expect |= std::uint64_t(1) << e;
        if (a.crossings != expect) bad(file, at + ": crossings do not match the samples");
        if (std::uint64_t(a.first_vertex) + std::uint64_t(std::popcount(a.crossings)) > t.vertex_ids.size())
            bad(file, at + ": vertex range out of bounds");
        for (int s = 0; s < mc::neighbour_slots; ++s) {
            const std::uint32_t m = t.neighbours[i * mc::neighbour_slots + std::size_t(s)];
            if (m != mc::none && (m >= n || t.nodes[m].level != a.level)) bad(file, at + ": bad neighbour");
        }
        if (a.level == 0) {
            if (a.child_mask || a.priority != mc::none) bad(file, at + ": a leaf with children or a priority");
            continue;
        }
        ++internal;
        if (a.child_mask == 0) bad(file, at + ": an internal node without children");
        if (a.priority == 0 || a.priority > n) bad(file, at + ": priority out of range");
        const int children = std::popcount(unsigned(a.child_mask));
        if (a.first_child <= i || std::uint64_t(a.first_child) + std::uint64_t(children) > n)
            bad(file, at + ": children out of range");
        for (int o = 0, c = 0; o < 8; ++o) {
            if (!(a.child_mask & (1u << o))) continue;
            const McNode& ch = t.nodes[a.first_child + std::uint32_t(c++)];
            if (ch.level + 1 != a.level || ch.parent != i || ch.x != 2 * a.x + std::uint32_t(o & 1) ||
                ch.y != 2 * a.y + std::uint32_t((o >> 1) & 1) || ch.z != 2 * a.z + std::uint32_t((o >> 2) & 1))
                bad(file, at + ": child " + std::to_string(o) + " does not belong to it");
            if (ch.priority <= a.priority && ch.level > 0) bad(file, at + ": a child numbered before its parent");
        }
    }
    if (t.order.size() != internal) bad(file, "priority order length");
    for (std::size_t k = 0; k < t.order.size(); ++k)
        if (t.order[k] >= n || t.nodes[t.order[k]].priority != k + 1) bad(file, "priority order entry " + std::to_string(k));
    if (t.cuts.empty() || t.cuts.back() != t.order.size()) bad(file, "priority levels do not end with every node expanded");
    for (std::size_t i = 1; i < t.cuts.size(); ++i)
        if (t.cuts[i] <= t.cuts[i - 1]) bad(file, "priority level " + std::to_string(i) + " does not expand more nodes");
    if (t.triangle_counts.size() != t.cuts.size()) bad(file, "triangle count table length");
    for (std::size_t i = 1; i < t.triangle_counts.size(); ++i)
        if (t.triangle_counts[i] < t.triangle_counts[i - 1])
            bad(file, "triangle count of priority " + std::to_string(i) + " decreases");
}

void write_mc_octree(const McOctree& t, const std::string& path, Progress* progress) {
    check_progress(progress, 0, "mcoctree: writing");
    Writer w;
    w.buf.insert(w.buf.end(), magic, magic + 8);
    w.put(version);
    w.put(std::uint32_t(t.has_colors() ? 1 : 0));
    w.put(t.origin.x), w.put(t.origin.y), w.put(t.origin.z), w.put(t.cube_size);
    w.put(std::uint32_t(t.levels));
    w.put(std::uint64_t(t.input_points));
    w.put(std::uint64_t(t.positions.size()));
    w.put(std::uint64_t(t.nodes.size()));
    w.put(std::uint64_t(t.vertex_ids.size()));
    w.put(std::uint64_t(t.order.size()));
    w.put(std::uint64_t(t.cuts.size()));
    w.put(std::uint64_t(t.warnings.size()));
    w.put_array(t.positions);
    w.put_array(t.normals);
    if (t.has_colors()) w.put_array(t.colors);
    for (const McNode& n : t.nodes) {
        w.put(n.x), w.put(n.y), w.put(n.z);
        w.put(n.level), w.put(n.child_mask), w.put(std::uint16_t(0));
        w.put(n.first_child), w.put(n.parent), w.put(n.inside), w.put(n.crossings), w.put(n.first_vertex),
            w.put(n.priority);
    }
    w.put_array(t.vertex_ids);
    w.put_array(t.neighbours);
    w.put_array(t.order);
    w.put_array(t.cuts);
    w.put_array(t.triangle_counts);
    w.put_array(t.metric);
    for (const std::string& s : t.warnings) {
        w.put(std::uint32_t(s.size()));
        w.buf.insert(w.buf.end(), s.begin(), s.end());
    }
    w.put(fnv1a(w.buf.data(), w.buf.size()));
    check_progress(progress, 0.5, "mcoctree: writing");
    AtomicFile file(path);
    file.stream().write(reinterpret_cast<const char*>(w.buf.data()), std::streamsize(w.buf.size()));
    file.commit();
    check_progress(progress, 1, "mcoctree: writing");
}

McOctree read_mc_octree(const std::string& path, Progress* progress) {
    check_progress(progress, 0, "mcoctree: reading");
    check_input_file(path, "a .mco file");
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw_error(Error::Kind::io, path, "cannot open for reading");
    const std::streamoff size = in.tellg();
    if (size < 0) throw_error(Error::Kind::io, path, "cannot read");
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(size));
    in.seekg(0);
    if (!in.read(reinterpret_cast<char*>(buf.data()), size)) throw_error(Error::Kind::io, path, "cannot read");
    if (buf.size() < 8 || std::memcmp(buf.data(), magic, 8) != 0)
        throw_error(Error::Kind::format, path, "not a marching-cube octree (.mco) file: bad magic bytes");
    if (buf.size() < 16) throw_error(Error::Kind::format, path, "truncated: the file ends inside the header");
    std::uint32_t ver;
    std::memcpy(&ver, buf.data() + 8, 4);
    if (ver != version)
        throw_error(Error::Kind::unsupported, path, "unsupported .mco version " + std::to_string(ver) + " (this build reads " +
                                                        std::to_string(version) + ")");
    if (buf.size() < 8 + 8) throw_error(Error::Kind::format, path, "truncated");
    std::uint64_t stored;
    std::memcpy(&stored, buf.data() + buf.size() - 8, 8);
    if (buf.size() < 24 || fnv1a(buf.data(), buf.size() - 8) != stored)
        throw_error(Error::Kind::format, path, "checksum mismatch: the file is truncated or corrupt");
    const std::vector<std::uint8_t> body(buf.begin(), buf.end() - 8);
    Reader r(body, path);
    r.pos = 12;
    McOctree t;
    const auto flags = r.get<std::uint32_t>("header");
    if (flags > 1) throw_error(Error::Kind::format, path, "unknown flags " + std::to_string(flags));
    t.origin.x = r.get<float>("header"), t.origin.y = r.get<float>("header"), t.origin.z = r.get<float>("header");
    t.cube_size = r.get<float>("header");
    t.levels = r.get<std::uint32_t>("header");
    t.input_points = static_cast<std::size_t>(r.get<std::uint64_t>("header"));
    const auto vertices = r.get<std::uint64_t>("header"), nodes = r.get<std::uint64_t>("header"),
               ids = r.get<std::uint64_t>("header"), order = r.get<std::uint64_t>("header"),
               cuts = r.get<std::uint64_t>("header"), warnings = r.get<std::uint64_t>("header");
    r.get_array(t.positions, vertices, "positions");
    r.get_array(t.normals, vertices, "normals");
    if (flags & 1) r.get_array(t.colors, vertices, "colours");
    if (nodes > (body.size() - r.pos) / node_bytes) r.truncated("nodes");
    t.nodes.resize(static_cast<std::size_t>(nodes));
    for (McNode& n : t.nodes) {
        n.x = r.get<std::uint32_t>("nodes"), n.y = r.get<std::uint32_t>("nodes"), n.z = r.get<std::uint32_t>("nodes");
        n.level = r.get<std::uint8_t>("nodes"), n.child_mask = r.get<std::uint8_t>("nodes");
        if (r.get<std::uint16_t>("nodes") != 0) bad(path, "reserved node bytes are not zero");
        n.first_child = r.get<std::uint32_t>("nodes"), n.parent = r.get<std::uint32_t>("nodes");
        n.inside = r.get<std::uint32_t>("nodes");
        n.crossings = r.get<std::uint64_t>("nodes");
        n.first_vertex = r.get<std::uint32_t>("nodes"), n.priority = r.get<std::uint32_t>("nodes");
    }
    r.get_array(t.vertex_ids, ids, "vertex indices");
    if (nodes > body.size()) r.truncated("neighbours");
    r.get_array(t.neighbours, nodes * mc::neighbour_slots, "neighbours");
    r.get_array(t.order, order, "priority order");
    r.get_array(t.cuts, cuts, "priority levels");
    r.get_array(t.triangle_counts, cuts, "triangle counts");
    r.get_array(t.metric, nodes, "metric");
    if (warnings > body.size()) r.truncated("warnings");
    for (std::uint64_t i = 0; i < warnings; ++i) {
        const auto len = r.get<std::uint32_t>("warnings");
        r.need(len, "warnings");
        t.warnings.emplace_back(reinterpret_cast<const char*>(body.data() + r.pos), len);
        r.pos += len;
    }
    if (r.pos != body.size()) bad(path, std::to_string(body.size() - r.pos) + " unexpected bytes after the warnings");
    validate_mc_octree(t, path);
    check_progress(progress, 1, "mcoctree: reading");
    return t;
}

}  // namespace lodforge
