// The out-of-core octree LOD asset on disk (format: docs/formats/lfo.md, version 3) and its
// reader with a bounded cache of node meshes, shared by `lodforge octree info/extract`, the run-time
// selection (octree_select.h) and the studio.
//
//     OctreeStore store("dragon.lfo");              // reads header and node table, no mesh data
//     OctreeStats s = store.stats();                // nodes, leaves, depth reached, per-level counts
//     Mesh m = extract_mesh(store, level_cut(store, 2));
//
// Levels: level 0 is the input (every leaf's own triangles); level L ≥ 1 takes, on every root-to-leaf
// path, the highest node of height < L (height: 0 for a leaf, 1 + the largest child height above)
// with its simplified mesh. level_count() − 1 is the root alone. A cut may also mix levels freely
// (CutNode per node): the result is crack-free wherever the input was (octree_simplify.h).
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/octree/octree_simplify.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace lodforge {

// One node as stored (little endian, 112 bytes each in the table). Children of a node are contiguous.
struct OctreeNode {
    std::uint32_t first_child = 0;  // index of the first child (valid when child_mask != 0)
    std::uint8_t child_mask = 0;    // bit i: octant i (x = bit 0, y = bit 1, z = bit 2) has a child
    std::uint8_t depth = 0;         // root 0
    std::uint8_t height = 0;        // leaf 0
    std::uint8_t flags = 0;         // bit 0: some component had no boundary edge (closed; clustered)
    std::uint32_t parent = 0;       // ~0 for the root
    std::uint32_t raw_crc = 0;      // CRC-32 of the raw chunk
    float cell_min[3] = {0, 0, 0};  // the node's cube (model units)
    float cell_size = 0;
    float bounds_min[3] = {0, 0, 0};  // bounds of the input triangles under the node (they may stick
    float bounds_max[3] = {0, 0, 0};  // out of the cell: triangles are assigned by centroid)
    float error = 0;                  // geometric error of the simplified mesh, model units (monotone)
    std::uint32_t mesh_crc = 0;       // CRC-32 of the mesh chunk
    std::uint64_t subtree_triangles = 0;  // input triangles under the node
    std::uint64_t raw_offset = 0, raw_bytes = 0;    // leaves: the input triangles (level 0)
    std::uint64_t mesh_offset = 0, mesh_bytes = 0;  // the simplified mesh
    std::uint32_t raw_triangles = 0;
    std::uint32_t mesh_triangles = 0;

    bool is_leaf() const { return child_mask == 0; }
    int child_count() const { return __builtin_popcount(child_mask); }
};
static_assert(sizeof(OctreeNode) == 112);

struct OctreeHeader {
    std::uint32_t version = 1;
    VertexLayout layout;
    // Texcoords are wedge UVs (layout flag 8): a vertex key's bits 32-62 then hash its u v (docs/octree.md).
    bool wedge_texcoords = false;
    std::uint64_t input_vertices = 0;
    std::uint64_t input_triangles = 0;
    std::uint32_t max_triangles = 0;  // the build knobs
    std::uint32_t max_depth = 0;
    Bounds bounds;                    // of the input
    float root_min[3] = {0, 0, 0};    // root cube
    float root_size = 0;
    std::uint64_t node_count = 0;
    std::uint64_t table_offset = 0;   // where the index (these fields and the node table) starts
    SimplifyWeights weights;          // normal, color, texcoord used by the build
};

struct OctreeStats {
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    int depth_reached = 0;
    int height = 0;                                   // of the root; level_count() = height + 2
    std::size_t max_leaf_triangles = 0;
    std::vector<std::uint64_t> leaves_per_depth;      // [depth]
    std::vector<std::uint64_t> triangles_per_depth;   // input triangles in leaves at [depth]
    std::vector<std::uint64_t> triangles_per_level;   // triangles of the whole-model mesh at [level]
    std::uint64_t input_triangles = 0;
    std::uint64_t file_bytes = 0;
};

// A cell for drawing (the studio's wireframe overlay).
struct OctreeCell {
    std::uint32_t node = 0;
    float min[3] = {0, 0, 0};
    float size = 0;
    int depth = 0;
    int height = 0;
    bool leaf = false;
    std::uint64_t triangles = 0;  // input triangles under the node
};

// One node of a cut and which of its meshes: the raw input triangles (leaves only) or simplified.
struct CutNode {
    std::uint32_t node = 0;
    bool raw = false;
};
using Cut = std::vector<CutNode>;

class OctreeStore {
public:
    // Opens an asset; throws Error(io) when unreadable, Error(unsupported) for another version,
    // Error(format) when it is not an asset, is truncated, fails a checksum, or its table is inconsistent. `cache_bytes` bounds the node meshes kept in memory.
    explicit OctreeStore(const std::string& path, std::size_t cache_bytes = std::size_t{64} << 20);
    ~OctreeStore();
    OctreeStore(const OctreeStore&) = delete;
    OctreeStore& operator=(const OctreeStore&) = delete;

    const std::string& path() const { return path_; }
    const OctreeHeader& header() const { return header_; }
    const std::vector<OctreeNode>& nodes() const { return nodes_; }
    const OctreeNode& node(std::uint32_t i) const { return nodes_[i]; }
    std::vector<std::uint32_t> children(std::uint32_t i) const;
    int level_count() const { return nodes_.empty() ? 0 : nodes_[0].height + 2; }
    OctreeStats stats() const;
    std::vector<OctreeCell> cells() const;

    // The mesh of a node (raw: leaves only), from the cache or read from disk. Throws Error(format)
    // when the stored chunk is damaged, Error(argument) for a bad node or raw on an inner node.
    std::shared_ptr<const NodeMesh> load(std::uint32_t node, bool raw);

    std::size_t cache_bytes() const { return cached_bytes_; }
    std::size_t cache_limit() const { return cache_limit_; }
    std::size_t cache_hits() const { return hits_; }
    std::size_t cache_misses() const { return misses_; }

private:
    struct Entry {
        std::shared_ptr<const NodeMesh> mesh;
        std::list<std::uint64_t>::iterator lru;
        std::size_t bytes = 0;
    };
    std::string path_;
    int fd_ = -1;
    std::uint64_t file_size_ = 0;
    OctreeHeader header_;
    std::vector<OctreeNode> nodes_;
    std::size_t cache_limit_;
    std::size_t cached_bytes_ = 0;
    std::size_t hits_ = 0, misses_ = 0;
    std::list<std::uint64_t> lru_;  // most recent first
    std::unordered_map<std::uint64_t, Entry> cache_;
};

// The whole-model cut at `level` (see the top of this file); Error(argument) when out of range.
Cut level_cut(const OctreeStore& store, int level);
// True when every input triangle is covered exactly once: on every root-to-leaf path exactly one node
// is in the cut, raw only on leaves. Nodes culled away are allowed when `allow_gaps`.
bool is_valid_cut(const OctreeStore& store, const Cut& cut, bool allow_gaps = false);
// The cut's triangles as one indexed Mesh; vertices shared between nodes are merged by key, so the
// result is one connected surface. Normals, colours and texcoords as the input had them; with per-face
// materials (layout.material) face_materials, and one default material per index (the asset stores
// indices, not the list: a caller that has the input's materials puts them back). `keys`, when
// given, receives each output vertex's key (input vertex index, or kRepresentativeKey | node).
Mesh extract_mesh(OctreeStore& store, const Cut& cut, Progress* progress = nullptr,
                  std::vector<std::uint64_t>* keys = nullptr);

// Asset writing helpers used by the builder (octree_build.cpp): the bytes of one node mesh chunk, and
// the index (header fields and node table) written after the chunks.
std::vector<std::uint8_t> encode_node_mesh(const NodeMesh& mesh);
std::vector<std::uint8_t> encode_octree_index(const OctreeHeader& header, const std::vector<OctreeNode>& nodes);

}  // namespace lodforge
