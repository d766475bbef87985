// Artist paint for one mesh (docs/artist-control.md, format in docs/formats/paint.md): per-vertex
// importance in [0, 1] and a lock mask, as SimplifyParams::importance and ::lock take them. A paint file
// names the SHA-256 of the mesh file it was painted on and its vertex count, so paint never lands on
// another mesh or on the same file read with another vertex layout.
//
//   VertexPaint paint = read_vertex_paint("spot.paint.json", sha256_file("spot.obj"), mesh.vertex_count());
//   params.importance = paint.importance;   params.lock = paint.lock;
#pragma once

#include "lodforge/mesh.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

struct VertexPaint {
    std::vector<float> importance;     // one per vertex, in [0, 1]; empty when the file has none
    std::vector<std::uint8_t> lock;    // one per vertex, 0 or 1; empty when the file has none
};

// Throws Error(io) naming `path` when it cannot be read, Error(format) for malformed JSON or a wrong
// "format" or "version", Error(invalid) when mesh_sha256 or vertex_count differ from the file's, an
// importance is not a finite number in [0, 1] or a locked vertex index is out of range.
VertexPaint read_vertex_paint(const std::string& path, const std::string& mesh_sha256, std::size_t vertex_count);
// Atomic write; importance values are written as given (shortest round-trip form).
void write_vertex_paint(const std::string& path, const VertexPaint& paint, const std::string& mesh_sha256,
                        std::size_t vertex_count);

// The SimplifyParams masks named by the CLI's --importance and --lock (and the preset keys of the same
// names): `importance` is a paint file or "color:r|g|b|a" (that vertex-colour channel of the mesh, read
// as importance), `lock` a paint file; empty = none. `mesh_path` is the file `mesh` was read from (its
// hash keys the paint). Throws as read_vertex_paint, Error(argument) for an unknown channel, and
// Error(invalid) for a colour channel asked of a mesh without vertex colours (naming mesh_path) or a
// paint file without the mask asked for (naming it).
void read_paint_sources(const std::string& importance, const std::string& lock, const Mesh& mesh,
                        const std::string& mesh_path, std::vector<float>& importance_out,
                        std::vector<std::uint8_t>& lock_out);

}  // namespace lodforge
