// View-dependent cut of the octree LOD: Bade et al. (UTM report 2006, §3.6) culls octree nodes against the
// view frustum and picks a discrete level per node by distance. The distance rule is made precise as
// the usual screen-space error of hierarchical LOD (e.g. Luebke et al., "Level of Detail for 3D
// Graphics", 2002, §4.3): a node of geometric error ε seen at distance d covers ε·h / (2 d tan(fov/2))
// pixels; a node is refined while that exceeds the tolerance, and errors are monotone up the tree, so
// the first node that passes is the coarsest acceptable one.
#include "lodforge/octree/octree_select.h"

#include "lodforge/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace lodforge {
namespace {

struct View {
    Vec3f eye, f, r, u;
    double tan_y = 1, tan_x = 1, pixels_per_unit_at_1 = 1;
};

Vec3f normalized(Vec3f v) {
    const float l = length(v);
    return l > 0 ? v * (1.f / l) : v;
}

View make_view(const Camera& c) {
    if (!(c.fov_y_degrees > 0 && c.fov_y_degrees < 180))
        throw Error(Error::Kind::argument, "camera: the field of view must be in (0, 180) degrees");
    if (c.viewport_width < 1 || c.viewport_height < 1) throw Error(Error::Kind::argument, "camera: empty viewport");
    if (!(is_finite(c.eye) && is_finite(c.target) && length(c.target - c.eye) > 0))
        throw Error(Error::Kind::argument, "camera: eye and target must be distinct finite points");
    View v;
    v.eye = c.eye;
    v.f = normalized(c.target - c.eye);
    Vec3f up = c.up;
    if (length(cross(v.f, normalized(up))) < 1e-4f) up = {0, 0, 1};
    if (length(cross(v.f, up)) < 1e-4f) up = {1, 0, 0};
    v.r = normalized(cross(v.f, up));
    v.u = cross(v.r, v.f);
    v.tan_y = std::tan(c.fov_y_degrees * M_PI / 360.0);
    v.tan_x = v.tan_y * c.viewport_width / c.viewport_height;
    v.pixels_per_unit_at_1 = c.viewport_height / (2.0 * v.tan_y);
    return v;
}

double box_distance(const OctreeNode& n, Vec3f p) {
    double d2 = 0;
    const float q[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) {
        const double lo = n.bounds_min[a], hi = n.bounds_max[a];
        const double e = q[a] < lo ? lo - q[a] : (q[a] > hi ? q[a] - hi : 0.0);
        d2 += e * e;
    }
    return std::sqrt(d2);
}

bool visible(const OctreeNode& n, const View& v) {
    // Inward plane normals through the eye: near (facing forward), left, right, bottom, top.
    const Vec3f planes[5] = {
        v.f,
        v.f * static_cast<float>(v.tan_x) + v.r,
        v.f * static_cast<float>(v.tan_x) - v.r,
        v.f * static_cast<float>(v.tan_y) + v.u,
        v.f * static_cast<float>(v.tan_y) - v.u,
    };
    for (const Vec3f& p : planes) {
        // The box corner furthest along the normal; if even it is behind the plane, the box is out.
        const Vec3f c{p.x >= 0 ? n.bounds_max[0] : n.bounds_min[0], p.y >= 0 ? n.bounds_max[1] : n.bounds_min[1],
                      p.z >= 0 ? n.bounds_max[2] : n.bounds_min[2]};
        if (dot(p, c - v.eye) < 0) return false;
    }
    return true;
}

double pixels(const OctreeNode& n, const View& v) {
    const double d = box_distance(n, v.eye);
    if (d <= 0) return std::numeric_limits<double>::infinity();
    return n.error * v.pixels_per_unit_at_1 / d;
}

}  // namespace

double projected_error_pixels(const OctreeNode& node, const Camera& camera) { return pixels(node, make_view(camera)); }

bool in_frustum(const OctreeNode& node, const Camera& camera) { return visible(node, make_view(camera)); }

SelectResult select_cut(const OctreeStore& store, const Camera& camera, const SelectParams& params) {
    if (!(params.screen_error_pixels > 0))
        throw Error(Error::Kind::argument, "select: the screen-space error must be > 0 pixels");
    const View v = make_view(camera);
    SelectResult r;
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
        const std::uint32_t i = stack.back();
        stack.pop_back();
        const OctreeNode& n = store.node(i);
        if (n.subtree_triangles == 0) continue;
        if (params.frustum_culling && !visible(n, v)) {
            ++r.culled_nodes;
            continue;
        }
        if (pixels(n, v) <= params.screen_error_pixels) {
            r.cut.push_back({i, false});
            ++r.simplified_nodes;
            r.triangles += n.mesh_triangles;
        } else if (n.is_leaf()) {
            r.cut.push_back({i, true});
            ++r.raw_leaves;
            r.triangles += n.raw_triangles;
        } else {
            for (int c = n.child_count() - 1; c >= 0; --c) stack.push_back(n.first_child + static_cast<std::uint32_t>(c));
            continue;
        }
        r.max_depth = std::max<int>(r.max_depth, n.depth);
    }
    return r;
}

}  // namespace lodforge
