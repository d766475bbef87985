// The overlay of two spherical triangulations (internal to the core; used by supermesh.cpp).
#pragma once

#include "morph/sphere_geometry.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lodforge::sphere {

struct SphereTriangulation {
    const std::vector<D3>* points = nullptr;                        // unit vectors
    const std::vector<std::array<std::uint32_t, 3>>* faces = nullptr;  // counter-clockwise from outside
};

// Each overlay vertex is a convex combination of at most three points of a mesh (unused corners have
// weight 0 and index 0).
struct OverlayWeights {
    std::array<std::uint32_t, 3> corner{0, 0, 0};
    std::array<double, 3> weight{0, 0, 0};
};

struct Overlay {
    // Vertices: A's points, then B's points, then one per crossing of an A edge with a B edge.
    std::vector<D3> points;
    std::vector<OverlayWeights> in_a, in_b;  // where each vertex lies in A's and in B's triangulation
    std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise from outside
    std::size_t crossings = 0;
    double min_det = 0;  // smallest det over the triangles
};

// The arrangement of the two triangulations' edges (great-circle arcs), each face (convex: an A
// triangle ∩ a B triangle) fanned into triangles. Returns false and says why in `why` when the input is
// not in general position within the predicates' tolerance (a vertex on or next to an edge of the other
// mesh, two crossings too close along an edge); the caller perturbs B and tries again.
bool overlay_triangulations(const SphereTriangulation& a, const SphereTriangulation& b, Overlay& out, std::string& why);

}  // namespace lodforge::sphere
