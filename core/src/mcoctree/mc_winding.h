// Generalized winding number of a triangle mesh (Jacobson, Kavan and Sorkine-Hornung, "Robust inside-outside
// segmentation using generalized winding numbers", 2013), evaluated fast by a tree of dipoles (Barill,
// Dickson, Schmidt, Levin and Jacobson, "Fast winding numbers for soups and clouds", 2018).
//
// The marching-cube octree signs its field by the nearest point's normal. On a low-poly mesh with folds,
// slivers or thin ridges that sign is wrong in whole regions (the Duck's bill, Spot's control cage); the
// winding number is 1 inside a closed surface and 0 outside whatever the faces' local shape, and it
// degrades gracefully over holes and overlapping shells (docs/mcoctree.md D1, "Faces larger than a cube").
#pragma once

#include "lodforge/mesh.h"

#include <cstdint>
#include <vector>

namespace lodforge::mc {

struct WindingTree {
    struct Node {
        Vec3f centre;           // area-weighted centroid of its triangles
        float radius = 0;       // of the ball about `centre` holding all its triangles
        Vec3f area;             // sum of its triangles' vector areas (half the cross products)
        std::uint32_t first = 0, count = 0;  // leaves: triangles [first, first + count) of `order`
        std::uint32_t left = 0, right = 0;   // inner nodes: children (count == 0)
    };
    std::vector<Node> nodes;            // root first
    std::vector<std::uint32_t> order;   // triangle indices, grouped by leaf
    const Mesh* mesh = nullptr;
};

// |sum of the faces' vector areas| / sum of their areas: 0 for a closed surface (whatever its shape), near 1
// for an open sheet. The winding number tells inside from outside only where it is small: across a sheet it
// goes from about +1/2 to -1/2 and never passes 1/2 (frag_115, one side of a room, is 0.995; the bunny
// with its open base 0.017, the milk truck 0.000).
double openness(const Mesh& mesh);

// The tree over `mesh`'s triangles (degenerate ones included: they add nothing). The mesh must outlive it.
WindingTree build_winding_tree(const Mesh& mesh);

// The winding number at `q`: 1 inside a closed, outward-wound surface, 0 outside. Nodes farther than
// `beta` times their radius are taken as one dipole (errors up to about a tenth at beta 1.5, below
// the 0.5 threshold that is read from it); the rest exactly, triangle by triangle (beta = infinity: all).
double winding_number(const WindingTree& tree, Vec3f q, double beta = 2.0);

}  // namespace lodforge::mc
