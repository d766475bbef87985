// Extra surface points on a mesh's large faces, for the marching-cube octree's distance field.
//
// The field's sign at a lattice point comes from its nearest input point and that point's normal. A mesh
// gives its vertices; where a face is larger than a cube the nearest vertex of a lattice point above the
// middle of the face is across the face or round a corner, and its averaged normal can give the wrong
// side (a box rebuilt with bubbles outside it). Points on those faces, about a cube apart, make the
// nearest point lie on the nearest face (docs/mcoctree.md D1, "Faces larger than a cube").
#pragma once

#include "lodforge/mesh.h"

#include <cstddef>
#include <span>
#include <vector>

namespace lodforge::mc {

struct FaceSampleParams {
    float min_edge = 0;  // a face is sampled when its longest edge is above this
    float spacing = 0;   // largest distance between neighbouring samples along an edge or a row
    std::size_t max_samples = 0;  // Error(argument) when the faces need more
};

struct FaceSamples {
    std::vector<Vec3f> points;
    // Orientation (unit length): the face's normal inside a face, the sum of the adjacent faces' normals
    // on an edge (Baerentzen and Aanaes' pseudo-normals: the side of a point whose closest surface point
    // is on a sharp edge is told right by it, and by neither face alone).
    std::vector<Vec3f> normals;
    std::vector<Vec3f> shading;  // the vertex normals interpolated (unit length): smooth like the input
    std::vector<Vec4f> colors;   // when the mesh has per-vertex colours
    std::size_t faces = 0;       // faces that got samples
};

// Whether some face has an edge longer than `min_edge` (stops at the first).
bool has_long_face(const Mesh& mesh, float min_edge);

// Samples on the faces of `mesh` whose longest edge exceeds params.min_edge: rows of points parallel to the
// shortest edge (so a sliver gets points in proportion to its area), and the points of each long edge once.
// `vertex_normals` (unit length, zero for a vertex without one) are interpolated for shading; a face with
// a vertex without a normal, and a degenerate face, gets none. `point_id` names each vertex's point
// (vertices at one position share it), so an edge split by a seam is sampled once and its pseudo-normal
// sums the faces on both sides. Indices must be in range (checked by the caller).
FaceSamples sample_large_faces(const Mesh& mesh, std::span<const Vec3f> vertex_normals,
                               std::span<const std::uint32_t> point_id, const FaceSampleParams& params);

// Per point (indexed by `point_id`, i.e. at the first vertex of each position): the angle-weighted sum of
// its faces' unit normals, made unit length; zero where the faces cancel (less than a tenth of the summed
// angles is left: a fold, a doubled face). This is the vertex's pseudo-normal: it tells the side of every
// point whose closest surface point is that vertex, where an area-weighted normal can be wrong at a
// sharp corner (Spot's control cage rebuilt with a sheet to the grid's edge).
std::vector<Vec3f> vertex_pseudo_normals(const Mesh& mesh, std::span<const std::uint32_t> point_id);

}  // namespace lodforge::mc
