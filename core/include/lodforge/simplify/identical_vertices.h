// Lossless re-indexing of meshes stored as triangle soups (glTF primitives without indices, OBJ or PLY
// files with a copy of every vertex per face): vertices equal in position and in every attribute are
// one vertex. Nothing is lost (no attribute differs); the sharing the file did not record is restored,
// so that the simplifier sees edges shared by faces instead of a seam on every edge.
//
//   IdenticalVertices iv = find_identical_vertices(mesh);
//   if (iv.duplicates * 4 >= mesh.vertex_count()) { Mesh m = iv.merged(mesh); ... }
#pragma once

#include "lodforge/mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lodforge {

struct IdenticalVertices {
    std::vector<std::uint32_t> merged_of;  // input vertex -> merged vertex (first-appearance order)
    std::vector<std::uint32_t> first_of;   // merged vertex -> its lowest input vertex
    std::size_t duplicates = 0;            // input vertices equal to an earlier one

    // The mesh on merged vertices: faces re-indexed, materials and face materials kept, attributes of
    // each merged vertex's first input vertex, position_ids empty (points are the positions).
    Mesh merged(const Mesh& mesh) const;
};

// Bit-identical position, normal, colour and every texture-coordinate set (meshopt_generateVertexRemapMulti;
// -0 and +0 differ, as any other bits do). O(n).
IdenticalVertices find_identical_vertices(const Mesh& mesh);

}  // namespace lodforge
