// Checks a mesh for the defects that break later stages. Importers throw on defects that make a mesh
// unusable (index out of range, non-finite positions); the softer findings (degenerate, duplicate or
// non-manifold faces, unused vertices) are reported here so the CLI `info` and the studio can show them.
#pragma once

#include "lodforge/mesh.h"

#include <cstddef>
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

}  // namespace lodforge
