// The .mco file: a built marching-cube octree in the tagged section container (io/binary_io.h,
// docs/formats/mco.md). The reader checks the checksums, every count against the bytes left before
// allocating, and then every structural invariant (validate_mc_octree), so a corrupt or lying file is an
// Error. Version 2 files (one flat body and a 64-bit FNV-1a checksum) are still read: their body is the
// version 3 sections' payloads back to back.
#include "lodforge/error.h"
#include "io/binary_io.h"
#include "mcoctree/mc_octree_internal.h"

#include <bit>
#include <cmath>
#include <cstring>

namespace lodforge {

namespace {

constexpr char magic[8] = {'L', 'F', 'M', 'C', 'O', '\r', '\n', '\x1a'};
constexpr std::uint32_t version = 3;  // 3: the section container; 2: priority levels, non-decreasing triangle table
constexpr std::uint32_t flat_version = 2;
constexpr std::size_t node_bytes = 44;

// The counts in section HEAD that size the other sections.
struct Counts {
    std::uint32_t flags = 0;
    std::uint64_t vertices = 0, nodes = 0, ids = 0, order = 0, cuts = 0, warnings = 0;
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
    binary::Writer head, vert, node, prio, warn;
    head.put(std::uint32_t(t.has_colors() ? 1 : 0));
    head.put(t.origin.x), head.put(t.origin.y), head.put(t.origin.z), head.put(t.cube_size);
    head.put(std::uint32_t(t.levels));
    head.put(std::uint64_t(t.input_points));
    for (std::size_t n : {t.positions.size(), t.nodes.size(), t.vertex_ids.size(), t.order.size(), t.cuts.size(),
                          t.warnings.size()})
        head.put(std::uint64_t(n));
    vert.put_array(t.positions);
    vert.put_array(t.normals);
    if (t.has_colors()) vert.put_array(t.colors);
    for (const McNode& n : t.nodes) {
        node.put(n.x), node.put(n.y), node.put(n.z);
        node.put(n.level), node.put(n.child_mask), node.put(std::uint16_t(0));
        node.put(n.first_child), node.put(n.parent), node.put(n.inside), node.put(n.crossings), node.put(n.first_vertex),
            node.put(n.priority);
    }
    node.put_array(t.vertex_ids);
    node.put_array(t.neighbours);
    prio.put_array(t.order);
    prio.put_array(t.cuts);
    prio.put_array(t.triangle_counts);
    prio.put_array(t.metric);
    for (const std::string& s : t.warnings) {
        warn.put(std::uint32_t(s.size()));
        warn.bytes.insert(warn.bytes.end(), s.begin(), s.end());
    }
    const std::vector<std::uint8_t> bytes = binary::write_container(
        magic, version,
        {{"HEAD", &head.bytes}, {"VERT", &vert.bytes}, {"NODE", &node.bytes}, {"PRIO", &prio.bytes}, {"WARN", &warn.bytes}});
    check_progress(progress, 0.5, "mcoctree: writing");
    binary::write_file(path, bytes);
    check_progress(progress, 1, "mcoctree: writing");
}

namespace {

Counts read_head(binary::Reader& r, McOctree& t) {
    Counts c;
    c.flags = r.get<std::uint32_t>("header");
    if (c.flags > 1) r.fail("unknown flags " + std::to_string(c.flags));
    t.origin.x = r.get<float>("header"), t.origin.y = r.get<float>("header"), t.origin.z = r.get<float>("header");
    t.cube_size = r.get<float>("header");
    t.levels = r.get<std::uint32_t>("header");
    t.input_points = static_cast<std::size_t>(r.get<std::uint64_t>("header"));
    for (std::uint64_t* n : {&c.vertices, &c.nodes, &c.ids, &c.order, &c.cuts, &c.warnings}) *n = r.get<std::uint64_t>("header");
    return c;
}

void read_vertices(binary::Reader& r, const Counts& c, McOctree& t) {
    t.positions = r.get_array<Vec3f>(c.vertices, "positions");
    t.normals = r.get_array<Vec3f>(c.vertices, "normals");
    if (c.flags & 1) t.colors = r.get_array<Vec4f>(c.vertices, "colours");
}

void read_nodes(binary::Reader& r, const Counts& c, McOctree& t) {
    if (c.nodes > r.left() / node_bytes) r.fail("truncated: the file ends inside the nodes");
    t.nodes.resize(static_cast<std::size_t>(c.nodes));
    for (McNode& n : t.nodes) {
        n.x = r.get<std::uint32_t>("nodes"), n.y = r.get<std::uint32_t>("nodes"), n.z = r.get<std::uint32_t>("nodes");
        n.level = r.get<std::uint8_t>("nodes"), n.child_mask = r.get<std::uint8_t>("nodes");
        if (r.get<std::uint16_t>("nodes") != 0) r.fail("corrupt marching-cube octree: reserved node bytes are not zero");
        n.first_child = r.get<std::uint32_t>("nodes"), n.parent = r.get<std::uint32_t>("nodes");
        n.inside = r.get<std::uint32_t>("nodes");
        n.crossings = r.get<std::uint64_t>("nodes");
        n.first_vertex = r.get<std::uint32_t>("nodes"), n.priority = r.get<std::uint32_t>("nodes");
    }
    t.vertex_ids = r.get_array<std::uint32_t>(c.ids, "vertex indices");
    t.neighbours = r.get_array<std::uint32_t>(c.nodes * mc::neighbour_slots, "neighbours");
}

void read_priorities(binary::Reader& r, const Counts& c, McOctree& t) {
    t.order = r.get_array<std::uint32_t>(c.order, "priority order");
    t.cuts = r.get_array<std::uint32_t>(c.cuts, "priority levels");
    t.triangle_counts = r.get_array<std::uint64_t>(c.cuts, "triangle counts");
    t.metric = r.get_array<float>(c.nodes, "metric");
}

void read_warnings(binary::Reader& r, const Counts& c, McOctree& t) {
    if (c.warnings > r.left() / 4) r.fail("truncated: the file ends inside the warnings");
    for (std::uint64_t i = 0; i < c.warnings; ++i) {
        const auto len = r.get<std::uint32_t>("warnings");
        t.warnings.push_back(r.get_string(len, "warnings"));
    }
}

// Version 2: magic, version, the payloads of HEAD..WARN back to back, FNV-1a of everything before it.
void read_flat(const std::vector<std::uint8_t>& buf, const std::string& path, McOctree& t) {
    std::uint64_t stored = 0;
    if (buf.size() >= 24) std::memcpy(&stored, buf.data() + buf.size() - 8, 8);
    if (buf.size() < 24 || binary::legacy_fnv1a(buf.data(), buf.size() - 8, binary::fnv1a_basis) != stored)
        throw_error(Error::Kind::format, path, "checksum mismatch: the file is truncated or corrupt");
    binary::Reader r(buf.data() + 12, buf.size() - 20, path, 12);
    const Counts c = read_head(r, t);
    read_vertices(r, c, t);
    read_nodes(r, c, t);
    read_priorities(r, c, t);
    read_warnings(r, c, t);
    r.expect_end("warnings");
}

}  // namespace

McOctree read_mc_octree(const std::string& path, Progress* progress) {
    check_progress(progress, 0, "mcoctree: reading");
    const std::vector<std::uint8_t> buf = binary::read_file(path, "a .mco file");
    const std::uint32_t ver = binary::peek_version(buf, path, magic, "marching-cube octree (.mco)");
    McOctree t;
    if (ver == flat_version) {
        read_flat(buf, path, t);
    } else if (ver == version) {
        const auto sec = binary::read_container(buf, path, magic, ".mco", {"HEAD", "VERT", "NODE", "PRIO", "WARN"});
        binary::Reader head = sec[0].reader(path), vert = sec[1].reader(path), node = sec[2].reader(path),
                       prio = sec[3].reader(path), warn = sec[4].reader(path);
        const Counts c = read_head(head, t);
        head.expect_end("header");
        read_vertices(vert, c, t);
        vert.expect_end("vertices");
        read_nodes(node, c, t);
        node.expect_end("neighbours");
        read_priorities(prio, c, t);
        prio.expect_end("metric");
        read_warnings(warn, c, t);
        warn.expect_end("warnings");
    } else {
        throw_error(Error::Kind::unsupported, path, "unsupported .mco version " + std::to_string(ver) +
                                                        " (this build reads " + std::to_string(flat_version) + " and " +
                                                        std::to_string(version) + ")");
    }
    validate_mc_octree(t, path);
    check_progress(progress, 1, "mcoctree: reading");
    return t;
}

}  // namespace lodforge
