// The octree LOD asset: header, node table and node meshes (docs/formats/lfo.md), read with a
// bounded LRU cache so a run-time cut over a model larger than memory only holds the nodes it draws
// (Bade et al. 2006, §3.6: node data is loaded from disk on demand).
#include "lodforge/octree/octree_store.h"

#include "lodforge/error.h"
#include "lodforge/io/input_file.h"

#include "octree/octree_format.h"
#include "octree/ooc_internal.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace lodforge {

std::vector<char> encode_node_mesh(const NodeMesh& mesh) {
    const std::size_t f = mesh.layout.floats();
    ooc::NodeChunkHeader h{ooc::kNodeChunkMagic, static_cast<std::uint32_t>(mesh.vertex_count()),
                           static_cast<std::uint32_t>(mesh.triangle_count()), static_cast<std::uint32_t>(f)};
    std::vector<char> out(sizeof h + mesh.keys.size() * 8 + mesh.vertices.size() * 4 + mesh.indices.size() * 4);
    char* p = out.data();
    std::memcpy(p, &h, sizeof h);
    p += sizeof h;
    std::memcpy(p, mesh.keys.data(), mesh.keys.size() * 8);
    p += mesh.keys.size() * 8;
    std::memcpy(p, mesh.vertices.data(), mesh.vertices.size() * 4);
    p += mesh.vertices.size() * 4;
    std::memcpy(p, mesh.indices.data(), mesh.indices.size() * 4);
    return out;
}

namespace {

[[noreturn]] void corrupt(const std::string& path, const std::string& what) {
    throw_error(Error::Kind::format, path, "damaged octree asset: " + what);
}

}  // namespace

OctreeStore::OctreeStore(const std::string& path, std::size_t cache_bytes) : path_(path), cache_limit_(cache_bytes) {
    check_input_file(path, "an octree asset");
    ooc::File f(path, O_RDONLY);
    file_size_ = f.size();
    ooc::AssetHeader h{};
    if (file_size_ < sizeof h + sizeof(ooc::AssetFooter))
        throw_error(Error::Kind::format, path, "not an octree asset (too short: " + std::to_string(file_size_) + " bytes)");
    f.read_at(&h, sizeof h, 0);
    if (std::memcmp(h.magic, ooc::kAssetMagic, 8) != 0) throw_error(Error::Kind::format, path, "not an octree asset (bad magic)");
    if (h.version < ooc::kAssetVersion)
        throw_error(Error::Kind::unsupported, path, "octree asset version " + std::to_string(h.version) +
                                                        " was written by an older LodForge without checksums (this build reads "
                                                        "version " + std::to_string(ooc::kAssetVersion) +
                                                        "); rebuild it with `lodforge octree build`");
    if (h.version != ooc::kAssetVersion)
        throw_error(Error::Kind::unsupported, path, "octree asset version " + std::to_string(h.version) +
                                                        " (this build reads version " + std::to_string(ooc::kAssetVersion) + ")");
    {
        ooc::AssetHeader zeroed = h;
        zeroed.header_crc = 0;
        if (ooc::chunk_crc({reinterpret_cast<const char*>(&zeroed), sizeof zeroed}) != h.header_crc)
            corrupt(path, "header checksum mismatch");
    }
    ooc::AssetFooter foot{};
    f.read_at(&foot, sizeof foot, file_size_ - sizeof foot);
    if (std::memcmp(foot.magic, ooc::kAssetEndMagic, 8) != 0 || foot.table_offset != h.table_offset)
        corrupt(path, "truncated or unfinished (no end marker)");
    if (h.node_count == 0 || h.node_count > (file_size_ / sizeof(OctreeNode)) ||
        h.table_offset + h.node_count * sizeof(OctreeNode) + sizeof foot != file_size_)
        corrupt(path, "node table does not fit the file");
    header_.version = h.version;
    header_.layout = VertexLayout::from_flags(h.layout);
    header_.wedge_texcoords = (h.layout & 8u) != 0;
    header_.input_vertices = h.input_vertices;
    header_.input_triangles = h.input_triangles;
    header_.max_triangles = h.max_triangles;
    header_.max_depth = h.max_depth;
    header_.bounds.add({h.bounds[0], h.bounds[1], h.bounds[2]});
    header_.bounds.add({h.bounds[3], h.bounds[4], h.bounds[5]});
    std::copy(h.root_min, h.root_min + 3, header_.root_min);
    header_.root_size = h.root_size;
    header_.node_count = h.node_count;
    header_.table_offset = h.table_offset;
    header_.weights.normal = h.weights[0];
    header_.weights.color = h.weights[1];
    header_.weights.texcoord = h.weights[2];
    nodes_.resize(static_cast<std::size_t>(h.node_count));
    f.read_at(nodes_.data(), nodes_.size() * sizeof(OctreeNode), h.table_offset);
    if (ooc::chunk_crc({reinterpret_cast<const char*>(nodes_.data()), nodes_.size() * sizeof(OctreeNode)}) != h.table_crc)
        corrupt(path, "node table checksum mismatch");
    // The table must describe a tree: children after their parent, inside the table, data in the file.
    const std::size_t n = nodes_.size();
    for (std::size_t i = 0; i < n; ++i) {
        const OctreeNode& d = nodes_[i];
        const std::string at = "node " + std::to_string(i);
        if (d.child_mask) {
            if (d.first_child <= i || d.first_child + static_cast<std::uint64_t>(d.child_count()) > n)
                corrupt(path, at + " has children outside the table");
            for (int c = 0; c < d.child_count(); ++c)
                if (nodes_[d.first_child + c].parent != i) corrupt(path, at + ": child does not point back");
        } else if (d.raw_bytes == 0 && d.raw_triangles != 0) {
            corrupt(path, at + " is a leaf without its triangles");
        }
        // Written so that no sum can wrap: offset + bytes did, and a chunk "ending" before the table was
        // then read from an offset near 2^64 into a buffer of that many bytes.
        const auto past = [&](std::uint64_t offset, std::uint64_t bytes) {
            return bytes > h.table_offset || offset > h.table_offset - bytes;
        };
        if (past(d.raw_offset, d.raw_bytes) || past(d.mesh_offset, d.mesh_bytes))
            corrupt(path, at + " points past the data section");
        if (!(std::isfinite(d.error) && d.error >= 0.f)) corrupt(path, at + " has an invalid error");
    }
    if (nodes_[0].parent != ~0u) corrupt(path, "node 0 is not the root");
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw_error(Error::Kind::io, path, std::string("cannot open: ") + std::strerror(errno));
}

OctreeStore::~OctreeStore() {
    if (fd_ >= 0) ::close(fd_);
}

std::vector<std::uint32_t> OctreeStore::children(std::uint32_t i) const {
    std::vector<std::uint32_t> out;
    const OctreeNode& d = nodes_.at(i);
    for (int c = 0; c < d.child_count(); ++c) out.push_back(d.first_child + static_cast<std::uint32_t>(c));
    return out;
}

OctreeStats OctreeStore::stats() const {
    OctreeStats s;
    s.nodes = nodes_.size();
    s.input_triangles = header_.input_triangles;
    s.file_bytes = file_size_;
    s.height = nodes_.empty() ? 0 : nodes_[0].height;
    for (const OctreeNode& d : nodes_) {
        s.depth_reached = std::max<int>(s.depth_reached, d.depth);
        if (!d.is_leaf()) continue;
        ++s.leaves;
        s.max_leaf_triangles = std::max<std::size_t>(s.max_leaf_triangles, d.raw_triangles);
        if (s.leaves_per_depth.size() <= d.depth) {
            s.leaves_per_depth.resize(d.depth + 1u, 0);
            s.triangles_per_depth.resize(d.depth + 1u, 0);
        }
        ++s.leaves_per_depth[d.depth];
        s.triangles_per_depth[d.depth] += d.raw_triangles;
    }
    for (int level = 0; level < level_count(); ++level) {
        std::uint64_t t = 0;
        for (const CutNode& c : level_cut(*this, level)) t += c.raw ? nodes_[c.node].raw_triangles : nodes_[c.node].mesh_triangles;
        s.triangles_per_level.push_back(t);
    }
    return s;
}

std::vector<OctreeCell> OctreeStore::cells() const {
    std::vector<OctreeCell> out(nodes_.size());
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const OctreeNode& d = nodes_[i];
        OctreeCell& c = out[i];
        c.node = static_cast<std::uint32_t>(i);
        std::copy(d.cell_min, d.cell_min + 3, c.min);
        c.size = d.cell_size;
        c.depth = d.depth;
        c.height = d.height;
        c.leaf = d.is_leaf();
        c.triangles = d.subtree_triangles;
    }
    return out;
}

std::shared_ptr<const NodeMesh> OctreeStore::load(std::uint32_t node, bool raw) {
    if (node >= nodes_.size()) throw Error(Error::Kind::argument, path_ + ": no node " + std::to_string(node));
    const OctreeNode& d = nodes_[node];
    if (raw && !d.is_leaf())
        throw Error(Error::Kind::argument, path_ + ": node " + std::to_string(node) + " is not a leaf (no raw level)");
    const std::uint64_t key = (std::uint64_t{node} << 1) | (raw ? 1u : 0u);
    if (auto it = cache_.find(key); it != cache_.end()) {
        ++hits_;
        lru_.splice(lru_.begin(), lru_, it->second.lru);
        return it->second.mesh;
    }
    ++misses_;
    const std::uint64_t offset = raw ? d.raw_offset : d.mesh_offset;
    const std::uint64_t bytes = raw ? d.raw_bytes : d.mesh_bytes;
    const std::string at = "node " + std::to_string(node);
    auto mesh = std::make_shared<NodeMesh>();
    mesh->layout = header_.layout;
    if (bytes == 0) {
        // An empty node mesh (a node whose input vanished entirely) is stored as nothing.
    } else {
        std::vector<char> buf(static_cast<std::size_t>(bytes));
        ooc::File::read_at_fd(fd_, path_, buf.data(), buf.size(), offset);
        if (ooc::chunk_crc(buf) != (raw ? d.raw_crc : d.mesh_crc)) corrupt(path_, at + ": mesh chunk checksum mismatch");
        ooc::NodeChunkHeader h{};
        if (buf.size() < sizeof h) corrupt(path_, at + ": mesh chunk too short");
        std::memcpy(&h, buf.data(), sizeof h);
        const std::size_t f = header_.layout.floats();
        if (h.magic != ooc::kNodeChunkMagic || h.floats != f ||
            sizeof h + std::uint64_t{h.vertices} * (8 + 4 * f) + std::uint64_t{h.triangles} * 12 != bytes)
            corrupt(path_, at + ": mesh chunk header does not match its size");
        if (h.triangles != (raw ? d.raw_triangles : d.mesh_triangles)) corrupt(path_, at + ": triangle count mismatch");
        const char* p = buf.data() + sizeof h;
        mesh->keys.resize(h.vertices);
        std::memcpy(mesh->keys.data(), p, mesh->keys.size() * 8);
        p += mesh->keys.size() * 8;
        mesh->vertices.resize(std::size_t{h.vertices} * f);
        std::memcpy(mesh->vertices.data(), p, mesh->vertices.size() * 4);
        p += mesh->vertices.size() * 4;
        mesh->indices.resize(std::size_t{h.triangles} * 3);
        std::memcpy(mesh->indices.data(), p, mesh->indices.size() * 4);
        for (std::uint32_t i : mesh->indices)
            if (i >= h.vertices) corrupt(path_, at + ": vertex index out of range");
        for (float v : mesh->vertices)
            if (!std::isfinite(v)) corrupt(path_, at + ": non-finite vertex data");
    }
    Entry e;
    e.mesh = mesh;
    e.bytes = mesh->memory_bytes() + 64;
    while (!lru_.empty() && cached_bytes_ + e.bytes > cache_limit_) {
        auto victim = cache_.find(lru_.back());
        cached_bytes_ -= victim->second.bytes;
        cache_.erase(victim);
        lru_.pop_back();
    }
    if (e.bytes <= cache_limit_) {
        lru_.push_front(key);
        e.lru = lru_.begin();
        cached_bytes_ += e.bytes;
        cache_.emplace(key, std::move(e));
    }
    return mesh;
}

Cut level_cut(const OctreeStore& store, int level) {
    if (level < 0 || level >= store.level_count())
        throw Error(Error::Kind::argument, store.path() + ": level " + std::to_string(level) + " does not exist (levels 0.." +
                                               std::to_string(store.level_count() - 1) + ")");
    Cut cut;
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
        const std::uint32_t i = stack.back();
        stack.pop_back();
        const OctreeNode& d = store.node(i);
        if (level == 0 && d.is_leaf()) {
            cut.push_back({i, true});
        } else if (level > 0 && d.height < level) {
            cut.push_back({i, false});
        } else {
            for (int c = d.child_count() - 1; c >= 0; --c) stack.push_back(d.first_child + static_cast<std::uint32_t>(c));
        }
    }
    return cut;
}

bool is_valid_cut(const OctreeStore& store, const Cut& cut, bool allow_gaps) {
    const std::size_t n = store.nodes().size();
    std::vector<std::uint8_t> in(n, 0);
    for (const CutNode& c : cut) {
        if (c.node >= n || in[c.node]) return false;
        if (c.raw && !store.node(c.node).is_leaf()) return false;
        in[c.node] = 1;
    }
    // covered[i]: the number of cut nodes on the path root..i; every leaf must see exactly 1.
    std::vector<std::uint8_t> covered(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const OctreeNode& d = store.node(static_cast<std::uint32_t>(i));
        const int above = d.parent == ~0u ? 0 : covered[d.parent];
        const int here = above + in[i];
        if (here > 1) return false;
        covered[i] = static_cast<std::uint8_t>(here);
        if (d.is_leaf() && here == 0 && !allow_gaps) return false;
    }
    return true;
}

Mesh extract_mesh(OctreeStore& store, const Cut& cut, Progress* progress, std::vector<std::uint64_t>* keys) {
    if (keys) keys->clear();
    const VertexLayout& L = store.header().layout;
    Mesh out;
    ooc::FlatMap map(1024);
    std::vector<std::uint32_t> local;
    for (std::size_t ci = 0; ci < cut.size(); ++ci) {
        if ((ci & 63) == 0) check_progress(progress, static_cast<double>(ci) / std::max<std::size_t>(cut.size(), 1), "octree: extracting");
        const std::shared_ptr<const NodeMesh> m = store.load(cut[ci].node, cut[ci].raw);
        local.resize(m->vertex_count());
        for (std::size_t i = 0; i < m->vertex_count(); ++i) {
            bool inserted = false;
            std::uint32_t& v = map.find_or_insert(m->keys[i], static_cast<std::uint32_t>(out.positions.size()), inserted);
            if (inserted) {
                const float* r = m->vertex(i);
                if (keys) keys->push_back(m->keys[i]);
                out.positions.push_back({r[0], r[1], r[2]});
                if (L.normals) {
                    const float* n = r + L.normal_offset();
                    out.normals.push_back({n[0], n[1], n[2]});
                }
                if (L.colors) {
                    const float* c = r + L.color_offset();
                    out.colors.push_back({c[0], c[1], c[2], c[3]});
                }
                if (L.texcoords) {
                    if (out.texcoords.empty()) out.texcoords.resize(1);
                    const float* t = r + L.texcoord_offset();
                    out.texcoords[0].push_back({t[0], t[1]});
                }
            }
            local[i] = v;
        }
        for (std::uint32_t i : m->indices) out.indices.push_back(local[i]);
    }
    check_progress(progress, 1.0, "octree: extracting");
    return out;
}

}  // namespace lodforge
