// Overlay of two triangulations of the sphere: the supermesh connectivity of issue 8, case (b)
// (docs/morph.md, "Case (b): two meshes").
//
// Follows:
// - J. R. Kent, W. E. Carlson, R. E. Parent, "Shape transformation for polyhedral objects", SIGGRAPH
//   1992: both meshes mapped to the sphere, their edge graphs merged; every crossing of two edges is a
//   new vertex and every vertex carries a position on both shapes.
// - M. de Berg et al., "Computational Geometry", ch. 2 (map overlay): the merged graph is built from
//   the crossings along each edge and the rotation order at every vertex, then its faces are traced.
//
// All combinatorial decisions (does edge a cross edge b, on which side does b leave a) are signs of
// determinants of the *input* points (orient_sign: a filtered predicate), so they are consistent with
// each other; a sign too close to zero to trust is reported as "not in general position" and the caller perturbs one mesh and retries.
#include "morph/sphere_overlay.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace lodforge::sphere {
namespace {

std::uint64_t key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

struct Edges {
    std::vector<std::array<std::uint32_t, 2>> ends;            // ends[0] < ends[1]
    std::unordered_map<std::uint64_t, std::uint32_t> id;       // (u, v), either order -> edge
    std::unordered_map<std::uint64_t, std::uint32_t> face_of;  // directed (u, v) -> the face left of it
    std::unordered_map<std::uint64_t, std::uint32_t> next_ccw; // directed (u, v) -> w: next neighbour CCW around u
};

Edges build_edges(const std::vector<std::array<std::uint32_t, 3>>& faces)
{
    Edges e;
    e.face_of.reserve(faces.size() * 3);
    e.next_ccw.reserve(faces.size() * 3);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t u = faces[f][c], v = faces[f][(c + 1) % 3], w = faces[f][(c + 2) % 3];
            e.face_of[key(u, v)] = f;
            e.next_ccw[key(u, v)] = w;
            if (u < v) {
                e.id[key(u, v)] = std::uint32_t(e.ends.size());
                e.id[key(v, u)] = std::uint32_t(e.ends.size());
                e.ends.push_back({u, v});
            }
        }
    return e;
}

struct Crossing {
    std::uint32_t a_edge, b_edge;
    D3 point;
    double ta, tb;        // fraction along the edge from ends[0] to ends[1]
    bool b_leaves_left;   // B's ends[1] is left of A's edge (ends[0] -> ends[1])
    std::uint32_t a_plus = 0, a_minus = 0, b_plus = 0, b_minus = 0;  // outgoing half-edges
};

// Fraction of x between p0 and p1 on their great-circle arc, in the gnomonic sense used by barycentric
// coordinates: x ∝ (1 − t)·p0 + t·p1.
double arc_fraction(const D3& p0, const D3& p1, const D3& x)
{
    const double s0 = norm(cross(p0, x)), s1 = norm(cross(p1, x));
    return s0 + s1 > 0 ? s0 / (s0 + s1) : 0.5;
}

// Three-point gnomonic barycentric coordinates of x in the spherical triangle (p0, p1, p2), clamped to
// the triangle (x is in it up to rounding).
std::array<double, 3> barycentric(const D3& p0, const D3& p1, const D3& p2, const D3& x)
{
    std::array<double, 3> w{std::max(0.0, det3(x, p1, p2)), std::max(0.0, det3(p0, x, p2)), std::max(0.0, det3(p0, p1, x))};
    const double s = w[0] + w[1] + w[2];
    if (!(s > 0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
    return {w[0] / s, w[1] / s, w[2] / s};
}

// A uniform grid over the cube [-1, 1]^3 holding arcs by their bounding boxes.
class ArcGrid {
public:
    explicit ArcGrid(std::size_t arcs) : n_(std::clamp(int(std::sqrt(double(arcs)) / 2), 4, 96)), cells_(std::size_t(n_) * n_ * n_) {}
    template <class F>
    void for_cells(const D3& p, const D3& q, F&& f) const
    {
        // The arc bulges out of the chord's box by at most its sagitta 1 − cos(θ/2).
        const double chord2 = dot(sub(p, q), sub(p, q));
        const double sag = 1 - std::sqrt(std::max(0.0, 1 - chord2 / 4)) + 1e-9;
        int lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = cell(std::min(p[k], q[k]) - sag);
            hi[k] = cell(std::max(p[k], q[k]) + sag);
        }
        for (int i = lo[0]; i <= hi[0]; ++i)
            for (int j = lo[1]; j <= hi[1]; ++j)
                for (int k = lo[2]; k <= hi[2]; ++k) f((std::size_t(i) * n_ + j) * n_ + k);
    }
    std::vector<std::vector<std::uint32_t>>& cells() { return cells_; }
    const std::vector<std::vector<std::uint32_t>>& cells() const { return cells_; }

private:
    int cell(double x) const { return std::clamp(int((x + 1) * 0.5 * n_), 0, n_ - 1); }
    int n_;
    std::vector<std::vector<std::uint32_t>> cells_;
};

}  // namespace

bool overlay_triangulations(const SphereTriangulation& a, const SphereTriangulation& b, Overlay& out, std::string& why)
{
    const auto& pa = *a.points;
    const auto& pb = *b.points;
    const Edges ea = build_edges(*a.faces), eb = build_edges(*b.faces);
    const std::uint32_t na = std::uint32_t(pa.size()), nb = std::uint32_t(pb.size());

    // 1. Crossings, from candidate pairs whose boxes share a grid cell.
    ArcGrid grid(ea.ends.size());
    for (std::uint32_t e = 0; e < ea.ends.size(); ++e)
        grid.for_cells(pa[ea.ends[e][0]], pa[ea.ends[e][1]], [&](std::size_t c) { grid.cells()[c].push_back(e); });
    std::vector<Crossing> crossings;
    std::vector<std::uint32_t> stamp(ea.ends.size(), UINT32_MAX);
    for (std::uint32_t g = 0; g < eb.ends.size(); ++g) {
        const D3& b0 = pb[eb.ends[g][0]];
        const D3& b1 = pb[eb.ends[g][1]];
        bool degenerate = false;
        grid.for_cells(b0, b1, [&](std::size_t c) {
            for (std::uint32_t e : grid.cells()[c]) {
                if (stamp[e] == g || degenerate) continue;
                stamp[e] = g;
                const D3& a0 = pa[ea.ends[e][0]];
                const D3& a1 = pa[ea.ends[e][1]];
                const int s0 = orient_sign(a0, a1, b0), s1 = orient_sign(a0, a1, b1);
                const int t0 = orient_sign(b0, b1, a0), t1 = orient_sign(b0, b1, a1);
                // Clearly on one side: no crossing, whatever the other signs say.
                if ((s0 == s1 && s0 != 0) || (t0 == t1 && t0 != 0)) continue;
                D3 x = cross(cross(a0, a1), cross(b0, b1));
                if (dot(x, add(a0, a1)) < 0) x = mul(x, -1);
                if (dot(x, add(b0, b1)) < 0) continue;  // the great circles meet on the far side
                if (s0 == 0 || s1 == 0 || t0 == 0 || t1 == 0) {
                    degenerate = true;
                    return;
                }
                x = normalized(x);
                crossings.push_back({e, g, x, arc_fraction(a0, a1, x), arc_fraction(b0, b1, x), s1 > 0});
            }
        });
        if (degenerate) {
            why = "a vertex lies on an edge of the other mesh (B edge " + std::to_string(g) + ")";
            return false;
        }
    }

    // 2. Crossings along each edge, in order from ends[0].
    auto order_along = [&](std::size_t edge_count, bool along_a, std::vector<std::uint32_t>& offset, std::vector<std::uint32_t>& list) {
        offset.assign(edge_count + 1, 0);
        for (const auto& c : crossings) ++offset[(along_a ? c.a_edge : c.b_edge) + 1];
        for (std::size_t i = 0; i < edge_count; ++i) offset[i + 1] += offset[i];
        list.resize(crossings.size());
        std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
        for (std::uint32_t i = 0; i < crossings.size(); ++i) list[fill[along_a ? crossings[i].a_edge : crossings[i].b_edge]++] = i;
        for (std::size_t e = 0; e < edge_count; ++e) {
            auto first = list.begin() + offset[e], last = list.begin() + offset[e + 1];
            std::sort(first, last, [&](std::uint32_t x, std::uint32_t y) {
                return along_a ? crossings[x].ta < crossings[y].ta : crossings[x].tb < crossings[y].tb;
            });
            for (auto it = first; it + 1 < last; ++it) {
                const double d = along_a ? crossings[*(it + 1)].ta - crossings[*it].ta : crossings[*(it + 1)].tb - crossings[*it].tb;
                if (!(d > 0)) return false;  // a wrong order of two close ones fails the checks of step 8
            }
        }
        return true;
    };
    std::vector<std::uint32_t> a_off, a_list, b_off, b_list;
    if (!order_along(ea.ends.size(), true, a_off, a_list) || !order_along(eb.ends.size(), false, b_off, b_list)) {
        why = "two crossings coincide along an edge";
        return false;
    }

    // 3. Half-edges along the chains ends[0], crossings..., ends[1]; pairs (2s, 2s+1) are twins.
    const std::uint32_t nx = std::uint32_t(crossings.size());
    const std::uint32_t nvert = na + nb + nx;
    std::vector<std::uint32_t> origin;
    std::vector<std::uint32_t> source;  // edge id; A edges first, then B edges offset by A's edge count
    std::vector<std::uint8_t> forward;  // runs from ends[0] towards ends[1]
    std::vector<std::uint32_t> first_forward_a(ea.ends.size()), last_backward_a(ea.ends.size());
    std::vector<std::uint32_t> first_forward_b(eb.ends.size()), last_backward_b(eb.ends.size());
    auto chain = [&](bool is_a, std::uint32_t e, std::uint32_t v0, std::uint32_t v1, const std::vector<std::uint32_t>& off,
                     const std::vector<std::uint32_t>& list) {
        std::uint32_t prev = v0;
        std::uint32_t prev_backward = UINT32_MAX;
        const std::uint32_t src = is_a ? e : std::uint32_t(ea.ends.size()) + e;
        auto segment = [&](std::uint32_t to) {
            const std::uint32_t h = std::uint32_t(origin.size());
            origin.push_back(prev), source.push_back(src), forward.push_back(1);
            origin.push_back(to), source.push_back(src), forward.push_back(0);
            return h;
        };
        for (std::uint32_t i = off[e]; i <= off[e + 1]; ++i) {
            const bool last = i == off[e + 1];
            const std::uint32_t to = last ? v1 : na + nb + list[i];
            const std::uint32_t h = segment(to);
            if (i == off[e]) (is_a ? first_forward_a : first_forward_b)[e] = h;
            if (prev_backward != UINT32_MAX) {
                Crossing& c = crossings[list[i - 1]];
                (is_a ? c.a_minus : c.b_minus) = prev_backward;
                (is_a ? c.a_plus : c.b_plus) = h;
            }
            prev_backward = h + 1;
            prev = to;
        }
        (is_a ? last_backward_a : last_backward_b)[e] = prev_backward;
    };
    for (std::uint32_t e = 0; e < ea.ends.size(); ++e) chain(true, e, ea.ends[e][0], ea.ends[e][1], a_off, a_list);
    for (std::uint32_t e = 0; e < eb.ends.size(); ++e) chain(false, e, na + eb.ends[e][0], na + eb.ends[e][1], b_off, b_list);
    const std::uint32_t nh = std::uint32_t(origin.size());

    // 4. Rotation system: the outgoing half-edges of every vertex, counter-clockwise from outside.
    std::vector<std::uint32_t> rot_off(nvert + 1, 0), rot, rot_pos(nh);
    for (std::uint32_t h = 0; h < nh; ++h) ++rot_off[origin[h] + 1];
    for (std::uint32_t v = 0; v < nvert; ++v) rot_off[v + 1] += rot_off[v];
    rot.resize(nh);
    auto ring = [&](const Edges& e, const std::vector<std::uint32_t>& ff, const std::vector<std::uint32_t>& lb, std::uint32_t u,
                    std::uint32_t offset_u, std::uint32_t start) {
        std::uint32_t v = start, slot = rot_off[offset_u + u];
        do {
            const std::uint32_t edge = e.id.at(key(u, v));
            rot[slot++] = u < v ? ff[edge] : lb[edge];
            v = e.next_ccw.at(key(u, v));
        } while (v != start && slot < rot_off[offset_u + u + 1]);
    };
    std::vector<std::uint8_t> filled(na + nb, 0);
    for (const auto& f : *a.faces)
        for (int c = 0; c < 3; ++c)
            if (!filled[f[c]]) filled[f[c]] = 1, ring(ea, first_forward_a, last_backward_a, f[c], 0, f[(c + 1) % 3]);
    for (const auto& f : *b.faces)
        for (int c = 0; c < 3; ++c)
            if (!filled[na + f[c]]) filled[na + f[c]] = 1, ring(eb, first_forward_b, last_backward_b, f[c], na, f[(c + 1) % 3]);
    for (std::uint32_t i = 0; i < nx; ++i) {
        const Crossing& c = crossings[i];
        std::uint32_t* r = &rot[rot_off[na + nb + i]];
        r[0] = c.a_plus, r[2] = c.a_minus;
        r[1] = c.b_leaves_left ? c.b_plus : c.b_minus;
        r[3] = c.b_leaves_left ? c.b_minus : c.b_plus;
    }
    for (std::uint32_t v = 0; v < nvert; ++v)
        for (std::uint32_t i = rot_off[v]; i < rot_off[v + 1]; ++i) rot_pos[rot[i]] = i - rot_off[v];

    // 5. Faces: next(h) = the half-edge clockwise after twin(h) around h's end.
    std::vector<std::uint32_t> face_of(nh, UINT32_MAX);
    std::vector<std::uint32_t> face_start;
    for (std::uint32_t h0 = 0; h0 < nh; ++h0) {
        if (face_of[h0] != UINT32_MAX) continue;
        const std::uint32_t f = std::uint32_t(face_start.size());
        face_start.push_back(h0);
        std::uint32_t h = h0;
        std::size_t steps = 0;
        do {
            face_of[h] = f;
            const std::uint32_t t = h ^ 1u, v = origin[t];
            const std::uint32_t deg = rot_off[v + 1] - rot_off[v];
            h = rot[rot_off[v] + (rot_pos[t] + deg - 1) % deg];
            if (++steps > nh) break;
        } while (h != h0);
        if (h != h0) {
            why = "inconsistent face cycle";
            return false;
        }
    }
    const std::size_t nf = face_start.size();
    const long long euler = (long long)nvert - (long long)nh / 2 + (long long)nf;
    if (euler != 2) {
        why = "the merged graph has Euler characteristic " + std::to_string(euler);
        return false;
    }

    // 6. Which A face and which B face each merged face lies in: set from the A (B) edges on its border,
    //    then carried across the other mesh's edges, which do not change it.
    const std::uint32_t a_edge_count = std::uint32_t(ea.ends.size());
    auto label = [&](bool is_a) {
        std::vector<std::uint32_t> lab(nf, UINT32_MAX), queue;
        for (std::uint32_t h = 0; h < nh; ++h) {
            const bool from_a = source[h] < a_edge_count;
            if (from_a != is_a || lab[face_of[h]] != UINT32_MAX) continue;
            const Edges& e = is_a ? ea : eb;
            const auto& ends = e.ends[is_a ? source[h] : source[h] - a_edge_count];
            lab[face_of[h]] = forward[h] ? e.face_of.at(key(ends[0], ends[1])) : e.face_of.at(key(ends[1], ends[0]));
            queue.push_back(face_of[h]);
        }
        std::vector<std::vector<std::uint32_t>> other_edges(nf);
        for (std::uint32_t h = 0; h < nh; ++h)
            if ((source[h] < a_edge_count) != is_a) other_edges[face_of[h]].push_back(h);
        while (!queue.empty()) {
            const std::uint32_t f = queue.back();
            queue.pop_back();
            for (std::uint32_t h : other_edges[f]) {
                const std::uint32_t g = face_of[h ^ 1u];
                if (lab[g] == UINT32_MAX) lab[g] = lab[f], queue.push_back(g);
            }
        }
        return lab;
    };
    const std::vector<std::uint32_t> face_a = label(true), face_b = label(false);

    // 7. Vertices and their places in both meshes.
    out = Overlay{};
    out.crossings = nx;
    out.points.resize(nvert);
    out.in_a.resize(nvert);
    out.in_b.resize(nvert);
    for (std::uint32_t i = 0; i < na; ++i) out.points[i] = pa[i];
    for (std::uint32_t i = 0; i < nb; ++i) out.points[na + i] = pb[i];
    for (std::uint32_t i = 0; i < nx; ++i) {
        const Crossing& c = crossings[i];
        out.points[na + nb + i] = c.point;
        out.in_a[na + nb + i] = {{ea.ends[c.a_edge][0], ea.ends[c.a_edge][1], 0}, {1 - c.ta, c.ta, 0}};
        out.in_b[na + nb + i] = {{eb.ends[c.b_edge][0], eb.ends[c.b_edge][1], 0}, {1 - c.tb, c.tb, 0}};
    }
    auto locate = [&](const std::vector<std::array<std::uint32_t, 3>>& faces, const std::vector<D3>& p, std::uint32_t f,
                      const D3& x) {
        const auto& t = faces[f];
        return OverlayWeights{t, barycentric(p[t[0]], p[t[1]], p[t[2]], x)};
    };
    for (std::uint32_t i = 0; i < na; ++i) {
        out.in_a[i] = {{i, 0, 0}, {1, 0, 0}};
        const std::uint32_t f = face_b[face_of[rot[rot_off[i]]]];
        if (f == UINT32_MAX) return why = "unlabelled face", false;
        out.in_b[i] = locate(*b.faces, pb, f, pa[i]);
    }
    for (std::uint32_t i = 0; i < nb; ++i) {
        out.in_b[na + i] = {{i, 0, 0}, {1, 0, 0}};
        const std::uint32_t f = face_a[face_of[rot[rot_off[na + i]]]];
        if (f == UINT32_MAX) return why = "unlabelled face", false;
        out.in_a[na + i] = locate(*a.faces, pa, f, pb[i]);
    }

    // 8. Each merged face is convex (an A triangle ∩ a B triangle): a fan from a corner whose triangles
    //    are all positive.
    out.min_det = INFINITY;
    std::vector<std::uint32_t> cycle;
    for (std::size_t f = 0; f < nf; ++f) {
        cycle.clear();
        std::uint32_t h = face_start[f];
        do {
            cycle.push_back(origin[h]);
            const std::uint32_t t = h ^ 1u, v = origin[t];
            const std::uint32_t deg = rot_off[v + 1] - rot_off[v];
            h = rot[rot_off[v] + (rot_pos[t] + deg - 1) % deg];
        } while (h != face_start[f]);
        const std::size_t m = cycle.size();
        bool done = false;
        for (std::size_t apex = 0; apex < m && !done; ++apex) {
            double worst = INFINITY;
            bool all_positive = true;
            for (std::size_t i = 1; i + 1 < m && all_positive; ++i) {
                const D3 &p = out.points[cycle[apex]], &q = out.points[cycle[(apex + i) % m]], &r = out.points[cycle[(apex + i + 1) % m]];
                all_positive = orient_sign(p, q, r) > 0;
                worst = std::min(worst, dot(p, cross(sub(q, p), sub(r, p))));
            }
            if (!all_positive) continue;
            for (std::size_t i = 1; i + 1 < m; ++i)
                out.triangles.push_back({cycle[apex], cycle[(apex + i) % m], cycle[(apex + i + 1) % m]});
            out.min_det = std::min(out.min_det, worst);
            done = true;
        }
        if (!done) {
            why = "a merged face of " + std::to_string(m) + " corners has no positive fan";
            return false;
        }
    }
    return true;
}

}  // namespace lodforge::sphere
