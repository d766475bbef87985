// Metro-style surface distance between two meshes (Cignoni, Rocchini, Scopigno, "Metro: Measuring Error
// on Simplified Surfaces", Computer Graphics Forum 1998): both surfaces are sampled (area-weighted,
// seeded random, plus their vertices) and every sample's distance to the closest point of the other
// surface is measured exactly (point–triangle distance over a bounding-volume hierarchy).
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace lodforge {

struct DistanceParams {
    // Area-weighted samples per surface; 0 = max(100 000, min(10 per triangle, 2 000 000)).
    std::size_t samples = 0;
    std::uint64_t seed = 1;        // same seed, same meshes → same result
    bool include_vertices = true;  // vertices are samples too (they count for the max, not the means)
    bool vertex_errors = true;     // fill DistanceResult::vertex_errors
    bool region_errors = false;    // fill DistanceResult::region_errors
    // Threads: above 1, the two directions (their trees, samples and vertices) run at once. The result
    // is the same at any count; progress then comes from the test side only, cancellation from both.
    unsigned threads = 1;
};

struct OneSidedDistance {
    double max = 0;   // model units
    double mean = 0;  // over the area-weighted samples
    double rms = 0;
    std::size_t samples = 0;
};

struct DistanceResult {
    OneSidedDistance test_to_reference;  // samples on the test mesh, distance to the reference surface
    OneSidedDistance reference_to_test;
    // Symmetric: Hausdorff = larger of the two maxima; mean and RMS over the samples of both sides.
    double hausdorff = 0, mean = 0, rms = 0;
    double diagonal = 0;  // bounding-box diagonal of the reference
    double hausdorff_relative = 0, mean_relative = 0, rms_relative = 0;  // divided by `diagonal`
    // Attributes at the test samples against the closest reference point (interpolated), when both
    // meshes have them: colour RMS over the R, G, B channels on the 0–255 scale; texcoord RMS (set 0,
    // UV units) of the distance between the two interpolated coordinates.
    bool has_color_error = false;
    double color_rms = 0;
    bool has_texcoord_error = false;
    double texcoord_rms = 0;
    // Per test vertex: distance to the reference surface (model units).
    std::vector<float> vertex_errors;
    // Per test vertex: the largest distance measured in its part of the test surface (model units), the
    // field for heat maps. A vertex's part is where it is the corner of largest barycentric weight; it
    // collects the vertex's own distance, the test samples there and the reference samples and vertices
    // whose closest test point lies there. So both directions count, the largest value is the Hausdorff
    // distance (with include_vertices), and a half-edge simplification, whose vertices lie on the
    // reference (vertex_errors all zero), still shows where its surface departs.
    std::vector<float> region_errors;
};

// Throws Error(invalid) when either mesh has no triangles, Error(cancelled) when progress asks to stop.
DistanceResult compare(const Mesh& reference, const Mesh& test, const DistanceParams& params = {},
                       Progress* progress = nullptr);

// A reference prepared once (its search tree: about a second on an 871K-triangle scan) for several
// comparisons against it, as the studio measures a chain's levels against the original. Refers to
// `reference`, which must outlive it. Throws Error(invalid) for a mesh without triangles.
class DistanceReference {
public:
    explicit DistanceReference(const Mesh& reference);
    ~DistanceReference();
    DistanceReference(const DistanceReference&) = delete;
    DistanceReference& operator=(const DistanceReference&) = delete;
    const Mesh& mesh() const { return *mesh_; }

private:
    struct Tree;
    const Mesh* mesh_;
    std::unique_ptr<Tree> tree_;
    friend DistanceResult compare(const DistanceReference&, const Mesh&, const DistanceParams&, Progress*);
};

// The same result as compare(reference.mesh(), test, params, progress).
DistanceResult compare(const DistanceReference& reference, const Mesh& test, const DistanceParams& params = {},
                       Progress* progress = nullptr);

}  // namespace lodforge
