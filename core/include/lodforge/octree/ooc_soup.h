// Streaming conversion of an indexed PLY of any size into a triangle soup on disk, within a memory
// budget: the first step of the out-of-core octree pipeline (docs/octree.md, "Triangle soup").
//
//     TempDirectory scratch(TempDirectory::beside("out.lfo"));   // lodforge/io/temp_directory.h
//     SoupResult s = convert_to_soup("scan.ply", scratch.file("soup"), {.memory_bytes = 16 << 20});
//     SoupReader r(s.path);  while (std::size_t n = r.read(65536, buffer)) ...
//
// Every soup triangle carries its three full vertex records (input vertex index, position, and the
// normals / RGBA colours / texcoords the PLY has), so later stages never need the vertex table again.
// When the vertex table fits in half the budget the conversion is one pass over the PLY; otherwise it
// is a two-level distribution sort on the dense keys (vertex index, then corner index): 3 passes over
// the data whatever its size, no comparison sort, no merge phase.
#pragma once

#include "lodforge/error.h"
#include "lodforge/progress.h"
#include "lodforge/types.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace lodforge {

// Which attributes each vertex record carries, and how many floats that is. Colours are always RGBA.
struct VertexLayout {
    bool normals = false;
    bool colors = false;
    bool texcoords = false;
    // The face's material index (a PLY face `texnumber`), stored as a float after the texcoords: a
    // label, never interpolated (not in the quadric attributes); vertices of different materials are
    // different vertices, so a material border is kept like a UV seam (docs/octree.md).
    bool material = false;

    std::size_t floats() const { return 3 + (normals ? 3 : 0) + (colors ? 4 : 0) + (texcoords ? 2 : 0) + (material ? 1 : 0); }
    std::size_t normal_offset() const { return 3; }
    std::size_t color_offset() const { return 3 + (normals ? 3 : 0); }
    std::size_t texcoord_offset() const { return color_offset() + (colors ? 4 : 0); }
    std::size_t material_offset() const { return texcoord_offset() + (texcoords ? 2 : 0); }
    // Bit 8 is taken by the wedge-texcoord flag of the soup and .lfo headers.
    std::uint32_t flags() const {
        return (normals ? 1u : 0u) | (colors ? 2u : 0u) | (texcoords ? 4u : 0u) | (material ? 16u : 0u);
    }
    static VertexLayout from_flags(std::uint32_t f) { return {(f & 1u) != 0, (f & 2u) != 0, (f & 4u) != 0, (f & 16u) != 0}; }
    friend bool operator==(const VertexLayout&, const VertexLayout&) = default;
};

// One soup corner on disk: uint32 input vertex index, then layout.floats() float32 (little endian).
inline std::size_t soup_corner_bytes(const VertexLayout& layout) { return 4 + 4 * layout.floats(); }
inline std::size_t soup_triangle_bytes(const VertexLayout& layout) { return 3 * soup_corner_bytes(layout); }

// A run of `count` triangle records in a temporary file, from byte `offset` on.
struct SoupRegion {
    std::string path;
    std::uint64_t offset = 0;
    std::uint64_t count = 0;
};

// What SoupParams::root_split answers: split the root about `mid` (its cell's midpoint), or not.
struct SoupRootSplit {
    bool split = false;
    std::array<double, 3> mid{};
};

struct SoupParams {
    std::size_t memory_bytes = std::size_t{256} << 20;  // working memory for the conversion
    // Find the odd non-manifold edges (SoupResult::odd_non_manifold_edges), which the octree needs
    // for watertight cuts; OoCS does not and skips the extra pass.
    bool count_edges = true;
    // When > 0: on the in-memory path, soup records up to this many bytes are returned in
    // SoupResult::memory instead of being written (the octree builder asks for this when the whole soup
    // would be processed in memory anyway); larger soups are written as usual.
    std::size_t memory_soup_bytes = 0;
    // 2: an ASCII PLY is parsed on two threads, and the external path's dereference and assembly passes
    // run on two threads (same soup bytes as with 1).
    int threads = 2;
    // In-memory path: the edge keys are sorted on background threads after convert_to_soup returns, so
    // that the caller's first steps overlap the sort. SoupResult::wait_edges() must then be called before
    // the two edge lists are read and before the temporary directory is removed. The sort reports no
    // progress and is not cancelled (it takes a fraction of the conversion).
    bool background_edges = false;
    // External path: asked once the soup's bounds, triangle count and layout are known (after the
    // dereference pass). When it answers split, the assembly pass writes every triangle straight into the
    // file of its octant about `mid` (the octant of its centroid, in double, ties to the upper half: the
    // octree's streaming split) instead of writing the soup file: SoupResult::octants, and `path` names no
    // file. The octree builder asks for this to save a write and two reads of the whole soup.
    std::function<SoupRootSplit(const Bounds& bounds, std::uint64_t triangles, const VertexLayout& layout)> root_split;
};

struct SoupEdgeJob;  // edge keys being sorted in the background (SoupParams::background_edges)

struct SoupResult {
    std::string path;
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;  // as stored in the PLY
    VertexLayout layout;
    // The texcoords are the face's wedge (per-corner) UVs, not the vertex's: one input vertex may then
    // carry different records in different triangles (split by UV in the octree, docs/octree.md).
    bool wedge_texcoords = false;
    Bounds bounds;                // of the vertices the triangles use
    bool external = false;        // false: the vertex table fitted in memory (one pass)
    int passes = 1;               // passes over the data (1, or 3 for the external path)
    std::uint64_t skipped_faces = 0;    // faces with fewer than 3 corners
    std::uint64_t temp_bytes_peak = 0;  // largest temporary file set on disk at one time
    // Edges (min vertex << 32 | max vertex) used by an odd number ≥ 3 of non-degenerate triangles,
    // sorted: the octree keeps every use of these in every node mesh (docs/octree.md).
    std::vector<std::uint64_t> odd_non_manifold_edges;
    // Edges used by exactly one non-degenerate triangle (the input's borders), same keys, sorted: shared
    // with no other node, so coarse levels may simplify them (docs/octree.md, "Coarse levels").
    std::vector<std::uint64_t> border_edges;
    // The triangle records (the file's body, without its header) when they were kept in memory
    // (SoupParams::memory_soup_bytes); `path` then names no file.
    std::vector<std::byte> memory;
    bool kept_in_memory = false;  // stays true after the builder has consumed (and freed) `memory`
    // SoupParams::root_split was answered with a split: octant o's triangles, in soup order, are the
    // concatenation of octants[o] (octant_counts[o] in all); the files are in the temporary directory.
    bool root_split = false;
    std::array<std::vector<SoupRegion>, 8> octants;
    std::array<std::uint64_t, 8> octant_counts{};
    // Set while the edge lists are still being sorted (SoupParams::background_edges).
    std::shared_ptr<SoupEdgeJob> edge_job;
    // Waits for a background sort and fills the two edge lists (rethrows its error); no-op otherwise.
    void wait_edges();
};

// Throws Error(io / format / invalid) for unreadable, malformed or unusable input (no triangles, no
// vertices, more than 2^32-2 vertices), Error(argument) for a budget under 4 MB, Error(cancelled).
// Temporary files go next to `soup_path` and are removed before returning or throwing.
SoupResult convert_to_soup(const std::string& ply_path, const std::string& soup_path, const SoupParams& params = {},
                           Progress* progress = nullptr);

// Sequential reader of a soup file written by convert_to_soup.
class SoupReader {
public:
    explicit SoupReader(const std::string& path);
    ~SoupReader();
    SoupReader(const SoupReader&) = delete;
    SoupReader& operator=(const SoupReader&) = delete;

    const VertexLayout& layout() const { return layout_; }
    std::uint64_t triangles() const { return triangles_; }
    std::uint64_t vertices() const { return vertices_; }
    const Bounds& bounds() const { return bounds_; }
    bool wedge_texcoords() const { return wedge_texcoords_; }
    std::uint64_t position() const { return next_; }  // triangles read so far
    // Reads up to max_triangles records into `out` (resized); returns how many (0 at the end).
    std::size_t read(std::size_t max_triangles, std::vector<std::byte>& out);
    void rewind() { next_ = 0; }

private:
    int fd_ = -1;
    std::string path_;
    VertexLayout layout_;
    bool wedge_texcoords_ = false;
    std::uint64_t triangles_ = 0, vertices_ = 0, next_ = 0;
    Bounds bounds_;
};

}  // namespace lodforge
