// Error heat maps: a mesh coloured by a per-vertex scalar (usually DistanceResult::vertex_errors), for
// viewing in MeshLab, CloudCompare or the studio (see docs/simplification.md, "Heatmaps").
//
//   DistanceResult d = compare(reference, simplified);
//   write_heatmap_ply(make_heatmap(simplified, d.vertex_errors), "error.ply");
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/types.h"

#include <string>
#include <vector>

namespace lodforge {

struct Heatmap {
    Mesh mesh;                   // the input's positions and faces, colours from the colour map
    std::vector<float> quality;  // the scalar per vertex (PLY `quality`, as MeshLab names it)
    float range_max = 0;         // the value mapped to the top of the colour map
};

// Viridis (matplotlib's perceptually uniform map, dark blue → green → yellow) at t in [0, 1] (clamped),
// alpha 1.
Vec4f viridis(float t);

// Colours `mesh` by `values` (one per vertex): 0 maps to the bottom of the colour map, `range_max` and
// above to the top; range_max <= 0 uses the largest value. Normals, texcoords and position_ids are kept,
// colours replaced. Throws Error(argument) when the sizes differ or a value is negative or not finite.
Heatmap make_heatmap(const Mesh& mesh, const std::vector<float>& values, float range_max = 0.f);

// The automatic top of a heat map's colour map: the `percentile` (in (0, 1]) of the values at the
// vertices some triangle uses. Unused vertices have no surface to colour, and their distance (often far
// from everything) would flatten every colour; a high percentile rather than the largest value keeps a
// single stray vertex from doing the same. Values that are negative or not finite are skipped. 0 when no
// used vertex has a positive value. Throws Error(argument) when the sizes differ or `percentile` is
// outside (0, 1].
float heatmap_range(const Mesh& mesh, const std::vector<float>& values, float percentile = 0.99f);

// Binary little-endian PLY: vertex x y z quality (float), red green blue alpha (uchar); face
// vertex_indices (uchar count, int). Written through AtomicFile; Error(io) names the file on failure.
void write_heatmap_ply(const Heatmap& heatmap, const std::string& path);

}  // namespace lodforge
