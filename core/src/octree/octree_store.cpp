// The octree LOD asset: header, node table and node meshes (docs/formats/lfo.md), read with a
// bounded LRU cache so a run-time cut over a model larger than memory only holds the nodes it draws
// (Bade et al. 2006, §3.6: node data is loaded from disk on demand).
#include "lodforge/octree/octree_store.h"

#include "lodforge/error.h"
#include "lodforge/io/input_file.h"
#include "lodforge/runtime/lodstrips_runtime.h"

#include "io/binary_io.h"
#include "octree/octree_format.h"
#include "octree/ooc_internal.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace lodforge {

std::vector<std::uint8_t> encode_node_mesh(const NodeMesh& mesh) {
    binary::Writer out;
    out.bytes.reserve(ooc::kNodeChunkHeaderBytes + mesh.keys.size() * 8 + (mesh.vertices.size() + mesh.indices.size()) * 4);
    out.put(ooc::kNodeChunkMagic);
    out.put(static_cast<std::uint32_t>(mesh.vertex_count()));
    out.put(static_cast<std::uint32_t>(mesh.triangle_count()));
    out.put(static_cast<std::uint32_t>(mesh.layout.floats()));
    out.put_array(mesh.keys);
    out.put_array(mesh.vertices);
    out.put_array(mesh.indices);
    return std::move(out.bytes);
}

std::vector<std::uint8_t> encode_octree_index(const OctreeHeader& header, const std::vector<OctreeNode>& nodes) {
    binary::Writer head, table;
    head.put(header.layout.flags() | (header.wedge_texcoords ? 8u : 0u));
    head.put(header.input_vertices);
    head.put(header.input_triangles);
    head.put(header.max_triangles);
    head.put(header.max_depth);
    for (const Vec3f& v : {header.bounds.min, header.bounds.max}) head.put(v);
    for (float v : header.root_min) head.put(v);
    head.put(header.root_size);
    head.put(static_cast<std::uint64_t>(nodes.size()));
    head.put(header.weights.normal);
    head.put(header.weights.color);
    head.put(header.weights.texcoord);
    table.put_array(nodes);
    return binary::write_container(ooc::kAssetMagic, ooc::kAssetVersion, {{"HEAD", &head.bytes}, {"NODE", &table.bytes}});
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
    if (file_size_ < ooc::kAssetLeadBytes + ooc::kAssetFooterBytes)
        throw_error(Error::Kind::format, path, "not an octree asset (too short: " + std::to_string(file_size_) + " bytes)");
    std::uint8_t lead[ooc::kAssetLeadBytes];
    f.read_at(lead, sizeof lead, 0);
    if (std::memcmp(lead, ooc::kAssetMagic, 8) != 0) throw_error(Error::Kind::format, path, "not an octree asset (bad magic)");
    binary::Reader lead_in(lead + 8, sizeof lead - 8, path, 8);
    const auto version = lead_in.get<std::uint32_t>("version");
    if (version < ooc::kAssetVersion)
        throw_error(Error::Kind::unsupported, path, "octree asset version " + std::to_string(version) +
                                                        " was written by an older LodForge (this build reads version " +
                                                        std::to_string(ooc::kAssetVersion) +
                                                        "); rebuild it with `lodforge octree build`");
    if (version != ooc::kAssetVersion)
        throw_error(Error::Kind::unsupported, path, "octree asset version " + std::to_string(version) +
                                                        " (this build reads version " + std::to_string(ooc::kAssetVersion) + ")");
    if (lead_in.get<std::uint32_t>("byte order") != lodstrips::endian_tag) corrupt(path, "bad byte-order tag");
    // The footer locates the index (a binary_io container: HEAD, NODE) between the chunks and itself.
    std::uint8_t foot[ooc::kAssetFooterBytes];
    f.read_at(foot, sizeof foot, file_size_ - sizeof foot);
    std::uint64_t index_offset = 0;
    std::memcpy(&index_offset, foot, 8);
    if (std::memcmp(foot + 8, ooc::kAssetEndMagic, 8) != 0 || index_offset < ooc::kAssetLeadBytes ||
        index_offset > file_size_ - sizeof foot)
        corrupt(path, "truncated or unfinished (no end marker)");
    // The index's own size field must span exactly to the footer before the index is read whole.
    const std::uint64_t index_bytes = file_size_ - sizeof foot - index_offset;
    std::uint64_t declared = 0;
    if (index_bytes >= 32) f.read_at(&declared, sizeof declared, index_offset + 24);
    if (declared != index_bytes) corrupt(path, "the index does not end at the footer");
    std::vector<std::uint8_t> index(static_cast<std::size_t>(index_bytes));
    f.read_at(index.data(), index.size(), index_offset);
    if (binary::peek_version(index, path, ooc::kAssetMagic, "octree asset index") != version)
        corrupt(path, "the index's version differs from the file's");
    const std::vector<binary::Section> sections =
        binary::read_container(index, path, ooc::kAssetMagic, "octree asset index", {"HEAD", "NODE"});
    // Section offsets are inside the index; messages name bytes of the file.
    binary::Reader head(sections[0].data, sections[0].size, path, index_offset + sections[0].offset, "section HEAD");
    binary::Reader table(sections[1].data, sections[1].size, path, index_offset + sections[1].offset, "section NODE");
    header_.version = version;
    const auto layout = head.get<std::uint32_t>("layout flags");
    if (layout > 31u) head.fail("unknown layout flags " + std::to_string(layout));
    header_.layout = VertexLayout::from_flags(layout);
    header_.wedge_texcoords = (layout & 8u) != 0;
    header_.input_vertices = head.get<std::uint64_t>("input vertices");
    header_.input_triangles = head.get<std::uint64_t>("input triangles");
    header_.max_triangles = head.get<std::uint32_t>("max triangles");
    header_.max_depth = head.get<std::uint32_t>("max depth");
    header_.bounds.add(head.get<Vec3f>("bounds"));
    header_.bounds.add(head.get<Vec3f>("bounds"));
    for (float& v : header_.root_min) v = head.get<float>("root cube");
    header_.root_size = head.get<float>("root cube");
    const auto node_count = head.get<std::uint64_t>("node count");
    header_.node_count = node_count;
    header_.table_offset = index_offset;
    header_.weights.normal = head.get<float>("weights");
    header_.weights.color = head.get<float>("weights");
    header_.weights.texcoord = head.get<float>("weights");
    head.expect_end("header fields");
    if (node_count == 0) corrupt(path, "no nodes");
    nodes_ = table.get_array<OctreeNode>(node_count, "node records");
    table.expect_end("node records");
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
        const auto inside = [&](std::uint64_t offset, std::uint64_t bytes) {
            return bytes == 0 || (offset >= ooc::kAssetLeadBytes && offset <= index_offset && bytes <= index_offset - offset);
        };
        if (!inside(d.raw_offset, d.raw_bytes) || !inside(d.mesh_offset, d.mesh_bytes))
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
        std::vector<std::uint8_t> buf(static_cast<std::size_t>(bytes));
        ooc::File::read_at_fd(fd_, path_, buf.data(), buf.size(), offset);
        if (binary::checksum(buf.data(), buf.size()) != (raw ? d.raw_crc : d.mesh_crc))
            corrupt(path_, at + ": mesh chunk checksum mismatch");
        binary::Reader in(buf.data(), buf.size(), path_, static_cast<std::size_t>(offset), at + (raw ? " raw chunk" : " mesh chunk"));
        const auto magic = in.get<std::uint32_t>("chunk magic");
        const auto vertices = in.get<std::uint32_t>("vertex count");
        const auto triangles = in.get<std::uint32_t>("triangle count");
        const std::size_t f = header_.layout.floats();
        if (magic != ooc::kNodeChunkMagic || in.get<std::uint32_t>("floats per vertex") != f)
            corrupt(path_, at + ": mesh chunk header does not match the asset");
        if (triangles != (raw ? d.raw_triangles : d.mesh_triangles)) corrupt(path_, at + ": triangle count mismatch");
        mesh->keys = in.get_array<std::uint64_t>(vertices, "vertex keys");
        mesh->vertices = in.get_array<float>(std::uint64_t{vertices} * f, "vertex records");
        mesh->indices = in.get_array<std::uint32_t>(std::uint64_t{triangles} * 3, "indices");
        in.expect_end("indices");
        for (std::uint32_t i : mesh->indices)
            if (i >= vertices) corrupt(path_, at + ": vertex index out of range");
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
        // Every corner of a triangle carries its face's material (a vertex key includes it).
        if (L.material)
            for (std::size_t t = 0; t < m->indices.size(); t += 3)
                out.face_materials.push_back(static_cast<std::uint32_t>(m->vertex(m->indices[t])[L.material_offset()]));
    }
    // The asset keeps material indices, not the material list: each index gets a default material so
    // the mesh is valid as it is (the pack puts the input's list back).
    if (!out.face_materials.empty())
        out.materials.resize(*std::max_element(out.face_materials.begin(), out.face_materials.end()) + std::size_t{1});
    for (std::size_t i = 0; i < out.materials.size(); ++i) out.materials[i].name = "material " + std::to_string(i);
    check_progress(progress, 1.0, "octree: extracting");
    return out;
}

}  // namespace lodforge
