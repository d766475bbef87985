// PLY (Stanford polygon file format) reading and writing: ASCII, binary little and big endian.
//
// Two layers. `read_ply`/`write_ply` move a whole Mesh. Under them, `PlyReader` streams a file element
// by element in caller-sized chunks without ever holding the file in memory, so the out-of-core builder
// can read meshes larger than RAM with the same parser (and the same error messages) as the importer.
// Every problem with the input is reported as lodforge::Error naming the file, the element and the byte
// offset (binary) or line (ASCII). Lying headers never cause big allocations: element counts are checked
// against the file size before anything is reserved. Supported variants and the rules for polygons,
// triangle strips and wedge texcoords are described in docs/ply.md.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/progress.h"
#include "lodforge/types.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace lodforge {

// Reads a whole PLY file. Positions (x y z) are required; normals, colours (uchar / 255 or float),
// texcoords (u v, s t, texture_u texture_v, ...) and MeshLab wedge texcoords (face `texcoord` lists)
// are taken when present; wedges are split as the Mesh contract says (stored vertex i stays vertex i).
// Polygons are fan-triangulated, `tristrips` elements expanded, faces with fewer than 3 corners dropped.
Mesh read_ply(const std::string& path, Progress* progress = nullptr);

// Writes positions, and as the options allow normals, colours (uchar or float, RGBA) and texcoord set 0
// (u v per vertex), triangles as `vertex_indices` (uchar count, int indices), and `comment TextureFile`
// for the first material's base colour texture path. Goes through AtomicFile: on any failure (disk
// full, cancel) the target is untouched and Error(io / cancelled) names the file.
void write_ply(const Mesh& mesh, const std::string& path, const WriteOptions& options = {},
               Progress* progress = nullptr);

// ---- Header model ----------------------------------------------------------------------------------

enum class PlyType : std::uint8_t { none, int8, uint8, int16, uint16, int32, uint32, float32, float64 };

std::size_t ply_type_size(PlyType type);  // bytes in binary files; 0 for none
const char* ply_type_name(PlyType type);  // "char", "uchar", "short", ..., "double" ("" for none)

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::none;        // the scalar type, or the item type of a list
    PlyType count_type = PlyType::none;  // the list length type; none for a scalar property

    bool is_list() const { return count_type != PlyType::none; }
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;

    int find_property(std::string_view property_name) const;  // index, or -1 when absent
};

struct PlyHeader {
    PlyEncoding format = PlyEncoding::ascii;
    std::string version;               // as written, normally "1.0"
    std::vector<PlyElement> elements;  // in file order, which is also the order of the data
    std::vector<std::string> comments; // text after "comment ", TextureFile lines included
    std::vector<std::string> obj_info; // text after "obj_info "
    // Paths from "comment TextureFile <path>", in order; a face's `texnumber` indexes this list.
    std::vector<std::string> texture_files;
    std::uint64_t data_offset = 0;     // byte offset of the first data byte (just after end_header)
    std::uint64_t header_lines = 0;    // lines up to and including end_header (ASCII line numbers)

    const PlyElement* find_element(std::string_view element_name) const;  // nullptr when absent
};

// ---- Streaming reader ------------------------------------------------------------------------------

// Which vertex attributes the file has (what read_vertices can fill).
struct PlyVertexAttributes {
    bool normals = false;    // nx ny nz
    bool colors = false;     // red green blue (or diffuse_*)
    bool alpha = false;      // alpha (else colours come out with alpha 1)
    bool texcoords = false;  // one of the u/v, s/t, texture_u/texture_v, texture_s/texture_t pairs
};

// Triangles produced by PlyReader::read_faces. Appended to, never cleared by the reader, so a caller
// may accumulate a whole file or clear() between chunks.
struct PlyFaceChunk {
    std::vector<std::uint32_t> indices;  // 3 per triangle, winding as in the file
    // 3 per triangle when the face element has a `texcoord` list (MeshLab wedge UVs), else empty.
    // NaN marks a corner of a face whose list is empty (no wedge UV for that face).
    std::vector<Vec2f> corner_texcoords;
    std::vector<std::int64_t> texnumbers;  // 1 per triangle when the face element has `texnumber`
    std::uint64_t faces_read = 0;            // face (or strip) records consumed
    std::uint64_t skipped_faces = 0;         // faces with fewer than 3 corners, dropped
    std::uint64_t dropped_strip_triangles = 0;  // degenerate triangles of `tristrips`, dropped

    std::size_t triangle_count() const { return indices.size() / 3; }
    void clear();
};

// Reads a PLY file sequentially. The constructor parses the header and checks that the announced
// element counts fit in the file; then the data is consumed element by element, in file order:
//
//     PlyReader reader(path);
//     while (const PlyElement* element = reader.current_element()) {
//         if (reader.at_vertices())   reader.read_vertices(positions_chunk, normals_chunk);
//         else if (reader.at_faces()) reader.read_faces(65536, faces);
//         else                        reader.skip_element();
//     }
//
// Only a fixed-size buffer is held (grown only for a single record larger than it). Not thread-safe.
class PlyReader {
public:
    // Opens a file; throws Error(io) when it cannot be read, Error(format) for a bad header.
    explicit PlyReader(const std::string& path);
    // Reads from memory (not copied: `data` must outlive the reader). `name` is used in messages.
    PlyReader(std::span<const std::byte> data, std::string name);
    ~PlyReader();
    PlyReader(PlyReader&&) noexcept;
    PlyReader& operator=(PlyReader&&) noexcept;

    const PlyHeader& header() const;
    const std::string& path() const;  // file name (or the memory buffer's name)
    std::uint64_t file_size() const;
    std::uint64_t position() const;   // byte offset of the next unread byte

    // The element the next record belongs to; nullptr once all data is read. Empty elements are passed.
    const PlyElement* current_element() const;
    std::uint64_t remaining() const;  // records of current_element() not read yet
    bool at_vertices() const;         // current element is "vertex"
    bool at_faces() const;            // current element is "face" or "tristrips"

    std::uint64_t vertex_count() const;  // from the header; 0 without a vertex element
    PlyVertexAttributes vertex_attributes() const;
    bool has_corner_texcoords() const;   // the face element has a `texcoord` list
    bool has_texnumbers() const;         // the face element has `texnumber`

    // Reads min(positions.size(), remaining()) vertices. Attribute spans are optional (empty = not
    // wanted) and otherwise at least as long as `positions`; attributes the file lacks are left as they
    // are. Colours come out as RGBA in [0, 1]. Throws Error(invalid) for a NaN/Inf position.
    std::size_t read_vertices(std::span<Vec3f> positions, std::span<Vec3f> normals = {},
                              std::span<Vec4f> colors = {}, std::span<Vec2f> texcoords = {});

    // Reads up to `max_records` records of the current face or tristrips element and appends their
    // triangles. Checks every index against vertex_count() (Error(invalid) naming the face).
    // Returns the number of records consumed.
    std::size_t read_faces(std::size_t max_records, PlyFaceChunk& out);

    // Skips the rest of the current element (binary files with fixed-size records skip in one seek).
    void skip_element();

    // ASCII records are one per line. Moves an ASCII reader forward to `byte_offset`, the start of a
    // line such that only blank lines precede record `record` of element `element` from there; `line` is
    // the number of newlines before `byte_offset` (for messages). Lets several readers of one file parse
    // parts of an element on different threads. Error(argument) for a binary file or a backward move.
    void seek_ascii_record(std::size_t element, std::uint64_t record, std::uint64_t byte_offset, std::uint64_t line);
    std::uint64_t line() const;  // ASCII: newlines consumed so far, header included

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Builds a whole Mesh from a freshly opened reader (what read_ply(path) does). Relative texture paths
// are resolved against the directory of reader.path().
Mesh read_ply(PlyReader& reader, Progress* progress = nullptr);

}  // namespace lodforge
