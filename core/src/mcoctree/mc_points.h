// The marching-cube octree's input points: a mesh's vertices (merged per position, normals oriented) and
// face samples as one point cloud with its kd-tree (mc_points.cpp), and the nearest-point result set the
// distance field queries it with.
#pragma once

#include "lodforge/mesh.h"

#include <nanoflann.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lodforge::mc {

struct PointCloud {
    std::vector<Vec3f> points, normals;
    // The normals the output's vertices interpolate, when they differ from the orientation (`normals`):
    // with a mesh's faces sampled, the orientation is the pseudo-normals and the shading the input's
    // (interpolated on the samples; mc_face_samples.h). Empty: `normals`.
    std::vector<Vec3f> shading;
    std::vector<Vec4f> colors;
    // The positions again as arrays for the kd-tree: its build reads a coordinate chosen at run time, which
    // Vec3f::operator[] would answer with two branches per read.
    std::vector<std::array<float, 3>> coords;
    // nanoflann adaptor
    std::size_t kdtree_get_point_count() const { return coords.size(); }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const { return coords[i][dim]; }
    template <class B> bool kdtree_get_bbox(B&) const { return false; }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointCloud>, PointCloud, 3,
                                                   std::uint32_t>;

inline const char* const input_name = "mcoctree input";

// nanoflann result set for the field's nearest point: the smallest squared distance, ties to the lowest
// point index (D1), so the field does not depend on the search structure's visiting order. The search
// radius handed to the tree sits a little above the best distance so that points at exactly that distance
// still reach addPoint (the tree's cell bounds are rounded); `bound` is an optional upper limit.
struct LowestNearest {
    float best = INFINITY, bound = INFINITY;
    std::uint32_t idx = UINT32_MAX;
    std::size_t size() const { return idx != UINT32_MAX; }
    bool full() const { return true; }
    bool addPoint(float d2, std::uint32_t i) {
        if (d2 < best || (d2 == best && i < idx)) best = d2, idx = i;
        return true;
    }
    float worstDist() const { return std::min(bound, best * (1 + 1e-5f) + 1e-30f); }
};

// A vertex's normal from its faces is an orientation only where the faces agree: its length at least a
// tenth of the faces' summed area normals. Where they fold back onto each other or disagree in winding
// (the same triangle listed with both windings, the folds of a badly oriented scan) the direction left is
// rounding noise or a mix with an arbitrary sign, and the nearest point's sign decides the side of every
// lattice point in its Voronoi cell: for a point on the hull that cell reaches the grid's edge, and so did
// a sheet of zero set (docs/mcoctree.md, pipeline step 1). On the clean scans (dragon, bunny, Lucy) every
// vertex keeps more than 0.3.
constexpr float kFoldedFaces = 0.1f;
// Copies of a point are merged with the sum of their normals unless that is only rounding noise (the
// dragon's seam copies whose sides nearly oppose keep their small sum: it measured better than the first
// copy's own normal, docs/mcoctree.md D1).
constexpr float kCancelled = 1e-5f;

// `unit_normals` and `point_ids` (for sampling large faces) get, per vertex of the mesh, its point's unit
// normal (zero when skipped) and the first vertex at its position; filled only when the mesh has faces.
PointCloud points_of(const Mesh& mesh, std::size_t& skipped, unsigned threads, std::vector<Vec3f>& unit_normals,
                     std::vector<std::uint32_t>& point_ids);

// Median distance from a point to its nearest other point (over up to 2000 points).
double median_spacing(const PointCloud& pc, const KdTree& tree);

}  // namespace lodforge::mc
