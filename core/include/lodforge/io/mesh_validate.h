// Checks a mesh for the defects that break later stages. Importers throw on defects that make a mesh
// unusable (index out of range, non-finite positions); the softer findings (degenerate, duplicate or
// non-manifold faces, unused vertices) are reported here so the CLI `info` and the studio can show them.
#pragma once

#include "lodforge/mesh.h"

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace lodforge {

struct ValidationParams {
    std::size_t max_examples = 5;  // face/vertex indices quoted per finding
};

struct ValidationFinding {
    enum class Severity { error, warning };
    Severity severity = Severity::warning;
    std::string code;     // stable identifier: "index_out_of_range", "non_finite_position", ...
    std::size_t count = 0;
    std::vector<std::size_t> examples;  // first few offending face or vertex indices
    std::string message;  // human sentence, e.g. "12 degenerate triangles (e.g. faces 3, 17)"
};

struct ValidationReport {
    std::vector<ValidationFinding> findings;
    bool has_errors() const;
    const ValidationFinding* find(const std::string& code) const;
};

// Codes: errors "array_size_mismatch", "index_out_of_range", "non_finite_position",
// "non_finite_attribute", "material_out_of_range"; warnings "degenerate_triangle" (repeated index),
// "zero_area_triangle", "duplicate_triangle" (same vertex set), "non_manifold_edge" (> 2 faces on an
// edge of points), "unreferenced_vertex".
ValidationReport validate(const Mesh& mesh, const ValidationParams& params = {});

// The vertex errors of validate() for readers that stream vertices in chunks and never hold a Mesh
// (the out-of-core octree): throws Error(invalid) naming `path` and the first vertex with a NaN or
// infinite coordinate, normal, colour or texture coordinate. `first` is the index of element 0 of the
// spans; empty attribute spans are absent attributes.
void check_vertex_chunk(const std::string& path, std::size_t first, std::span<const Vec3f> positions,
                        std::span<const Vec3f> normals = {}, std::span<const Vec4f> colors = {},
                        std::span<const Vec2f> texcoords = {});
// The extent error of validate(): throws Error(invalid) naming `path` when the diagonal of `bounds`
// overflows float.
void check_extent(const std::string& path, const Bounds& bounds);

}  // namespace lodforge
