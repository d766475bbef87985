// Run-time selection over an octree LOD asset: frustum culling of nodes and a per-node level chosen
// by projected screen-space error (docs/octree.md, "Run-time selection"). The document (§3.6) picks a
// discrete level per node "by distance" without a formula; here a node's stored geometric error
// (model units) is projected at the distance of the nearest point of its bounds and compared with a
// tolerance in pixels.
//
//     Camera cam;  cam.eye = {..};  cam.target = {..};  cam.fov_y_degrees = 45;
//     SelectResult s = select_cut(store, cam, {.screen_error_pixels = 2});
//     Mesh view = extract_mesh(store, s.cut);      // only the nodes it needs are read
#pragma once

#include "lodforge/octree/octree_store.h"
#include "lodforge/types.h"

#include <cstddef>
#include <cstdint>

namespace lodforge {

struct Camera {
    Vec3f eye{0, 0, 1};
    Vec3f target{0, 0, 0};
    Vec3f up{0, 1, 0};             // replaced by +Z when parallel to the view direction
    float fov_y_degrees = 60.f;    // vertical field of view, in (0, 180)
    int viewport_width = 1920;     // pixels
    int viewport_height = 1080;
};

struct SelectParams {
    float screen_error_pixels = 1.f;  // refine a node while its projected error exceeds this (> 0)
    bool frustum_culling = true;      // drop nodes wholly outside the view frustum
};

struct SelectResult {
    Cut cut;
    std::size_t culled_nodes = 0;     // subtrees dropped by the frustum
    std::size_t raw_leaves = 0;       // nodes drawn at full resolution
    std::size_t simplified_nodes = 0;
    std::uint64_t triangles = 0;      // of the cut
    int max_depth = 0;                // deepest node in the cut
};

// Throws Error(argument) for a degenerate camera (eye = target, fov outside (0, 180), empty viewport)
// or a non-positive tolerance. Reads only the node table (no mesh data).
SelectResult select_cut(const OctreeStore& store, const Camera& camera, const SelectParams& params = {});

// The node's error in pixels seen from `camera` (infinity when the eye is inside its bounds).
double projected_error_pixels(const OctreeNode& node, const Camera& camera);

// Whether the node's bounds intersect the view frustum (no far plane).
bool in_frustum(const OctreeNode& node, const Camera& camera);

}  // namespace lodforge
