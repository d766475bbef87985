// The discontinuities the collapse simplifier treats specially, classified per edge (issue 31, "seam
// inspector"; docs/artist-control.md). Edges are on points (vertices at one position are one point, as
// the simplifier welds them), each given by the representative vertices of its two points.
//
//   SeamReport r = classify_seams(mesh);
//   r.edges[int(SeamClass::uv)].size();   // UV seam edges (any set); r.uv_set_edges[s] per set
#pragma once

#include "lodforge/mesh.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lodforge {

enum class SeamClass : int {
    uv,            // two faces use different texture coordinates at an end of the edge (any set)
    uv_mirror,     // the two faces' UV triangles (set 0) have opposite orientations: a mirrored chart
    crease,        // a hard-normal crease: the faces' normals at an end differ by more than crease_angle
    material,      // the two faces have different materials
    color,         // the two faces use different vertex colours at an end
    border,        // one face: an open border
    non_manifold,  // more than two faces
};
inline constexpr int kSeamClasses = 7;
std::string_view to_string(SeamClass c);  // "uv", "uv_mirror", "crease", "material", "color", "border", "non_manifold"

struct SeamParams {
    float crease_angle_degrees = 1.f;  // vertex normals further apart than this are a hard edge
    float color_tolerance = 1.f / 512;  // per channel, on the [0, 1] scale (half a step of 8-bit colour)
};

struct SeamReport {
    // Per class, the edges (representative vertex of each point, smaller first); an edge may be in
    // several classes (a UV seam along a crease).
    std::array<std::vector<std::pair<std::uint32_t, std::uint32_t>>, kSeamClasses> edges;
    std::vector<std::size_t> uv_set_edges;  // UV seam edges per texcoord set
    std::size_t edge_count = 0;             // edges on points in all
};

SeamReport classify_seams(const Mesh& mesh, const SeamParams& params = {});

// The CLI's --seams and the preset key "seams": "weight=CLASS:W[,CLASS:W...]" (W finite, > 0) as
// SimplifyParams::seam_weights (1 for the classes not named). Throws Error(argument) naming the text for
// anything else (an unknown class, a bad number; protect and allow per class are not built).
std::vector<float> parse_seam_weights(std::string_view text);

}  // namespace lodforge
