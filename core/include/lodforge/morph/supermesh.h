// A supermesh from two closed genus-0 meshes with different connectivity (issue 8, case (b); LODStrips
// thesis chapter 6; docs/morph.md, "Case (b): two meshes").
//
//   Mesh a = read_mesh("spot.obj"), b = read_mesh("ball.ply");
//   Landmarks l = read_landmarks("l.json");
//   SupermeshResult r = build_supermesh(a, b, l, {}, "spot.obj", "ball.ply", "l.json");
//   // r.morph: one connectivity, frame 0 = shape A, frame 1 = shape B; LOD/.lfmorph/extract apply.
//
// Both meshes are mapped bijectively onto the unit sphere, B's map is rotated and warped so the landmark
// pairs meet, and the two spherical triangulations are overlaid: every vertex of A and of B is a vertex
// of the supermesh, plus one vertex per crossing of an A edge with a B edge.
#pragma once

#include "lodforge/morph/landmarks.h"
#include "lodforge/mesh.h"
#include "lodforge/morph/morph.h"
#include "lodforge/progress.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

// A mesh welded to its surface points (position_ids) with the topology of a sphere.
struct SphereTopology {
    std::vector<Vec3f> points;                     // one per point
    std::vector<std::array<std::uint32_t, 3>> faces;  // point indices, counter-clockwise from outside
    std::vector<std::uint32_t> point_of_vertex;    // wedge -> point
};

// Welds `mesh` by position_ids and checks it is a closed, connected, consistently oriented, manifold
// surface of Euler characteristic 2 (genus 0). Unused points are an error too (they would have no place
// on the sphere). Throws Error(unsupported) for another genus or several components, Error(invalid) for
// border edges, non-manifold edges/vertices, inconsistent orientation, degenerate (repeated-index) faces,
// naming `source` and what was found ("genus 1", "37 border edges", "2 components").
SphereTopology check_sphere_topology(const Mesh& mesh, const std::string& source);

struct SphereMapParams {
    int stretch_rounds = 8;    // Tutte solves, each reweighted by the last one's area stretch (1 = plain)
    int repair_sweeps = 200;   // local sweeps moving only the points of folded faces
    int fallback_rounds = 30;  // then, if folds remain, rounds of Möbius centering + 10 global sweeps
};

struct SphereMap {
    std::vector<std::array<double, 3>> points;  // unit vectors, one per point of the SphereTopology
    std::size_t cut_face = 0;        // the face whose star became the outer triangle of the Tutte disk
    double min_face_orient = 0;      // smallest det[p0, p1, p2] over the faces (> 0: no fold)
    double min_face_angle = 0;       // smallest triangle corner angle on the sphere, radians
    double area_distortion = 0;      // Σ a_f·(a_f / s_f) over faces (3D and sphere area shares); 1 = area-preserving
};

// Spherical parametrisation: Tutte embedding (mean-value weights) of the mesh minus one face into a
// triangle, inverse stereographic projection, then fold-checked relaxation on the sphere alternating
// with Möbius centering. Every face is positively oriented on the sphere (orient3d against the centre)
// on return; otherwise Error(invalid) naming `source`.
SphereMap map_to_sphere(const SphereTopology& mesh, const SphereMapParams& params, const std::string& source,
                        Progress* progress = nullptr);

// Moves only the points of folded faces (towards their neighbours' centroid, each move kept when it
// unfolds a face of the point's star) for up to `sweeps` sweeps; returns the faces still folded.
std::size_t repair_sphere_folds(const SphereTopology& mesh, std::vector<std::array<double, 3>>& points, int sweeps);

// Moves each unpinned point of a folded face into the kernel of its star (where all its faces are
// positive), when that lowers its star's folds, for up to `sweeps` sweeps; returns the faces still folded.
std::size_t untangle_sphere_folds(const SphereTopology& mesh, std::vector<std::array<double, 3>>& points,
                                  const std::vector<std::uint8_t>& pinned, int sweeps);
// Moves the unpinned points of faces whose smallest corner sine is below min_sine towards their
// neighbours' centroid when that improves the worst face of their star without folding one.
void relax_sphere_slivers(const SphereTopology& mesh, std::vector<std::array<double, 3>>& points,
                          const std::vector<std::uint8_t>& pinned, double min_sine, int sweeps);

struct SupermeshParams {
    SphereMapParams sphere;
    // Keyframes of the output: 0 or 2 = the two shapes; N > 2 = N evenly spaced samples of the linear
    // blend (same V(t); more frames for the per-frame collapse orders and the single order's cost).
    std::size_t frames = 0;
    int max_warp_steps = 400;  // landmark warp: steps of the Gaussian-RBF flow, each fold-checked
    double warp_tolerance = 1e-6;  // stop when every landmark pair is closer than this (radians)
    int max_overlay_tries = 6;     // overlay retries after a near-degenerate configuration (B turned slightly)
};

struct SupermeshResult {
    MorphMesh morph;               // frame 0 = shape A, frame 1 = shape B; one connectivity
    std::size_t a_points = 0;      // supermesh vertices 0 .. a_points-1 are A's points, in A's order
    std::size_t b_points = 0;      // then B's points, in B's order
    std::size_t crossings = 0;     // then one vertex per A-edge/B-edge crossing
    double landmark_residual = 0;  // largest angle (radians) between a landmark pair after alignment
    double rotation_residual = 0;  // the same after the rotation only (before the warp)
    double mobius_residual = 0;    // the same after the rotation and the Möbius map (3+ pairs; else = rotation)
    int warp_steps = 0;
    int overlay_tries = 0;         // 1 when the first overlay was in general position
    double min_face_orient = 0;    // smallest det over the supermesh faces on the sphere (> 0)
    std::vector<std::array<double, 3>> sphere_points;  // each supermesh vertex on the common sphere
};

// Builds the supermesh. The landmarks (vertex indices of A and B as read_mesh returns them) must be at
// least one pair and are checked with check_landmarks against `landmark_source`. Attributes other than
// positions (texcoords, colours, materials) are not carried: the supermesh has positions only and each
// frame's normals come from its faces. Throws as check_sphere_topology / map_to_sphere, Error(invalid)
// when the landmarks cannot be brought together without folding the map (rotation, Möbius map, warp
// with local untangling: docs/morph.md).
SupermeshResult build_supermesh(const Mesh& a, const Mesh& b, const Landmarks& landmarks,
                                const SupermeshParams& params, const std::string& source_a,
                                const std::string& source_b, const std::string& landmark_source,
                                Progress* progress = nullptr);

// read_mesh both files, read_landmarks, build_supermesh; the MorphMesh's frame names are the two files.
MorphMesh load_supermesh(const std::string& path_a, const std::string& path_b, const std::string& landmarks_path,
                         const SupermeshParams& params = {}, Progress* progress = nullptr);

}  // namespace lodforge
