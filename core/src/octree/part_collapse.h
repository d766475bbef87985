// Interior simplification of one part of an octree node's patch by edge collapse, its border locked
// (docs/octree.md, "Parts simplified by edge collapse"). Internal to the node operator.
#pragma once

#include "lodforge/octree/octree_simplify.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lodforge::ooc {

struct PartCollapse {
    std::vector<std::uint32_t> indices;  // triangles, indices into the node's input vertices (a subset of them)
    double error = 0;                    // largest collapse error estimate, model units
};

// Simplifies the part made of `triangles` (triangle numbers of `input`) by half-edge collapses, down to
// `target` triangles or until the next collapse's error estimate would exceed `max_error` (model units),
// moving no vertex. With `lock_border` no border vertex is removed, and false is returned (`out`
// unspecified) unless the result has exactly the part's oriented boundary (a non-manifold or
// inconsistently oriented part fails), so the caller's crack-freeness argument holds for every part it
// accepts; without it border vertices slide along the border (a part sharing no edge with another node).
// `weld`: vertices at one position (a UV seam stored as split vertices) collapse together, as the
// collapse simplifier welds them; only for a node that shares nothing with another (the root).
bool collapse_part(const NodeMesh& input, const std::vector<std::uint32_t>& triangles, std::size_t target,
                   double max_error, bool lock_border, PartCollapse& out, bool weld = false);

}  // namespace lodforge::ooc
