// Edge-collapse simplification with quadric error metrics.
//
// Based on:
//  - M. Garland, P. Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997
//    (plane quadrics, greedy collapse order by a priority queue, border constraint planes);
//  - M. Garland, P. Heckbert, "Simplifying Surfaces with Color and Texture using Quadric Error Metrics",
//    IEEE Visualization 1998 (attributes in the quadric);
//  - H. Hoppe, "New Quadric Metric for Simplifying Meshes with Appearance Attributes", IEEE Visualization
//    1999 (memory-efficient attribute quadrics per wedge, seams as wedges of one point);
//  - T. Dey, H. Edelsbrunner et al., "Topology Preserving Edge Contraction", 1999 (link condition).
//
//  - A. Kapoulkine, meshoptimizer's simplifier (2016-, MIT): rounds of independent cheapest-first
//    collapses over a sorted candidate list, adjacency rebuilt between rounds, seam edges constrained.
//
// Layout: flat arrays. Faces keep their input index and store wedge (vertex) ids. Default schedule
// (passes, see run_passes): point → faces as a CSR rebuilt after each round; every point's cheapest
// outgoing collapse is costed once, re-costed only when its neighbourhood changed. Greedy schedule: each
// point has a list of its faces that grows by merging on collapse and one entry in an indexed binary heap;
// a collapse u → v re-evaluates v and, around v, only what changed.
#include "lodforge/simplify/simplify.h"
#include "lodforge/simplify/identical_vertices.h"

#include "lodforge/error.h"
#include "lodforge/simplify/quadric.h"
#include "lodforge/simplify/seams.h"
#include "simplify/simplify_internal.h"
#include "simplify/simplify_weld.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <numeric>
#include <span>
#include <string>
#include <unordered_map>

namespace lodforge {
namespace simplify_detail {

// Attribute values are multiplied by 10 x their weight (see setup()): the default colour weight 0.1 is then
// meshoptimizer's 1.0, so the same SimplifyWeights serve the clustering and octree methods, which read a
// weight as a cost in diagonals.
constexpr double kAttributeScale = 10.0;  // (wedge, material) classes around one point; more = locked point
// Weight of a border edge's constraint plane in units of |edge|² (a face counts its area): how strongly a
// sliding border keeps its outline, which on an open scan is what the eye sees first. With GH97's weight 1
// the coloured scans lost to gltfpack in the image compare by their silhouette (color.ply at 5 %: 2.1 % of
// the pixels against 0.8 %). Image error there (gltfpack 2.05): weight 1 2.95, 10 2.66, 20 2.41, 30 2.34;
// above 20 the bunny's hole rims start to fold faces at 1 % (docs/simplification.md, "Borders"). Seams
// keep weight 1.
constexpr double kBorderPlaneWeight = 20.0;

// Faces of a border point that cheapest_plain_border() takes on its stack (more: the general path).
constexpr std::size_t kPlainBorderFaces = 32;

void Simplifier::setup() {
    const std::size_t nv = mesh_.vertex_count();
    pid_ = derive_points(mesh_, params_.weld, 0.f, representative_);
    points_ = representative_.size();

    const Bounds b = mesh_.bounds();
    const double diag = b.diagonal();
    scale_ = diag > 0 ? diag : 1.0;
    centre_ = to3d(b.center());
    pts_.assign(points_, PointRec{});
    geo_.assign(points_, Quadric{});
    for (std::size_t p = 0; p < points_; ++p) {
        const Vec3d q = to3d(mesh_.positions[representative_[p]]);
        pts_[p].pos = {(q.x - centre_.x) / scale_, (q.y - centre_.y) / scale_, (q.z - centre_.z) / scale_};
    }

    // Wedges of each point.
    wedge_begin_.assign(points_ + 1, 0);
    for (std::uint32_t w = 0; w < nv; ++w) ++wedge_begin_[pid_[w] + 1];
    for (std::size_t p = 0; p < points_; ++p) wedge_begin_[p + 1] += wedge_begin_[p];
    wedge_list_.resize(nv);
    {
        std::vector<std::uint32_t> fill(wedge_begin_.begin(), wedge_begin_.end() - 1);
        for (std::uint32_t w = 0; w < nv; ++w) wedge_list_[fill[pid_[w]]++] = w;
    }
    for (std::size_t p = 0; p < points_; ++p) {
        pts_[p].one_wedge = wedge_begin_[p + 1] - wedge_begin_[p] == 1;
        pts_[p].wedge = wedge_list_[wedge_begin_[p]];
    }

    // Faces: drop those degenerate on points.
    const std::size_t nf = mesh_.triangle_count();
    corners_.assign(mesh_.indices.begin(), mesh_.indices.end());
    face_alive_ = initial_faces(mesh_, pid_);
    fpt_.resize(corners_.size());
    for (std::size_t i = 0; i < corners_.size(); ++i) fpt_[i] = pid_[corners_[i]];
    for (std::size_t f = 0; f < nf; ++f) alive_faces_ += face_alive_[f];
    greedy_ = false;
    build_csr();
    if (params_.schedule == SimplifyParams::Schedule::greedy) {
        pfaces_.resize(points_);
        for (std::uint32_t p = 0; p < points_; ++p) {
            const auto fs = faces_of(p);
            pfaces_[p].assign(fs.begin(), fs.end());
        }
        greedy_ = true;
        HugeVector<std::uint32_t>().swap(csr_faces_);
    }

    // Attributes, weighted so that a difference of 1 spread over a region of size d costs like a
    // deviation of kAttributeScale * weight * d (see combine()); kAttributeScale keeps the weights on the
    // scale the clustering and octree methods read them on (docs/simplification.md, "Attribute fidelity").
    const auto& w = params_.weights;
    struct Channel { const float* base; std::size_t stride, count; double weight; bool unit; };
    std::vector<Channel> channels;
    attr_channels_.clear();
    using AK = AttrChannel::Kind;
    auto add_channel = [&](const float* base, std::size_t count, double weight, AK kind, std::size_t set) {
        channels.push_back({base, count, count, weight, kind == AK::normal});
        attr_channels_.push_back({kind, set, dims_, count, kAttributeScale * weight});
        dims_ += count;
    };
    dims_ = 0;
    if (mesh_.has_normals() && w.normal > 0) add_channel(&mesh_.normals[0].x, 3, w.normal, AK::normal, 0);
    if (mesh_.has_colors() && w.color > 0) add_channel(&mesh_.colors[0].x, 4, w.color, AK::color, 0);
    for (std::size_t s = 0; s < mesh_.texcoords.size(); ++s) {
        const float ws = s < w.texcoord_sets.size() ? w.texcoord_sets[s] : w.texcoord;
        if (ws > 0 && !mesh_.texcoords[s].empty()) add_channel(&mesh_.texcoords[s][0].x, 2, ws, AK::texcoord, s);
    }
    if (nv == 0) dims_ = 0;
    // Half-edge only: there the kept wedges keep their UVs, so the fold test is exact; optimal placement
    // re-solves them after the run (testing its faces at the input UVs refused collapses it needs).
    uv_sets_.clear();
    for (const AttrChannel& c : attr_channels_)
        if (c.kind == AK::texcoord && dims_ > 0 && params_.placement == Placement::half_edge)
            uv_sets_.push_back(&mesh_.texcoords[c.set]);
    attrs_.assign(nv * dims_, 0.0);
    if (dims_ > 0) {
        for (std::size_t v = 0; v < nv; ++v) {
            std::size_t j = 0;
            for (const Channel& c : channels) {
                // Normals are directions: PLY scans carry unnormalised ones (color.ply's are up to 6.3 long),
                // which would weigh their normal differences up to 40x (docs/simplification.md, "Attribute
                // fidelity"). A zero normal stays zero.
                double scale = kAttributeScale * c.weight;
                if (c.unit) {
                    double len2 = 0;
                    for (std::size_t k = 0; k < c.count; ++k) len2 += double(c.base[v * c.stride + k]) * c.base[v * c.stride + k];
                    if (len2 > 0 && std::isfinite(len2)) scale /= std::sqrt(len2);
                }
                for (std::size_t k = 0; k < c.count; ++k) attrs_[v * dims_ + j++] = scale * c.base[v * c.stride + k];
            }
        }
    }
    // Geometry only: no attribute quadrics at all (AttributeQuadrics of dimension 0 still holds 11 doubles a
    // vertex, which were allocated and zeroed for nothing: callgrind put 3.2 M of the bunny's 247 M
    // instructions at 10 % in that memset). Every use of aq_ is behind dims_ > 0.
    aq_ = AttributeQuadrics(dims_ > 0 ? nv : 0, dims_);
    const bool boxes = dims_ > 0 && params_.placement == Placement::optimal;
    if (boxes) {
        attr_lo_.assign(nv * dims_, std::numeric_limits<double>::infinity());
        attr_hi_.assign(nv * dims_, -std::numeric_limits<double>::infinity());
    }

    // Quadrics.
    for (std::uint32_t f = 0; f < nf; ++f) {
        if (!face_alive_[f]) continue;
        const std::uint32_t* c = &corners_[3 * f];
        const Vec3d p0 = pts_[pid_[c[0]]].pos, p1 = pts_[pid_[c[1]]].pos, p2 = pts_[pid_[c[2]]].pos;
        const Vec3d n = crossd(sub(p1, p0), sub(p2, p0));
        const double len = std::sqrt(dotd(n, n));
        if (!(len > 0)) continue;
        const double area = face_weight(0.5 * len);
        const Vec3d un{n.x / len, n.y / len, n.z / len};
        const Quadric q = Quadric::from_plane(un, -dotd(un, p0), area);
        for (int k = 0; k < 3; ++k) geo_[pid_[c[k]]] += q;
        if (dims_ > 0) {
            const std::size_t wedges[3] = {c[0], c[1], c[2]};
            // The plain area whatever area_weight says: the attribute error is an integral (combine()).
            aq_.add_triangle(wedges, 3, p0, p1, p2, attr(c[0]), attr(c[1]), attr(c[2]), 0.5 * len);
            if (boxes)
                for (int k = 0; k < 3; ++k)
                    for (int m = 0; m < 3; ++m) merge_box(c[k], attr(c[m]), attr(c[m]));
        }
    }
    point_alive_.assign(points_, 1);
    // One material on every face (glTF meshes carry face_materials even with a single material) makes
    // (wedge, material) classes the wedges alone, as without materials. Not for the greedy schedule,
    // which is kept as it was (its after_collapse() reads a ring the fused paths do not leave behind).
    one_material_ = greedy_ ? mesh_.face_materials.empty()
                            : std::adjacent_find(mesh_.face_materials.begin(), mesh_.face_materials.end(),
                                                 std::not_equal_to<>()) == mesh_.face_materials.end();
    fusable_ = one_material_ && params_.extra_frames.empty() && params_.placement == Placement::half_edge;
    plain_ = dims_ == 0 && fusable_;
    // Artist control: per point, the largest importance of its vertices and locked if any is. The
    // fused and plain paths cost without the importance factor, so importance takes the general path.
    if (!params_.importance.empty()) {
        importance_.assign(points_, 0.f);
        for (std::size_t i = 0; i < nv; ++i) importance_[pid_[i]] = std::max(importance_[pid_[i]], params_.importance[i]);
        fusable_ = plain_ = false;
    }
    if (std::any_of(params_.seam_weights.begin(), params_.seam_weights.end(), [](float x) { return x != 1.f; })) {
        // Per point, the largest weight of the seam classes it lies on.
        seam_factor_.assign(points_, 1.f);
        const SeamReport seams = classify_seams(mesh_);
        for (std::size_t c = 0; c < params_.seam_weights.size(); ++c)
            for (const auto& [e0, e1] : seams.edges[c])
                for (const std::uint32_t p : {pid_[e0], pid_[e1]}) seam_factor_[p] = std::max(seam_factor_[p], params_.seam_weights[c]);
        fusable_ = plain_ = false;
    }
    if (!params_.lock.empty()) {
        pinned_.assign(points_, 0);
        for (std::size_t i = 0; i < nv; ++i) pinned_[pid_[i]] |= params_.lock[i] != 0;
    }
    if (greedy_) heap_.reset(points_);  // the pass schedule has no heap (28 bytes a point, set or reserved)
    if (!params_.extra_frames.empty()) setup_frames();
}

// Point → live faces (ascending face index), from the corners as they are now. The live faces are kept as
// a list compacted here, so late rounds (few faces left) do not scan the dead ones.
void Simplifier::build_csr() {
    if (!live_listed_) {
        live_faces_.clear();
        for (std::uint32_t f = 0; f < face_alive_.size(); ++f)
            if (face_alive_[f]) live_faces_.push_back(f);
        live_listed_ = true;
    } else {
        std::erase_if(live_faces_, [&](std::uint32_t f) { return !face_alive_[f]; });
    }
    csr_begin_.assign(points_ + 1, 0);
    for (std::uint32_t f : live_faces_)
        for (int k = 0; k < 3; ++k) ++csr_begin_[fpt_[3 * f + k] + 1];
    for (std::size_t p = 0; p < points_; ++p) csr_begin_[p + 1] += csr_begin_[p];
    csr_faces_.resize(csr_begin_[points_]);
    scratch_fill_.assign(csr_begin_.begin(), csr_begin_.end() - 1);
    for (std::uint32_t f : live_faces_)
        for (int k = 0; k < 3; ++k) csr_faces_[scratch_fill_[fpt_[3 * f + k]]++] = f;
}

// Constraint plane through edge pq, perpendicular to its (first) face (GH97 §6.1), weighted factor x |pq|².
void Simplifier::add_edge_plane(std::uint32_t p, std::uint32_t q, double factor) {
    for (std::uint32_t f : faces_of(p)) {
        const std::uint32_t* cc = &fpt_[3 * f];
        if (cc[0] != q && cc[1] != q && cc[2] != q) continue;
        const Vec3d a0 = pts_[cc[0]].pos, a1 = pts_[cc[1]].pos, a2 = pts_[cc[2]].pos;
        const Vec3d n = crossd(sub(a1, a0), sub(a2, a0));
        const Vec3d e = sub(pts_[q].pos, pts_[p].pos);
        Vec3d m = crossd(e, n);
        const double len = std::sqrt(dotd(m, m));
        if (!(len > 0)) return;
        m = {m.x / len, m.y / len, m.z / len};
        Quadric bq = Quadric::from_plane(m, -dotd(m, pts_[p].pos), factor * constraint_weight(dotd(e, e), 0.5 * std::sqrt(dotd(n, n))));
        bq.weight = 0;  // a constraint, not surface: it must not dilute the mean
        geo_[p] += bq;
        geo_[q] += bq;
        if (frames_ > 0) add_frame_border_planes(p, q, f, factor);
        return;
    }
}

// Edge pq (two faces) is a seam: the faces on either side use different wedges at p or at q (UV or
// normal seams, and welded cracks of scans). Seams get the border constraint plane too, as
// meshoptimizer does: a seam point only slides along its seam, and the plane keeps the seam's shape.
bool Simplifier::is_seam_edge(std::uint32_t p, std::uint32_t q) const {
    std::uint32_t wp = kNone, wq = kNone;
    for (std::uint32_t f : faces_of(p)) {
        const std::uint32_t* fp = &fpt_[3 * f];
        const std::uint32_t* c = &corners_[3 * f];
        std::uint32_t a = kNone, b = kNone;
        for (int k = 0; k < 3; ++k) {
            if (fp[k] == p) a = c[k];
            else if (fp[k] == q) b = c[k];
        }
        if (b == kNone) continue;
        if (wp == kNone) {
            wp = a;
            wq = b;
        } else if (a != wp || b != wq) {
            return true;
        }
    }
    return false;
}

void Simplifier::classify_points() {
    // Neighbour counts per point: an edge with one face is a border edge, with more than two non-manifold.
    // The neighbours keep their order of first appearance (the constraint planes are added in it); the
    // stamped marks replace a search of the list, and counts saturate (only 1, 2 and more matter).
    std::vector<std::uint32_t> ring;
    std::vector<std::uint8_t> count(points_, 0);
    for (std::uint32_t p = 0; p < points_; ++p) {
        ring.clear();
        const std::uint32_t stamp = next_seen();
        for (std::uint32_t f : faces_of(p))
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t q = fpt_[3 * f + k];
                if (q == p) continue;
                if (pts_[q].seen != stamp) {
                    pts_[q].seen = stamp;
                    count[q] = 1;
                    ring.push_back(q);
                } else if (count[q] < 3) {
                    ++count[q];
                }
            }
        int border = 0;
        bool complex = false;
        for (const std::uint32_t q : ring) {
            const int c = count[q];
            if (c == 2 && q > p && !(pts_[p].one_wedge && pts_[q].one_wedge) && is_seam_edge(p, q)) {
                add_edge_plane(p, q, 1.0);
            } else if (c == 1) {
                ++border;
                if (q > p) add_edge_plane(p, q, kBorderPlaneWeight);
            } else if (c > 2) {
                complex = true;
            }
        }
        if (complex || (border != 0 && border != 2))
            pts_[p].kind = params_.lock_border && border != 0 ? Kind::locked : Kind::complex;
        else if (border == 2) pts_[p].kind = params_.lock_border ? Kind::locked : Kind::border;
        // A point with many (wedge, material) classes (a corner of several seams) stays.
        int classes = 0;
        for (std::uint32_t i = wedge_begin_[p]; i < wedge_begin_[p + 1]; ++i) ++classes;
        if (classes > kMaxClasses / 2 || pinned(p)) pts_[p].kind = Kind::locked;
    }
}

void Simplifier::neighbours(std::uint32_t p, std::vector<std::uint32_t>& out) {
    out.clear();
    const auto faces = faces_of(p);
    for (std::uint32_t f : faces) prefetch(&fpt_[3 * f]);
    const std::uint32_t stamp = next_seen();
    pts_[p].seen = stamp;
    for (std::uint32_t f : faces) {
        if (killed(&fpt_[3 * f])) continue;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t q = fpt_[3 * f + k];
            if (pts_[q].seen != stamp) {
                pts_[q].seen = stamp;
                out.push_back(q);
            }
        }
    }
}

// Cost of moving point u onto point v (infinity when not allowed); fills the wedge mapping. Without
// `full`, an interior point with one wedge moving onto a point with one wedge skips the face walk (the
// mapping is trivial); the collapse itself always re-evaluates with `full`.
double Simplifier::evaluate(std::uint32_t u, std::uint32_t v, Plan& plan, bool full) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (pts_[u].kind == Kind::locked) return inf;  // locked points stay, but others may move onto them
    // A complex point moving onto an interior or border point would make that one complex: it may only
    // join complex or locked points (meshoptimizer's rule).
    if (pts_[u].kind == Kind::complex && pts_[v].kind != Kind::complex && pts_[v].kind != Kind::locked) return inf;
    plan.count = 0;
    plan.edge_faces = 0;
    if (!full && pts_[u].kind == Kind::interior && one_material_ && pts_[u].one_wedge &&
        pts_[v].one_wedge) {
        plan.count = 1;
        plan.material[0] = 0;
        // Only attribute costs read the wedges (0 stands in for geometry-only runs: unused, not kNone).
        plan.wedge[0] = dims_ > 0 ? pts_[u].wedge : 0;
        plan.target[0] = dims_ > 0 ? pts_[v].wedge : 0;
        plan.edge_faces = -1;  // not counted
    }
    if (plan.count == 0) for (std::uint32_t f : faces_of(u)) {
        const std::uint32_t* c = &corners_[3 * f];
        const std::uint32_t* fp = &fpt_[3 * f];
        if (killed(fp)) continue;
        std::uint32_t wu = kNone, wv = kNone;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t q = fp[k];
            if (q == u) wu = c[k];
            else if (q == v) wv = c[k];
        }
        const std::uint32_t mat = material(f);
        int i = 0;
        while (i < plan.count && !(plan.wedge[i] == wu && plan.material[i] == mat)) ++i;
        if (i == plan.count) {
            if (plan.count == kMaxClasses) return inf;
            plan.wedge[i] = wu;
            plan.material[i] = mat;
            plan.target[i] = kNone;
            ++plan.count;
        }
        if (wv == kNone) continue;
        ++plan.edge_faces;
        if (plan.target[i] == kNone) plan.target[i] = wv;
        else if (plan.target[i] != wv) return inf;  // the class would have to split
    }
    return plan_cost(u, v, plan);
}

double Simplifier::plan_cost(std::uint32_t u, std::uint32_t v, Plan& plan) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (plan.edge_faces == 0) return inf;
    if (pts_[u].kind == Kind::border && plan.edge_faces != 1) return inf;  // border points slide along the border
    // Every class must be carried by a collapsing face: otherwise a seam (or material border) through u
    // would be dragged across the surface.
    for (int i = 0; i < plan.count; ++i) {
        if (plan.target[i] != kNone) continue;
        if (params_.preserve_seams) return inf;
        // Seams may close: take the target of another class of the same wedge, or any target.
        for (int j = 0; j < plan.count; ++j)
            if (plan.target[j] != kNone && (plan.wedge[j] == plan.wedge[i] || plan.target[i] == kNone))
                plan.target[i] = plan.target[j];
    }
    // One wedge must map to one wedge (two materials sharing a wedge must agree).
    for (int i = 0; i < plan.count; ++i)
        for (int j = i + 1; j < plan.count; ++j)
            if (plan.wedge[i] == plan.wedge[j] && plan.target[i] != plan.target[j]) return inf;

    // Half-edge: v stays where it is, so its own error is already paid; the cost is the error of u's
    // region at p_v, a mean over u's area (adding v's area would let large points swallow neighbours
    // cheaply). Optimal placement moves both, so both quadrics count.
    const bool half_edge = params_.placement == Placement::half_edge;
    Quadric q = geo_[u];
    if (!half_edge) q += geo_[v];
    plan.position = pts_[v].pos;
    if (params_.placement == Placement::optimal) {
        Vec3d p;
        if (optimal_position(q, p)) {
            // Keep the optimum near the edge: far solutions come from nearly flat quadrics.
            const Vec3d e = sub(pts_[u].pos, pts_[v].pos);
            const Vec3d d = sub(p, pts_[v].pos);
            if (dotd(d, d) <= 4 * dotd(e, e)) plan.position = p;
        }
        if (q.evaluate(pts_[u].pos) < q.evaluate(plan.position) && pts_[v].kind == Kind::interior) plan.position = pts_[u].pos;
        if (pinned(v)) plan.position = pts_[v].pos;  // a locked point never moves
    }
    const double geometric = q.evaluate(plan.position);
    double cost = 0;  // attributes
    if (dims_ > 0 && !half_edge) {
        cost = merged_attribute_cost(v, plan);
    } else if (dims_ > 0) {
        for (int i = 0; i < plan.count; ++i) {
            bool first = true;  // a wedge with two material classes is counted once
            for (int j = 0; j < i; ++j) first = first && plan.wedge[j] != plan.wedge[i];
            if (first) cost += aq_.evaluate(plan.wedge[i], plan.position, attr(plan.target[i]));
        }
    }
    const double factor = importance_factor(u, v);
    if (frames_ > 0) return factor * frames_cost(u, v, geometric, cost, q.weight);
    return factor * combine(geometric, cost, q.weight);
}

// Optimal placement re-solves every wedge's attributes at the new position (run() writes them out), so a
// collapse costs, per wedge of v, the minimum over attribute values of its quadric merged with those of
// u's wedges that map onto it: the cost is taken at the attributes the result will have (as
// meshoptimizer's vertex update does), not at v's old ones.
double Simplifier::merged_attribute_cost(std::uint32_t v, const Plan& plan) const {
    double cost = 0;
    std::size_t idx[kMaxClasses + 1];
    for (std::uint32_t k = wedge_begin_[v]; k < wedge_begin_[v + 1]; ++k) {
        const std::uint32_t w = wedge_list_[k];
        std::size_t n = 0;
        idx[n++] = w;
        for (int i = 0; i < plan.count; ++i) {
            if (plan.target[i] != w) continue;
            bool first = true;  // a wedge with two material classes is counted once
            for (std::size_t j = 1; j < n; ++j) first = first && idx[j] != plan.wedge[i];
            if (first) idx[n++] = plan.wedge[i];
        }
        cost += aq_.minimum(idx, n, plan.position);
    }
    return cost;
}

// Neighbours and classes kept on the stack by for_each_cost() (a point with more: evaluated one by one).
constexpr int kBatchNeighbours = 32;

template <class F>
bool Simplifier::for_each_cost(std::uint32_t p, F&& f) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    const PointRec& rp = pts_[p];
    // The classes of p in evaluate()'s order (first appearance over p's live faces) and, per neighbour
    // (first appearance, as neighbours() lists them), the wedge each class maps to, the faces along the
    // edge and whether a class would split.
    std::uint32_t cls_wedge[kMaxClasses], cls_material[kMaxClasses];
    int classes = 0;
    std::uint32_t cand[kBatchNeighbours];
    std::uint32_t target[kBatchNeighbours][kMaxClasses];
    int edges[kBatchNeighbours];
    bool split[kBatchNeighbours];
    int count = 0;
    for (std::uint32_t face : faces_of(p)) {
        const std::uint32_t* c = &corners_[3 * face];
        const std::uint32_t* fp = &fpt_[3 * face];
        if (killed(fp)) continue;
        const int k = fp[0] == p ? 0 : fp[1] == p ? 1 : 2;
        const std::uint32_t wu = c[k], mat = material(face);
        int i = 0;
        while (i < classes && !(cls_wedge[i] == wu && cls_material[i] == mat)) ++i;
        if (i == classes) {
            if (classes == kMaxClasses) return false;
            cls_wedge[i] = wu;
            cls_material[i] = mat;
            ++classes;
        }
        for (int m = 0; m < 3; ++m) {
            if (m == k) continue;
            const std::uint32_t q = fp[m];
            int j = 0;
            while (j < count && cand[j] != q) ++j;
            if (j == count) {
                if (count == kBatchNeighbours) return false;
                cand[j] = q;
                for (int t = 0; t < kMaxClasses; ++t) target[j][t] = kNone;
                edges[j] = 0;
                split[j] = false;
                ++count;
            }
            ++edges[j];
            if (target[j][i] == kNone) target[j][i] = c[m];
            else if (target[j][i] != c[m]) split[j] = true;
        }
    }
    Plan plan;
    for (int j = 0; j < count; ++j) {
        const std::uint32_t v = cand[j];
        // evaluate()'s checks before its face walk, then its plan.
        if (rp.kind == Kind::locked ||
            (rp.kind == Kind::complex && pts_[v].kind != Kind::complex && pts_[v].kind != Kind::locked)) {
            f(v, inf);
            continue;
        }
        if (rp.kind == Kind::interior && one_material_ && rp.one_wedge && pts_[v].one_wedge) {
            plan.count = 1;
            plan.material[0] = 0;
            plan.wedge[0] = dims_ > 0 ? pts_[p].wedge : 0;
            plan.target[0] = dims_ > 0 ? pts_[v].wedge : 0;
            plan.edge_faces = -1;
        } else {
            if (split[j]) {
                f(v, inf);
                continue;
            }
            plan.count = classes;
            for (int i = 0; i < classes; ++i) {
                plan.wedge[i] = cls_wedge[i];
                plan.material[i] = cls_material[i];
                plan.target[i] = target[j][i];
            }
            plan.edge_faces = edges[j];
        }
        f(v, plan_cost(p, v, plan));
    }
    return true;
}

bool Simplifier::valid(std::uint32_t u, std::uint32_t v, const Plan& plan) {
    // Link condition on points: the common neighbours of u and v are exactly the apexes of uv's faces.
    neighbours(u, scratch_a_);
    neighbours(v, scratch_b_);
    const std::uint32_t ring = next_ring();
    for (std::uint32_t b : scratch_b_) pts_[b].ring = ring;
    int common = 0;
    for (std::uint32_t a : scratch_a_) common += pts_[a].ring == ring;
    if (common != plan.edge_faces) return false;
    if (std::size_t(plan.edge_faces) >= alive_faces_) return false;  // it would remove the last faces

    const double min_dot = params_.min_normal_dot;
    auto face_ok = [&](std::uint32_t f, std::uint32_t moved) {
        const std::uint32_t* c = &fpt_[3 * f];
        Vec3d p[3], q[3];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t pt = c[k];
            p[k] = pts_[pt].pos;
            q[k] = pt == moved ? plan.position : pts_[pt].pos;
        }
        const Vec3d n0 = crossd(sub(p[1], p[0]), sub(p[2], p[0]));
        const Vec3d n1 = crossd(sub(q[1], q[0]), sub(q[2], q[0]));
        const double l0 = dotd(n0, n0), l1 = dotd(n1, n1);
        if (!(l0 > 0)) return true;  // was degenerate already: nothing to flip
        double longest = 0;
        for (int k = 0; k < 3; ++k) {
            const Vec3d e = sub(q[(k + 1) % 3], q[k]);
            longest = std::max(longest, dotd(e, e));
        }
        if (!(l1 > 1e-12 * longest * longest)) return false;  // would become a needle or collapse
        return dotd(n0, n1) >= min_dot * std::sqrt(l0 * l1);
    };
    for (std::uint32_t f : faces_of(u)) {
        const std::uint32_t* c = &fpt_[3 * f];
        const std::uint32_t a = c[0], b = c[1], cc = c[2];
        if (a == v || b == v || cc == v || killed(c)) continue;  // removed with the collapse (or before)
        if (!face_ok(f, u)) return false;
        // A face whose other two points are both common neighbours may already exist around v
        // (tetrahedron-like configurations the vertex link test misses).
        const std::uint32_t o1 = a == u ? b : a, o2 = cc == u ? b : cc;
        const bool c1 = pts_[o1].ring == ring, c2 = pts_[o2].ring == ring;
        if (c1 && c2) {
            for (std::uint32_t g : faces_of(v)) {
                const std::uint32_t* d = &fpt_[3 * g];
                if (killed(d)) continue;
                int hits = 0;
                for (int k = 0; k < 3; ++k) hits += (d[k] == o1 || d[k] == o2);
                if (hits == 2) return false;
            }
        }
    }
    if (params_.placement == Placement::optimal) {
        for (std::uint32_t f : faces_of(v)) {
            const std::uint32_t* c = &fpt_[3 * f];
            if (c[0] == u || c[1] == u || c[2] == u || killed(c)) continue;
            if (!face_ok(f, v)) return false;
        }
    }
    if (!uv_sets_.empty() && !texture_kept(u, v, plan)) return false;
    return frames_ == 0 || frames_valid(u, v);
}

// No face of u that survives the collapse turns its texture over: in every weighted texcoord set, the
// face's UV triangle with u's wedge replaced by its target keeps its orientation and a non-zero area.
// Neither the normal test nor the attribute cost sees a fold: a face may turn by up to
// acos(min_normal_dot) in space while its UV triangle folds over, and the attribute planes extrapolate
// smoothly past it; a folded UV triangle draws a mirrored strip of texture from beyond its neighbours,
// often from beyond the chart's edge (laurana500 at 20 %: 389 px of wrong texture along seams, 238 px
// without folds; docs/image-compare.md, "Seam slits"). Mirrored charts are fine: each face is compared
// with its own orientation.
bool Simplifier::texture_kept(std::uint32_t u, std::uint32_t v, const Plan& plan) const {
    for (std::uint32_t f : faces_of(u)) {
        const std::uint32_t* fp = &fpt_[3 * f];
        if (killed(fp) || fp[0] == v || fp[1] == v || fp[2] == v) continue;  // removed with the collapse
        const std::uint32_t* c = &corners_[3 * f];
        const int k = fp[0] == u ? 0 : fp[1] == u ? 1 : 2;
        int i = 0;
        while (i < plan.count && plan.wedge[i] != c[k]) ++i;
        if (i == plan.count || plan.target[i] == c[k]) continue;
        for (const std::vector<Vec2f>* set : uv_sets_) {
            const Vec2f a = (*set)[c[(k + 1) % 3]], b = (*set)[c[(k + 2) % 3]];
            auto area = [&](Vec2f p) {
                return (double(a.x) - p.x) * (double(b.y) - p.y) - (double(a.y) - p.y) * (double(b.x) - p.x);
            };
            const double before = area((*set)[c[k]]);
            if (before != 0 && !(area((*set)[plan.target[i]]) * before > 0)) return false;
        }
    }
    return true;
}

double Simplifier::plain_plan(std::uint32_t u, std::uint32_t v, Plan& plan) const {
    plan.count = 1;
    plan.material[0] = 0;
    plan.wedge[0] = pts_[u].wedge;
    plan.target[0] = pts_[v].wedge;
    plan.position = pts_[v].pos;
    plan.edge_faces = -1;  // plain_valid() counts them
    const Quadric& q = geo_[u];
    const double e = q.evaluate(plan.position);
    return q.weight > 0 ? e / q.weight : e * 1e12;
}

double Simplifier::fused_plan(std::uint32_t u, std::uint32_t v, Plan& plan) {
    plan.count = 1;
    plan.material[0] = 0;
    plan.wedge[0] = pts_[u].wedge;
    plan.target[0] = pts_[v].wedge;
    plan.edge_faces = 1;  // plain_valid() counts them
    plan.position = pts_[v].pos;
    return fused_cost(u, v);
}

// valid() for a plain pair: v's ring is marked first, so u's neighbours, the common count, the faces
// along uv, the flip and needle checks and the twin-face check all come from one walk over u's faces.
// Leaves u's ring in scratch_a_ as valid() does.
template <bool kFaceOrder>
bool Simplifier::plain_valid(std::uint32_t u, std::uint32_t v, const Plan& plan) {
    const std::uint32_t ring = next_ring();
    for (std::uint32_t g : faces_of(v)) {
        const std::uint32_t* d = &fpt_[3 * g];
        if (killed(d)) continue;
        pts_[d[0]].ring = pts_[d[1]].ring = pts_[d[2]].ring = ring;
    }
    pts_[v].ring = 0;  // v's ring proper (u is in it, but never counted: it is not u's neighbour)
    scratch_a_.clear();
    const std::uint32_t stamp = next_seen();
    pts_[u].seen = stamp;
    int common = 0, edge_faces = 0;
    bool ok = true;
    const double min_dot = params_.min_normal_dot;
    const Vec3d pu = pts_[u].pos, pv = plan.position;
    for (std::uint32_t f : faces_of(u)) {
        const std::uint32_t* c = &fpt_[3 * f];
        if (killed(c)) continue;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t q = c[k];
            if (pts_[q].seen != stamp) {
                pts_[q].seen = stamp;
                scratch_a_.push_back(q);
                common += pts_[q].ring == ring;
            }
        }
        if (!ok) continue;  // the ring is still needed whole
        if (c[0] == v || c[1] == v || c[2] == v) {
            ++edge_faces;
            continue;
        }
        // u's other two points, in the face's winding: (u, o1, o2).
        const int k = c[0] == u ? 0 : c[1] == u ? 1 : 2;
        const std::uint32_t o1 = c[(k + 1) % 3], o2 = c[(k + 2) % 3];
        const Vec3d p1 = pts_[o1].pos, p2 = pts_[o2].pos;
        Vec3d n0, n1;
        if constexpr (kFaceOrder) {
            Vec3d a[3], b[3];
            for (int j = 0; j < 3; ++j) {
                a[j] = c[j] == u ? pu : pts_[c[j]].pos;
                b[j] = c[j] == u ? pv : a[j];
            }
            n0 = crossd(sub(a[1], a[0]), sub(a[2], a[0]));
            n1 = crossd(sub(b[1], b[0]), sub(b[2], b[0]));
        } else {
            n0 = crossd(sub(p1, pu), sub(p2, pu));
            n1 = crossd(sub(p1, pv), sub(p2, pv));
        }
        const double l0 = dotd(n0, n0), l1 = dotd(n1, n1);
        if (l0 > 0) {
            const Vec3d e0 = sub(p1, pv), e1 = sub(p2, p1), e2 = sub(pv, p2);
            const double longest = std::max({dotd(e0, e0), dotd(e1, e1), dotd(e2, e2)});
            if (!(l1 > 1e-12 * longest * longest) || dotd(n0, n1) < min_dot * std::sqrt(l0 * l1)) {
                ok = false;
                continue;
            }
        }
        if (pts_[o1].ring == ring && pts_[o2].ring == ring) {
            for (std::uint32_t g : faces_of(v)) {
                const std::uint32_t* d = &fpt_[3 * g];
                if (killed(d)) continue;
                int hits = 0;
                for (int j = 0; j < 3; ++j) hits += (d[j] == o1 || d[j] == o2);
                if (hits == 2) {
                    ok = false;
                    break;
                }
            }
        }
    }
    // A border point slides along its border: onto a neighbour over one face only (as in evaluate()).
    if (pts_[u].kind == Kind::border && edge_faces != 1) return false;
    // A collapse that would remove the last faces (a lone triangle, fins on one edge) is refused: a target
    // of one triangle must not end in an empty mesh.
    return ok && edge_faces > 0 && common == edge_faces && std::size_t(edge_faces) < alive_faces_;
}

void Simplifier::collapse(std::uint32_t u, std::uint32_t v, const Plan& plan) {
    // Wedge targets (a wedge of u that no face uses follows the first class, so replays stay exact).
    auto target_of = [&](std::uint32_t w) {
        for (int i = 0; i < plan.count; ++i)
            if (plan.wedge[i] == w) return plan.target[i];
        return plan.target[0];
    };
    for (std::uint32_t f : faces_of(u)) {
        std::uint32_t* c = &corners_[3 * f];
        std::uint32_t* fp = &fpt_[3 * f];
        if (killed(fp)) continue;
        if (fp[0] == v || fp[1] == v || fp[2] == v) {
            face_alive_[f] = 0;
            --alive_faces_;
            if (greedy_)
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t apex = fp[k];
                    if (apex != u && apex != v) std::erase(pfaces_[apex], f);
                }
            // The apex's CSR entry stays for the rest of the pass; two equal corners mark the face killed.
            for (int k = 0; k < 3; ++k)
                if (fp[k] == u) fp[k] = v;
            continue;
        }
        for (int k = 0; k < 3; ++k)
            if (fp[k] == u) {
                c[k] = target_of(c[k]);
                fp[k] = v;
            }
        if (greedy_) pfaces_[v].push_back(f);
    }
    if (greedy_) {
        std::vector<std::uint32_t>().swap(pfaces_[u]);
        std::erase_if(pfaces_[v], [&](std::uint32_t f) { return !face_alive_[f]; });
    }

    geo_[v] += geo_[u];
    for (std::size_t f = 0; f < frames_; ++f) frame_geo_[v * frames_ + f] += frame_geo_[u * frames_ + f];
    Collapse rec;
    rec.from_point = u;
    rec.to_point = v;
    rec.moves_begin = static_cast<std::uint32_t>(result_.moves.size());
    const bool one = pts_[u].one_wedge;
    for (std::uint32_t k = one ? 0 : wedge_begin_[u], e = one ? 1 : wedge_begin_[u + 1]; k < e; ++k) {
        const std::uint32_t w = one ? pts_[u].wedge : wedge_list_[k];
        const std::uint32_t t = target_of(w);
        // A wedge no live face uses may still hold faces of another chart in its quadric; optimal
        // placement solves attributes from the quadrics, so it drops them rather than mix charts.
        bool in_plan = false;
        for (int i = 0; i < plan.count; ++i) in_plan = in_plan || plan.wedge[i] == w;
        if (dims_ > 0 && (attr_lo_.empty() || in_plan)) aq_.accumulate(t, w);
        if (!attr_lo_.empty() && in_plan && t != w) merge_box(t, &attr_lo_[w * dims_], &attr_hi_[w * dims_]);
        result_.moves.push_back({w, t});
    }
    rec.moves_end = static_cast<std::uint32_t>(result_.moves.size());
    result_.collapses.push_back(rec);
    pts_[v].pos = plan.position;
    if (!importance_.empty()) importance_[v] = std::max(importance_[v], importance_[u]);  // v stands for u's region
    point_alive_[u] = 0;
}

// The cheapest outgoing collapse of p (validity is checked when it is popped).
std::uint32_t Simplifier::cheapest(std::uint32_t p, double& best) {
    best = std::numeric_limits<double>::infinity();
    std::uint32_t to = kNone;
    const bool pen = height_weight_ > 0;
    const Vec3d nb = pen ? fan_normal(p) : Vec3d{0, 0, 0};
    if (plain_ && pts_[p].kind == Kind::interior && pts_[p].one_wedge)
        return pen ? cheapest_plain<true>(p, best, nb) : cheapest_plain<false>(p, best, nb);
    if (plain_ && pts_[p].kind == Kind::border && pts_[p].one_wedge && faces_of(p).size() <= kPlainBorderFaces && !pen)
        return cheapest_plain_border(p, best);
    if (fusable_ && !greedy_ && pts_[p].kind == Kind::interior && pts_[p].one_wedge) {
        // Attribute run, one-wedge interior point: what for_each_cost() gives (the same neighbours in the
        // same order, the same plans), without its per-neighbour class table: a one-wedge neighbour
        // has the trivial mapping, a seam neighbour's is evaluate()'s.
        Plan plan;
        const auto faces = faces_of(p);
        for (std::uint32_t f : faces) prefetch(&fpt_[3 * f]);
        for (std::uint32_t f : faces)
            for (int k = 0; k < 3; ++k) prefetch_point(fpt_[3 * f + k]);
        const std::uint32_t stamp = next_seen();
        pts_[p].seen = stamp;
        for (std::uint32_t f : faces) {
            const std::uint32_t* fp = &fpt_[3 * f];
            if (killed(fp)) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t n = fp[k];
                if (pts_[n].seen == stamp) continue;
                pts_[n].seen = stamp;
                double c = pts_[n].one_wedge ? fused_cost(p, n) : evaluate(p, n, plan, false);
                if (pen && std::isfinite(c)) c += penalty(p, n, nb);
                if (c < best) {
                    best = c;
                    to = n;
                }
            }
        }
        return to;
    }
    auto consider = [&](std::uint32_t n, double c) {
        if (pen && std::isfinite(c)) c += penalty(p, n, nb);
        if (c < best) {
            best = c;
            to = n;
        }
    };
    // (The greedy schedule reads v's neighbours from scratch_n_ after update_best(v): it keeps the list.)
    if (!greedy_ && for_each_cost(p, consider)) return to;
    Plan plan;
    neighbours(p, scratch_n_);
    for (std::uint32_t n : scratch_n_) prefetch_point(n);
    for (std::uint32_t n : scratch_n_) consider(n, evaluate(p, n, plan, false));
    return to;
}

// cheapest() for a one-wedge interior point in a plain run (geometry only, half-edge): a function of its own,
// with the height term a template argument, so that its loop is compiled alone (callgrind: inside cheapest()
// GCC left Quadric::evaluate an out-of-line call, and forcing it inline there cost more than the call).
template <bool pen>
std::uint32_t Simplifier::cheapest_plain(std::uint32_t p, double& best, const Vec3d& nb) {
    std::uint32_t to = kNone;
    // Geometry only, half-edge, one wedge: the cost is Q_p at the neighbour over p's area (what
    // evaluate() computes without a face walk). The neighbours are read straight off the faces.
    // The one-wedge neighbours are compared by Q_p alone and only the least is divided by the
    // area (a division per neighbour was a fifth of re-costing): the same cost, and the same
    // target unless two errors round to one cost.
    const Quadric& q = geo_[p];
    Plan plan;
    const auto faces = faces_of(p);
    for (std::uint32_t f : faces) prefetch(&fpt_[3 * f]);
    for (std::uint32_t f : faces)
        for (int k = 0; k < 3; ++k) prefetch_point(fpt_[3 * f + k]);
    double least = std::numeric_limits<double>::infinity();
    std::uint32_t least_to = kNone;
    std::size_t least_at = 0, best_at = 0, at = 0;
    // A neighbour's second appearance (each interior edge has two faces) would give the same cost,
    // which loses every comparison: it is skipped (same result, half the quadric evaluations).
    const std::uint32_t stamp = next_seen();
    pts_[p].seen = stamp;
    for (std::uint32_t f : faces)
        for (int k = 0; k < 3; ++k, ++at) {
            const std::uint32_t n = fpt_[3 * f + k];
            if (pts_[n].seen == stamp) continue;
            pts_[n].seen = stamp;
            if (pen) {
                // The height term differs per neighbour, so each cost is complete (divided as evaluate()
                // divides, so the plain and general paths give the same costs).
                double c = pts_[n].one_wedge ? (q.weight > 0 ? q.evaluate(pts_[n].pos) / q.weight : q.evaluate(pts_[n].pos) * 1e12)
                                             : evaluate(p, n, plan, false);
                if (std::isfinite(c)) c += penalty(p, n, nb);
                if (c < best) {
                    best = c;
                    to = n;
                    best_at = at;
                }
            } else if (pts_[n].one_wedge) {
                const double e = q.evaluate(pts_[n].pos);
                if (e < least) {
                    least = e;
                    least_to = n;
                    least_at = at;
                }
            } else {
                const double c = evaluate(p, n, plan, false);  // onto a seam point: the wedge mapping decides
                if (c < best) {
                    best = c;
                    to = n;
                    best_at = at;
                }
            }
        }
    if (least_to != kNone) {
        const double c = q.weight > 0 ? least / q.weight : least * 1e12;
        if (c < best || (c == best && least_at < best_at)) {
            best = c;
            to = least_to;
        }
    }
    return to;
}

// cheapest() for a one-wedge border point in a plain run: evaluate() allows only the neighbours that
// share one live face with p (its border edges), at Q_p over p's area; they are found from one walk
// over p's faces instead of one face walk per neighbour. Same candidates, order and costs.
std::uint32_t Simplifier::cheapest_plain_border(std::uint32_t p, double& best) {
    best = std::numeric_limits<double>::infinity();
    std::uint32_t to = kNone;
    std::uint32_t ring[2 * kPlainBorderFaces];
    int count = 0;
    for (std::uint32_t f : faces_of(p)) {
        const std::uint32_t* c = &fpt_[3 * f];
        if (killed(c)) continue;
        for (int k = 0; k < 3; ++k)
            if (c[k] != p) ring[count++] = c[k];
    }
    const Quadric& q = geo_[p];
    Plan plan;
    for (int i = 0; i < count; ++i) {
        const std::uint32_t n = ring[i];
        int seen = 0;
        for (int j = 0; j < count; ++j) seen += ring[j] == n;
        if (seen != 1) continue;  // an interior edge of p (evaluate(): infinite)
        double c;
        if (pts_[n].one_wedge) {
            const double e = q.evaluate(pts_[n].pos);
            c = q.weight > 0 ? e / q.weight : e * 1e12;
        } else {
            c = evaluate(p, n, plan, false);  // onto a seam point: the wedge mapping decides
        }
        if (c < best) {
            best = c;
            to = n;
        }
    }
    return to;
}

// The cheapest collapse of p that is allowed now (other than onto `rejected`), or kNone.
std::uint32_t Simplifier::cheapest_valid(std::uint32_t u, std::uint32_t rejected, double& cost) {
    Plan plan;
    options_.clear();
    const bool pen = height_weight_ > 0;
    const Vec3d nb = pen ? fan_normal(u) : Vec3d{0, 0, 0};
    auto option = [&](std::uint32_t n, double c) {
        if (n != rejected && std::isfinite(c)) options_.emplace_back(pen ? c + penalty(u, n, nb) : c, n);
    };
    if (greedy_ || !for_each_cost(u, option)) {
        neighbours(u, scratch_n_);
        for (std::uint32_t n : scratch_n_) option(n, evaluate(u, n, plan, false));
    }
    std::sort(options_.begin(), options_.end());
    for (const auto& [estimate, n] : options_) {
        const double c = evaluate(u, n, plan, true);
        if (!std::isfinite(c) || !valid(u, n, plan)) continue;
        cost = pen ? c + penalty(u, n, nb) : c;
        return n;
    }
    return kNone;
}

void Simplifier::update_best(std::uint32_t p) {
    pts_[p].constrained = 0;
    double best;
    const std::uint32_t to = cheapest(p, best);
    if (to == kNone) {
        heap_.remove(p);
        return;
    }
    pts_[p].best_to = to;
    heap_.set(p, best);
}

// u → rejected is not allowed now: u's entry becomes its cheapest valid collapse, or u leaves the heap
// until its neighbourhood changes.
void Simplifier::reroute(std::uint32_t u, std::uint32_t rejected) {
    pts_[u].constrained = 1;
    double c;
    const std::uint32_t n = cheapest_valid(u, rejected, c);
    if (n == kNone) {
        heap_.remove(u);
        return;
    }
    pts_[u].best_to = n;
    heap_.set(u, c);
}

// After u → v: v's costs all changed; around v only edges to v changed, unless a point's best target was u
// or v (or its entry was constrained), which is then fully re-evaluated.
void Simplifier::after_collapse(std::uint32_t u, std::uint32_t v) {
    heap_.remove(u);
    update_best(v);
    // v's neighbours, read here: update_best() leaves them in scratch_n_ only on its general path (the
    // plain paths read the faces directly), and relying on that left a stale ring behind on plain runs.
    neighbours(v, ring_);
    for (std::uint32_t n : ring_) {
        heap_.prefetch(n);
        prefetch(faces_of(n).data());
    }
    Plan plan;
    for (std::uint32_t n : ring_) {
        if (pts_[n].best_to == u || pts_[n].best_to == v || pts_[n].constrained || !heap_.contains(n)) {
            update_best(n);
            continue;
        }
        const double c = evaluate(n, v, plan, false);
        if (c < heap_.key(n)) {
            pts_[n].best_to = v;
            heap_.set(n, c);
        }
    }
}

// The classic schedule: one heap entry per point, the globally cheapest valid collapse first.
void Simplifier::run_greedy(std::size_t target, double limit, double& max_cost) {
    for (std::uint32_t a = 0; a < points_; ++a) {
        update_best(a);
        if ((a & 0xffff) == 0) check_progress(progress_, 0.0, "simplify");
    }
    std::size_t iterations = 0;
    Plan plan;
    while (true) {
        if (alive_faces_ <= target) {
            result_.reason = SimplifyResult::StopReason::target_reached;
            break;
        }
        if (heap_.empty()) break;
        if ((++iterations & 1023) == 0) report(target);
        const std::uint32_t u = heap_.top(), v = pts_[u].best_to;
        const double cost = evaluate(u, v, plan, true);
        if (!std::isfinite(cost)) {  // the seam mapping forbids it
            reroute(u, v);
            continue;
        }
        if (cost > heap_.key(u) * (1 + 1e-9) + 1e-30) {  // dearer than estimated: requeue
            heap_.set(u, cost);
            continue;
        }
        if (cost > limit) {
            result_.reason = SimplifyResult::StopReason::error_limit;
            break;
        }
        if (!valid(u, v, plan)) {
            reroute(u, v);
            continue;
        }
        max_cost = std::max(max_cost, cost);
        collapse(u, v, plan);
        after_collapse(u, v);
    }
}

void Simplifier::report(std::size_t target) {
    if (!progress_) return;
    const double span = double(start_faces_ - std::min(start_faces_, target));
    check_progress(progress_, span > 0 ? double(start_faces_ - alive_faces_) / span : 1.0, "simplify");
}

// Pass schedule (after meshoptimizer's simplifier, Kapoulkine 2016-): every candidate (a point's cheapest
// outgoing collapse) is costed once, all are sorted (radix sort on the float bits of the cost) and walked
// cheapest first up to kPassSlack times the cost at rank kPassRank; a collapse u → v is applied when
// neither u nor v is locked, and then locks u and v for the rest of the pass (meshoptimizer's rule; locking
// u's whole ring as before took twice the passes). The CSR is not updated inside a pass, yet stays exact
// for every unlocked point: a collapse only renames u to v in u's faces (v is locked, u is gone) and kills
// uv's faces, which collapse() marks by making two corners equal (killed()), so every walk skips them. So
// the link, flip and seam checks of a later collapse of the pass read the mesh as it is, and its cost is
// unchanged (half-edge: Q_u and p_v only change when u or v collapse). After the pass the CSR is rebuilt
// from the compacted live-face list and only the points whose neighbourhood changed are re-costed.
// Nothing depends on the target except where the walk stops, so a run to a lower target starts with
// exactly the collapses of a run to a higher one.
constexpr double kPassRank = 0.25;
constexpr double kPassSlack = 1.5;

void Simplifier::run_passes(std::size_t target, double limit, double& max_cost) {
    // Per point (in PointRec): cost of its entry, the kept point of a collapse next to it (see kGained)
    // and the round that locked it.
    // PointRec::dirty: 0 = entry current, kGained = compare the edge to Round::gained, else re-cost fully.
    constexpr std::uint8_t kGained = 2;
    for (PointRec& r : pts_) r.dirty = 1;
    std::vector<std::uint32_t> alive(points_);
    std::iota(alive.begin(), alive.end(), 0u);
    HugeVector<std::uint64_t> order, tmp;
    order.reserve(points_);
    Plan plan;
    const bool moves_kept = params_.placement == Placement::optimal;
    for (std::uint32_t pass = 1;; ++pass) {
        report(target);
        // Re-cost what changed, in index order (coherent memory), and gather the candidates.
        order.clear();
        std::erase_if(alive, [&](std::uint32_t a) { return !point_alive_[a]; });
        for (std::size_t i = 0; i < alive.size(); ++i) {
            const std::uint32_t a = alive[i];
            if ((i & 0xffff) == 0xffff) report(target);
            // After the first pass the dirty points are sparse: their quadric and face list are cold
            // when cheapest() reads them, so they are fetched a few points ahead.
            if (i + 16 < alive.size()) prefetch_point(alive[i + 16]);
            if (i + 8 < alive.size() && pts_[alive[i + 8]].dirty == 1) {
                const std::uint32_t b = alive[i + 8];
                prefetch(&geo_[b]);
                prefetch(reinterpret_cast<const char*>(&geo_[b]) + 64);
                prefetch(&csr_faces_[csr_begin_[b]]);
            }
            if (pts_[a].dirty == kGained) {
                // Only a new edge to the kept point of a collapse appeared (half-edge: nothing else
                // about this point's costs changed), so it is compared against the current entry.
                pts_[a].dirty = 0;
                const std::uint32_t v = pts_[a].gained;
                if (point_alive_[v]) {
                    // (evaluate() takes the trivial plan for such a pair; fused_cost() is its arithmetic.)
                    const bool trivial = fusable_ && pts_[a].kind == Kind::interior && pts_[a].one_wedge &&
                                         pts_[v].one_wedge;
                    double c = trivial ? fused_cost(a, v) : evaluate(a, v, plan, false);
                    if (height_weight_ > 0 && std::isfinite(c)) c += penalty(a, v, fan_normal(a));
                    if (c < pts_[a].cost) {
                        pts_[a].cost = c;
                        pts_[a].best_to = v;
                    }
                }
            } else if (pts_[a].dirty) {
                pts_[a].dirty = 0;
                double c;
                const std::uint32_t to = pts_[a].constrained ? cheapest_valid(a, kNone, c) : cheapest(a, c);
                pts_[a].constrained = 0;
                pts_[a].best_to = to;
                pts_[a].cost = to == kNone ? std::numeric_limits<double>::infinity() : c;
            }
            if (std::isfinite(pts_[a].cost)) {
                // Non-negative floats order as their bit patterns; the cost is rounded up so a key never
                // undercuts its cost.
                // (The next float up of a non-negative finite float is its bit pattern plus one, FLT_MAX's
                // being +inf: what std::nextafter gives, without its libm call per candidate.)
                const float key = static_cast<float>(pts_[a].cost);
                std::uint32_t bits;
                std::memcpy(&bits, &key, sizeof bits);
                if (double(key) < pts_[a].cost) ++bits;
                order.push_back(std::uint64_t(bits) << 32 | a);
            }
        }
        if (order.empty()) return;  // topology_limit
        // LSD radix sort on the key (bits 32..63), stable, so equal costs keep the point order.
        tmp.resize(order.size());
        for (int shift = 32; shift < 64; shift += 11) {
            std::uint32_t count[2049] = {};
            for (std::uint64_t e : order) ++count[((e >> shift) & 2047) + 1];
            for (int i = 0; i < 2048; ++i) count[i + 1] += count[i];
            for (std::uint64_t e : order) tmp[count[(e >> shift) & 2047]++] = e;
            order.swap(tmp);
        }
        const std::size_t rank = std::min(order.size() - 1, static_cast<std::size_t>(double(order.size()) * kPassRank));
        const double threshold = kPassSlack * pts_[static_cast<std::uint32_t>(order[rank])].cost;
        std::size_t applied = 0;
        bool limited = false, changed = false;
        // The walk jumps across the mesh in cost order, so each candidate's records are cold: they are
        // prefetched in stages (the point, then its target and face list, then the faces' points) far
        // enough ahead that each stage's addresses are loaded by the time the next needs them.
        const std::size_t walk = order.size();
        auto ahead = [&](std::size_t i) {
            if (i + 16 < walk) {
                const auto a = static_cast<std::uint32_t>(order[i + 16]);
                prefetch(&pts_[a]);
                prefetch(&csr_begin_[a]);
            }
            if (i + 8 < walk) {
                const auto a = static_cast<std::uint32_t>(order[i + 8]);
                prefetch(&csr_faces_[csr_begin_[a]]);
                prefetch(&geo_[a]);  // the cost (plain_plan) and the collapse read Q_u (88 bytes)
                prefetch(reinterpret_cast<const char*>(&geo_[a]) + 64);
                const std::uint32_t b = pts_[a].best_to;
                if (b != kNone) {
                    prefetch(&pts_[b]);
                    prefetch(&csr_begin_[b]);
                }
            }
            if (i + 4 < walk) {
                const auto a = static_cast<std::uint32_t>(order[i + 4]);
                for (std::uint32_t k = csr_begin_[a], e = std::min(csr_begin_[a + 1], csr_begin_[a] + 8); k < e; ++k)
                    prefetch(&fpt_[3 * csr_faces_[k]]);
                const std::uint32_t b = pts_[a].best_to;
                if (b != kNone) {
                    prefetch(&csr_faces_[csr_begin_[b]]);
                    prefetch(&geo_[b]);  // Q_v += Q_u
                    prefetch(reinterpret_cast<const char*>(&geo_[b]) + 64);
                }
            }
            if (i + 2 < walk) {
                // v's faces (its ring is marked first) and the corners the collapse rewrites.
                const auto a = static_cast<std::uint32_t>(order[i + 2]);
                const std::uint32_t b = pts_[a].best_to;
                if (b != kNone)
                    for (std::uint32_t k = csr_begin_[b], e = std::min(csr_begin_[b + 1], csr_begin_[b] + 8); k < e; ++k)
                        prefetch(&fpt_[3 * csr_faces_[k]]);
            }
        };
        for (std::size_t i = 0; i < walk; ++i) {
            ahead(i);
            const auto u = static_cast<std::uint32_t>(order[i]);
            if (pts_[u].cost > threshold && applied > 0) break;  // a pass never ends empty-handed
            const std::uint32_t v = pts_[u].best_to;
            if (pts_[u].lock == pass || pts_[v].lock == pass) continue;  // the next pass sees it again
            bool plain = plain_pair(u, v), fused = !plain && fused_pair(u, v);
            double c = plain ? plain_plan(u, v, plan) : fused ? fused_plan(u, v, plan) : evaluate(u, v, plan, true);
            if ((plain || fused) && c > limit && pts_[u].kind == Kind::border) {
                // plain_plan() and fused_plan() do not see a border point's edge count: evaluate() tells
                // a forbidden collapse (infinite) from one over the limit, as for any other pair.
                plain = fused = false;
                c = evaluate(u, v, plan, true);
            }
            if (!std::isfinite(c)) {  // the seam mapping forbids it
                pts_[u].constrained = pts_[u].dirty = 1;
                changed = true;
                continue;
            }
            if (c > limit) {
                pts_[u].cost = c;
                limited = true;
                continue;
            }
            const bool ok = plain   ? plain_valid(u, v, plan)
                            : fused ? plain_valid<true>(u, v, plan) && (uv_sets_.empty() || texture_kept(u, v, plan))
                                    : valid(u, v, plan);
            if (!ok) {
                pts_[u].constrained = pts_[u].dirty = 1;
                changed = true;
                continue;
            }
            // valid() left u's ring in scratch_a_ and v's in scratch_b_.
            for (std::uint32_t n : scratch_a_) {
                if (moves_kept || n == v || pts_[n].best_to == u || pts_[n].best_to == v || pts_[n].constrained ||
                    !std::isfinite(pts_[n].cost) || (pts_[n].dirty == kGained && pts_[n].gained != v))
                    pts_[n].dirty = 1;
                else if (pts_[n].dirty == 0) {
                    pts_[n].dirty = kGained;
                    pts_[n].gained = v;
                }
            }
            pts_[v].lock = pass;
            if (moves_kept)
                for (std::uint32_t n : scratch_b_) pts_[n].dirty = 1;  // v moved: their edges to it changed
            pts_[u].lock = pass;
            max_cost = std::max(max_cost, c);  // the quadric cost: the height term only orders
            if (height_weight_ > 0) {
                // u's region is now within its bound plus p_u's height of v's faces (u's fan, before the
                // collapse renames it).
                const double h = height(u, v, fan_normal(u));
                pts_[v].bound = std::max(pts_[v].bound, static_cast<float>(double(pts_[u].bound) + h));
            }
            collapse(u, v, plan);
            pts_[u].cost = std::numeric_limits<double>::infinity();
            changed = true;
            if (alive_faces_ <= target) {
                result_.reason = SimplifyResult::StopReason::target_reached;
                return;
            }
            if ((++applied & 1023) == 0) report(target);
        }
        if (applied == 0 && !changed) {
            if (limited) result_.reason = SimplifyResult::StopReason::error_limit;
            return;
        }
        build_csr();
    }
}

SimplifyResult Simplifier::run() {
    const auto& p = params_;
    if (!(p.target_ratio >= 0.f && p.target_ratio <= 1.f))
        throw Error(Error::Kind::argument, "simplify: target_ratio must be in [0, 1], got " + std::to_string(p.target_ratio));
    if (!(p.max_error >= 0.f))
        throw Error(Error::Kind::argument, "simplify: max_error must be >= 0, got " + std::to_string(p.max_error));
    if (p.target_triangles == 0 && p.target_ratio == 0.f && std::isinf(p.max_error))
        throw Error(Error::Kind::argument, "simplify: set target_triangles, target_ratio or max_error");
    const auto& w = p.weights;
    bool weights_ok = w.normal >= 0 && w.color >= 0 && w.texcoord >= 0 && std::isfinite(w.normal) &&
                      std::isfinite(w.color) && std::isfinite(w.texcoord);
    for (float t : w.texcoord_sets) weights_ok = weights_ok && t >= 0 && std::isfinite(t);
    if (!weights_ok) throw Error(Error::Kind::argument, "simplify: attribute weights must be finite and >= 0");
    if (!(p.min_normal_dot >= -1.f && p.min_normal_dot <= 1.f))
        throw Error(Error::Kind::argument, "simplify: min_normal_dot must be in [-1, 1]");
    if (!(p.height_weight >= 0.f) || !std::isfinite(p.height_weight))
        throw Error(Error::Kind::argument, "simplify: height_weight must be finite and >= 0");
    if (!p.extra_frames.empty() && p.placement != Placement::half_edge)
        throw Error(Error::Kind::argument, "simplify: extra_frames need Placement::half_edge");
    for (std::size_t f = 0; f < p.extra_frames.size(); ++f) {
        const std::vector<Vec3f>* frame = p.extra_frames[f];
        if (!frame || frame->size() != mesh_.vertex_count())
            throw Error(Error::Kind::argument, "simplify: extra frame " + std::to_string(f) + " has " +
                                                   std::to_string(frame ? frame->size() : 0) + " positions for " +
                                                   std::to_string(mesh_.vertex_count()) + " vertices");
        for (const Vec3f& x : *frame)
            if (!is_finite(x)) throw Error(Error::Kind::argument, "simplify: extra frame " + std::to_string(f) + " has a non-finite position");
    }

    check_progress(progress_, 0.0, "simplify");
    // The height term orders the pass schedule's half-edge collapses (with extra frames, frame 0's heights);
    // the greedy schedule and optimal placement (the kept point moves, so the height over p_v is not the
    // height over the result) keep the quadric order.
    if (p.schedule == SimplifyParams::Schedule::passes && p.placement == Placement::half_edge)
        height_weight_ = double(p.height_weight);
    setup();
    classify_points();

    std::size_t target = p.target_triangles;
    if (p.target_ratio > 0.f)
        // A ratio asks for a smaller mesh, never for none: a count that rounds to 0 is 1.
        target = std::max({target, std::size_t(1),
                           static_cast<std::size_t>(std::llround(p.target_ratio * double(mesh_.triangle_count())))});
    start_faces_ = alive_faces_;
    result_.target_triangles = target;
    result_.dropped_faces = mesh_.triangle_count() - alive_faces_;

    const double limit = std::isinf(p.max_error) ? std::numeric_limits<double>::infinity()
                                                 : double(p.max_error) * double(p.max_error);
    double max_cost = 0;
    result_.reason = SimplifyResult::StopReason::topology_limit;
    if (alive_faces_ <= target) result_.reason = SimplifyResult::StopReason::target_reached;
    else if (greedy_) run_greedy(target, limit, max_cost);
    else run_passes(target, limit, max_cost);
    check_progress(progress_, 1.0, "simplify");

    // Output: surviving faces in input order.
    std::vector<std::uint32_t> corners, sources;
    corners.reserve(alive_faces_ * 3);
    sources.reserve(alive_faces_);
    for (std::uint32_t f = 0; f < face_alive_.size(); ++f) {
        if (!face_alive_[f]) continue;
        corners.insert(corners.end(), &corners_[3 * f], &corners_[3 * f] + 3);
        sources.push_back(f);
    }
    std::vector<Vec3f> moved;
    if (p.placement == Placement::optimal) {
        moved.resize(points_);
        for (std::size_t i = 0; i < points_; ++i)
            moved[i] = pinned(static_cast<std::uint32_t>(i))
                           ? mesh_.positions[representative_[i]]  // bit for bit, not through the normalisation
                           : Vec3f{static_cast<float>(pts_[i].pos.x * scale_ + centre_.x), static_cast<float>(pts_[i].pos.y * scale_ + centre_.y),
                                   static_cast<float>(pts_[i].pos.z * scale_ + centre_.z)};
    }
    result_.mesh = build_mesh(mesh_, pid_, moved.empty() ? nullptr : &moved, corners, sources, result_.vertex_map);
    if (p.placement == Placement::optimal) write_solved_attributes(result_.mesh, result_.vertex_map);
    result_.triangles = result_.mesh.triangle_count();
    result_.error_relative = static_cast<float>(std::sqrt(max_cost));
    result_.error = static_cast<float>(std::sqrt(max_cost) * scale_);
    result_.input_points = std::move(pid_);
    return std::move(result_);
}

}  // namespace simplify_detail

namespace simplify_detail {

// Writes the attributes that minimise each surviving wedge's attribute quadric at its point's final
// position (Hoppe 1999: the area-weighted mean of its faces' attribute planes there). A wedge's quadric
// only ever holds faces that had that wedge or a wedge mapped onto it along a shared face, so one UV
// chart's faces: the solve never mixes charts. Empty quadrics keep the input value; normals are
// renormalised (a zero mean keeps the input normal) and colours clamped to [0, 1]. Every value is first
// clamped into the box of the attribute values of the faces the quadric holds (see attr_lo_).
void Simplifier::write_solved_attributes(Mesh& out, const std::vector<std::uint32_t>& vertex_map) const {
    if (dims_ == 0) return;
    std::vector<double> s(dims_);
    for (std::size_t i = 0; i < vertex_map.size(); ++i) {
        const std::uint32_t w = vertex_map[i];
        if (pinned(pid_[w])) continue;  // a locked point keeps its attributes
        if (!aq_.optimal_attributes(w, pts_[pid_[w]].pos, s.data())) continue;
        for (std::size_t j = 0; j < dims_; ++j)
            if (attr_lo_[w * dims_ + j] <= attr_hi_[w * dims_ + j])
                s[j] = std::clamp(s[j], attr_lo_[w * dims_ + j], attr_hi_[w * dims_ + j]);
        for (const AttrChannel& c : attr_channels_) {
            const double* a = &s[c.offset];
            bool finite = true;
            for (std::size_t k = 0; k < c.count; ++k) finite = finite && std::isfinite(a[k]);
            if (!finite) continue;
            auto value = [&](std::size_t k) { return static_cast<float>(a[k] / c.scale); };
            switch (c.kind) {
                case AttrChannel::Kind::normal: {
                    const Vec3f n{value(0), value(1), value(2)};
                    const float len = length(n);
                    if (len > 1e-6f) out.normals[i] = n * (1.f / len);
                    break;
                }
                case AttrChannel::Kind::color:
                    out.colors[i] = {std::clamp(value(0), 0.f, 1.f), std::clamp(value(1), 0.f, 1.f),
                                     std::clamp(value(2), 0.f, 1.f), std::clamp(value(3), 0.f, 1.f)};
                    break;
                case AttrChannel::Kind::texcoord:
                    out.texcoords[c.set][i] = {value(0), value(1)};
                    break;
            }
        }
    }
}

}  // namespace simplify_detail

using namespace simplify_detail;

namespace {

// SimplifyParams::importance and lock against the mesh they are given for (before any re-indexing).
void check_artist_masks(const Mesh& mesh, const SimplifyParams& params) {
    if (!params.importance.empty() && params.importance.size() != mesh.vertex_count())
        throw Error(Error::Kind::argument, "simplify: importance has " + std::to_string(params.importance.size()) +
                                               " values for " + std::to_string(mesh.vertex_count()) + " vertices");
    for (std::size_t v = 0; v < params.importance.size(); ++v)
        if (!(params.importance[v] >= 0.f && params.importance[v] <= 1.f))
            throw Error(Error::Kind::argument, "simplify: importance of vertex " + std::to_string(v) + " is " +
                                                   std::to_string(params.importance[v]) + ", outside [0, 1]");
    if (!(params.importance_scale >= 0.f) || !std::isfinite(params.importance_scale))
        throw Error(Error::Kind::argument, "simplify: importance_scale must be finite and >= 0");
    if (params.seam_weights.size() > std::size_t(kSeamClasses))
        throw Error(Error::Kind::argument, "simplify: seam_weights has " + std::to_string(params.seam_weights.size()) +
                                               " values for " + std::to_string(kSeamClasses) + " seam classes");
    for (float w : params.seam_weights)
        if (!(w > 0.f) || !std::isfinite(w)) throw Error(Error::Kind::argument, "simplify: seam weights must be finite and > 0");
    if (!params.lock.empty() && params.lock.size() != mesh.vertex_count())
        throw Error(Error::Kind::argument, "simplify: lock has " + std::to_string(params.lock.size()) + " values for " +
                                               std::to_string(mesh.vertex_count()) + " vertices");
}

}  // namespace

SimplifyResult simplify(const Mesh& mesh, const SimplifyParams& params, Progress* progress) {
    check_artist_masks(mesh, params);
    IdenticalVertices iv;
    if (soup_worth_merging(mesh, params, iv)) {
        const Mesh merged = iv.merged(mesh);
        // Artist masks follow the vertices onto the merged ones (largest importance, locked if any).
        const bool masks = !params.importance.empty() || !params.lock.empty();
        SimplifyParams mp;
        if (masks) {
            mp = params;
            const std::size_t n = merged.vertex_count();
            if (!params.importance.empty()) mp.importance.assign(n, 0.f);
            if (!params.lock.empty()) mp.lock.assign(n, 0);
            for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
                const std::uint32_t m = iv.merged_of[v];
                if (!params.importance.empty()) mp.importance[m] = std::max(mp.importance[m], params.importance[v]);
                if (!params.lock.empty()) mp.lock[m] |= params.lock[v] != 0;
            }
        }
        Simplifier s(merged, masks ? mp : params, progress);
        SimplifyResult r = s.run();
        to_input_numbering(r, iv);
        return r;
    }
    Simplifier s(mesh, params, progress);
    return s.run();
}

std::vector<std::uint32_t> replay_collapses(const Mesh& input, const SimplifyResult& result, std::size_t k) {
    if (k > result.collapses.size())
        throw Error(Error::Kind::argument, "replay_collapses: " + std::to_string(k) + " collapses requested, " +
                                               std::to_string(result.collapses.size()) + " recorded");
    if (result.input_points.size() != input.vertex_count())
        throw Error(Error::Kind::argument, "replay_collapses: the result was not made from this mesh");
    std::vector<std::uint32_t> to(input.vertex_count());
    std::iota(to.begin(), to.end(), 0u);
    for (std::size_t i = 0; i < k; ++i) {
        const Collapse& c = result.collapses[i];
        for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m) to[result.moves[m].from] = result.moves[m].to;
    }
    auto resolve = [&](std::uint32_t w) {
        std::uint32_t r = w;
        while (to[r] != r) r = to[r];
        while (to[w] != r) {  // path compression
            const std::uint32_t next = to[w];
            to[w] = r;
            w = next;
        }
        return r;
    };
    std::vector<std::uint32_t> out;
    const auto& pts = result.input_points;
    const std::vector<std::uint8_t> start = initial_faces(input, pts);
    for (std::size_t f = 0; f < input.triangle_count(); ++f) {
        if (!start[f]) continue;
        const std::uint32_t a = resolve(input.indices[3 * f]), b = resolve(input.indices[3 * f + 1]),
                            c = resolve(input.indices[3 * f + 2]);
        if (pts[a] == pts[b] || pts[b] == pts[c] || pts[a] == pts[c]) continue;
        out.push_back(a);
        out.push_back(b);
        out.push_back(c);
    }
    return out;
}

}  // namespace lodforge
