// Welding and output layout of the collapse simplifier: which vertices are one point, which input faces
// it starts from, and the output mesh laid out as Mesh requires. Internal to the core (simplify.cpp);
// weld_seams() (lodforge/simplify/simplify.h) is defined with them.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/simplify/identical_vertices.h"
#include "lodforge/simplify/simplify.h"

#include <cstdint>
#include <vector>

namespace lodforge::simplify_detail {

// Point id of every vertex (position_ids, joined further at equal positions with `weld`, within
// `tolerance` when > 0); `representative` gets the first vertex of each point.
std::vector<std::uint32_t> derive_points(const Mesh& mesh, bool weld, float tolerance,
                                         std::vector<std::uint32_t>& representative);

// The faces `corners` (input vertex ids; `face_source`: input face of each) with the vertices they use,
// one vertex per point first; `positions` (per point) replaces the input positions when given.
// `vertex_map` receives output vertex → input vertex.
Mesh build_mesh(const Mesh& src, const std::vector<std::uint32_t>& point_of, const std::vector<Vec3f>* positions,
                const std::vector<std::uint32_t>& corners, const std::vector<std::uint32_t>& face_source,
                std::vector<std::uint32_t>& vertex_map);

// 1 for each input face the simplifier starts from: not degenerate on points, not a repeat of an earlier
// face's points (either winding).
std::vector<std::uint8_t> initial_faces(const Mesh& mesh, const std::vector<std::uint32_t>& point);

// True when `mesh` is a triangle soup worth simplifying on its merged vertices; fills `iv` then.
bool soup_worth_merging(const Mesh& mesh, const SimplifyParams& params, IdenticalVertices& iv);

// Restates a result computed on iv.merged(mesh) in the numbering of `mesh`.
void to_input_numbering(SimplifyResult& r, const IdenticalVertices& iv);

}  // namespace lodforge::simplify_detail
