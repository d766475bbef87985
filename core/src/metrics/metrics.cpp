// Sampled symmetric surface distance (Metro: Cignoni, Rocchini, Scopigno, CGF 1998).
//
// Closest points come from a bounding-volume hierarchy over the triangles (median split, 4 triangles per
// leaf) queried with the exact point–triangle distance of Ericson, "Real-Time Collision Detection" §5.1.5.
// Consecutive samples come from the same or neighbouring triangles, so each query starts with the
// previous answer as its bound, which prunes almost the whole tree. A k-d tree over triangle centroids
// (nanoflann) would need a search radius widened by the largest triangle and a second exact pass; the
// BVH is exact in one pass and has no dependency.
#include "lodforge/metrics/metrics.h"

#include "lodforge/error.h"
#include "parallel_for.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>

namespace lodforge {
namespace {

struct P3 {
    double x, y, z;
};
P3 operator-(P3 a, P3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
P3 operator+(P3 a, P3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P3 operator*(P3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot3(P3 a, P3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
P3 cross3(P3 a, P3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
P3 to_p3(Vec3f v) { return {v.x, v.y, v.z}; }

// Closest point of triangle abc to p; returns barycentrics (of a, b, c) in `bary`.
P3 closest_on_triangle(P3 p, P3 a, P3 b, P3 c, double bary[3]) {
    const P3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) { bary[0] = 1; bary[1] = 0; bary[2] = 0; return a; }
    const P3 bp = p - b;
    const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) { bary[0] = 0; bary[1] = 1; bary[2] = 0; return b; }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        bary[0] = 1 - v; bary[1] = v; bary[2] = 0;
        return a + ab * v;
    }
    const P3 cp = p - c;
    const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) { bary[0] = 0; bary[1] = 0; bary[2] = 1; return c; }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        bary[0] = 1 - w; bary[1] = 0; bary[2] = w;
        return a + ac * w;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        bary[0] = 0; bary[1] = 1 - w; bary[2] = w;
        return b + (c - b) * w;
    }
    const double sum = va + vb + vc;
    if (!(sum > 0)) {  // degenerate (zero-area) triangle: closest of its three edges
        double best = INFINITY;
        P3 out = a;
        const P3 pts[3] = {a, b, c};
        for (int e = 0; e < 3; ++e) {
            const P3 s = pts[e], t = pts[(e + 1) % 3], st = t - s;
            const double len2 = dot3(st, st);
            const double k = len2 > 0 ? std::clamp(dot3(p - s, st) / len2, 0.0, 1.0) : 0.0;
            const P3 q = s + st * k;
            const double d = dot3(p - q, p - q);
            if (d < best) {
                best = d;
                out = q;
                bary[0] = bary[1] = bary[2] = 0;
                bary[e] = 1 - k;
                bary[(e + 1) % 3] = k;
            }
        }
        return out;
    }
    const double denom = 1 / sum;
    const double v = vb * denom, w = vc * denom;
    bary[0] = 1 - v - w; bary[1] = v; bary[2] = w;
    return a + ab * v + ac * w;
}

class TriangleBvh {
public:
    explicit TriangleBvh(const Mesh& mesh) : mesh_(mesh) {
        const std::size_t n = mesh.triangle_count();
        order_.resize(n);
        std::iota(order_.begin(), order_.end(), 0u);
        centroids_.resize(n);
        for (std::size_t t = 0; t < n; ++t) {
            const P3 a = vertex(t, 0), b = vertex(t, 1), c = vertex(t, 2);
            centroids_[t] = (a + b + c) * (1.0 / 3.0);
        }
        nodes_.reserve(2 * n / kLeaf + 2);
        build(0, static_cast<std::uint32_t>(n));
        tris_.resize(n * 9);
        for (std::size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                const P3 v = vertex(order_[i], k);
                tris_[9 * i + 3 * k] = v.x;
                tris_[9 * i + 3 * k + 1] = v.y;
                tris_[9 * i + 3 * k + 2] = v.z;
            }
    }

    struct Hit {
        std::uint32_t triangle = 0;  // mesh triangle index
        double distance2 = INFINITY;
        double bary[3] = {1, 0, 0};
    };

    // `hint` is a slot (BVH order) to test first; updated to the answer's slot.
    Hit closest(P3 p, std::uint32_t& hint) const { return search<false>(p, hint, 0, nullptr); }

    // closest(), and in `ties` every triangle whose closest point is within `tolerance` of the nearest
    // distance (the nearest included): coincident or touching faces that are equally close up to rounding,
    // among which an attribute comparison must choose (their attributes may differ: UV seams, decals).
    Hit closest_with_ties(P3 p, std::uint32_t& hint, double tolerance, std::vector<Hit>& ties) const {
        ties.clear();
        const Hit best = search<true>(p, hint, tolerance, &ties);
        const double limit = reach2(best.distance2, tolerance);
        std::erase_if(ties, [&](const Hit& h) { return h.distance2 > limit; });
        for (Hit& h : ties) h.triangle = order_[h.triangle];  // slots → mesh triangles
        return best;
    }

private:
    static constexpr std::uint32_t kLeaf = 4;

    // The squared distance within `tolerance` of a squared distance d2.
    static double reach2(double d2, double tolerance) {
        const double d = std::sqrt(d2) + tolerance;
        return d * d;
    }

    template <bool kTies>
    Hit search(P3 p, std::uint32_t& hint, double tolerance, std::vector<Hit>* ties) const {
        Hit best;
        std::uint32_t best_slot = hint;
        // With ties, boxes as far as the nearest distance plus the tolerance are still visited.
        double best_reach2 = INFINITY;
        auto bound = [&] { return kTies ? best_reach2 : best.distance2; };
        auto visit = [&](std::uint32_t slot) {
            if constexpr (kTies) {
                Hit h;
                test(p, slot, h, h.triangle);  // h.triangle = slot
                if (h.distance2 < best.distance2) {
                    best = h;
                    best_slot = slot;
                    best_reach2 = reach2(h.distance2, tolerance);
                }
                if (h.distance2 <= best_reach2) ties->push_back(h);  // the final filter drops the early ones
            } else {
                test(p, slot, best, best_slot);
            }
        };
        if (hint < order_.size()) visit(hint);
        std::uint32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes_[stack[--top]];
            const double reach = bound();
            if (kTies ? box_distance2(node, p) > reach : box_distance2(node, p) >= reach) continue;
            if (node.count > 0) {
                for (std::uint32_t i = node.start; i < node.start + node.count; ++i)
                    if (!kTies || i != hint) visit(i);
                continue;
            }
            const std::uint32_t left = static_cast<std::uint32_t>(&node - nodes_.data()) + 1, right = node.right;
            const double dl = box_distance2(nodes_[left], p), dr = box_distance2(nodes_[right], p);
            // Push the farther child first so the nearer one is visited next.
            if (dl < dr) {
                if (kTies ? dr <= reach : dr < reach) stack[top++] = right;
                if (kTies ? dl <= reach : dl < reach) stack[top++] = left;
            } else {
                if (kTies ? dl <= reach : dl < reach) stack[top++] = left;
                if (kTies ? dr <= reach : dr < reach) stack[top++] = right;
            }
        }
        hint = best_slot;
        best.triangle = order_[best_slot];
        return best;
    }
    struct Node {
        float lo[3], hi[3];
        std::uint32_t start = 0, count = 0;  // leaf: slots [start, start + count)
        std::uint32_t right = 0;             // inner: right child (left child follows the node)
    };

    P3 vertex(std::size_t t, int k) const { return to_p3(mesh_.positions[mesh_.indices[3 * t + k]]); }

    void test(P3 p, std::uint32_t slot, Hit& best, std::uint32_t& best_slot) const {
        const double* v = &tris_[9 * slot];
        double bary[3];
        const P3 q = closest_on_triangle(p, {v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, bary);
        const P3 d = p - q;
        const double d2 = dot3(d, d);
        if (d2 < best.distance2) {
            best.distance2 = d2;
            std::copy(bary, bary + 3, best.bary);
            best_slot = slot;
        }
    }

    static double box_distance2(const Node& n, P3 p) {
        const double c[3] = {p.x, p.y, p.z};
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double lo = n.lo[k], hi = n.hi[k];
            const double d = c[k] < lo ? lo - c[k] : (c[k] > hi ? c[k] - hi : 0.0);
            d2 += d * d;
        }
        return d2;
    }

    std::uint32_t build(std::uint32_t begin, std::uint32_t end) {
        const auto index = static_cast<std::uint32_t>(nodes_.size());
        nodes_.emplace_back();
        Node node;
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (std::uint32_t i = begin; i < end; ++i) {
            const std::uint32_t t = order_[i];
            for (int k = 0; k < 3; ++k) {
                const P3 v = vertex(t, k);
                const double c[3] = {v.x, v.y, v.z};
                for (int a = 0; a < 3; ++a) { lo[a] = std::min(lo[a], c[a]); hi[a] = std::max(hi[a], c[a]); }
            }
            const double c[3] = {centroids_[t].x, centroids_[t].y, centroids_[t].z};
            for (int a = 0; a < 3; ++a) { clo[a] = std::min(clo[a], c[a]); chi[a] = std::max(chi[a], c[a]); }
        }
        for (int a = 0; a < 3; ++a) {
            // Round outwards so float boxes still contain the double-precision triangles.
            node.lo[a] = std::nextafter(static_cast<float>(lo[a]), -INFINITY);
            node.hi[a] = std::nextafter(static_cast<float>(hi[a]), INFINITY);
        }
        if (end - begin <= kLeaf) {
            node.start = begin;
            node.count = end - begin;
            nodes_[index] = node;
            return index;
        }
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
        const std::uint32_t mid = begin + (end - begin) / 2;
        auto key = [&](std::uint32_t t) {
            return axis == 0 ? centroids_[t].x : (axis == 1 ? centroids_[t].y : centroids_[t].z);
        };
        std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                         [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
        build(begin, mid);
        node.right = build(mid, end);
        nodes_[index] = node;
        return index;
    }

    const Mesh& mesh_;
    std::vector<std::uint32_t> order_;
    std::vector<P3> centroids_;
    std::vector<Node> nodes_;
    std::vector<double> tris_;
};

struct Accumulator {
    double max = 0, sum = 0, sum2 = 0;
    std::size_t count = 0;
    void add_sample(double d) {
        max = std::max(max, d);
        sum += d;
        sum2 += d * d;
        ++count;
    }
    OneSidedDistance finish() const {
        OneSidedDistance r;
        r.max = max;
        r.samples = count;
        if (count) {
            r.mean = sum / double(count);
            r.rms = std::sqrt(sum2 / double(count));
        }
        return r;
    }
};

// The corner of largest barycentric weight (the first on ties, so the field is deterministic).
int major_corner(double w0, double w1, double w2) {
    if (w0 >= w1 && w0 >= w2) return 0;
    return w1 >= w2 ? 1 : 2;
}

void raise_to(std::vector<float>* field, std::uint32_t v, double d) {
    if (field) (*field)[v] = std::max((*field)[v], static_cast<float>(d));
}

void require_triangles(const Mesh& m, const char* which) {
    if (m.triangle_count() == 0)
        throw Error(Error::Kind::invalid, std::string("compare: the ") + which + " mesh has no triangles");
}

// Samples `from` and measures against `to`; fills attribute errors when asked. `region` (per vertex of
// the test mesh, or null) takes each distance at the sample's major corner: on `from`'s triangle when
// `region_on_from`, else on the `to` triangle holding the closest point.
Accumulator measure(const Mesh& from, const TriangleBvh& to_bvh, const Mesh& to, const DistanceParams& params,
                    std::uint64_t seed, bool attributes, DistanceResult& result, Progress* progress,
                    double progress_base, std::vector<float>* region, bool region_on_from) {
    Accumulator acc;
    const std::size_t nt = from.triangle_count();
    std::vector<double> area(nt);
    double total = 0;
    for (std::size_t t = 0; t < nt; ++t) {
        const P3 a = to_p3(from.positions[from.indices[3 * t]]), b = to_p3(from.positions[from.indices[3 * t + 1]]),
                 c = to_p3(from.positions[from.indices[3 * t + 2]]);
        const P3 n = cross3(b - a, c - a);
        area[t] = 0.5 * std::sqrt(dot3(n, n));
        total += area[t];
    }
    std::size_t wanted = params.samples;
    if (wanted == 0) wanted = std::max<std::size_t>(100000, std::min<std::size_t>(10 * nt, 2000000));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);

    const bool colors = attributes && from.has_colors() && to.has_colors();
    const bool uvs = attributes && from.has_texcoords() && to.has_texcoords();
    double color_sum2 = 0, uv_sum2 = 0;
    std::size_t attr_count = 0;
    std::vector<TriangleBvh::Hit> ties;
    // Equally close up to rounding: 1e-7 of the diagonal, far above the error of the double closest-point
    // arithmetic on float vertices and far below any geometric difference a comparison reports.
    const double tie_tolerance = 1e-7 * static_cast<double>(to.bounds().diagonal());

    std::uint32_t hint = 0xffffffffu;
    std::size_t done = 0;
    const double per = total > 0 ? double(wanted) / total : 0.0;
    for (std::size_t t = 0; t < nt; ++t) {
        const auto count = static_cast<std::size_t>(std::floor(area[t] * per + uni(rng)));
        const std::uint32_t i0 = from.indices[3 * t], i1 = from.indices[3 * t + 1], i2 = from.indices[3 * t + 2];
        const P3 a = to_p3(from.positions[i0]), b = to_p3(from.positions[i1]), c = to_p3(from.positions[i2]);
        for (std::size_t s = 0; s < count; ++s) {
            const double r1 = std::sqrt(uni(rng)), r2 = uni(rng);
            const double w0 = 1 - r1, w1 = r1 * (1 - r2), w2 = r1 * r2;
            const P3 p = a * w0 + b * w1 + c * w2;
            // (With attributes the query also lists the faces equally close: see below.)
            const TriangleBvh::Hit hit = colors || uvs ? to_bvh.closest_with_ties(p, hint, tie_tolerance, ties)
                                                       : to_bvh.closest(p, hint);
            const double distance = std::sqrt(hit.distance2);
            acc.add_sample(distance);
            if (region) {
                if (region_on_from) {
                    const int k = major_corner(w0, w1, w2);
                    raise_to(region, from.indices[3 * t + k], distance);
                } else {
                    const int k = major_corner(hit.bary[0], hit.bary[1], hit.bary[2]);
                    raise_to(region, to.indices[3 * hit.triangle + k], distance);
                }
            }
            if (colors || uvs) {
                // The attributes at `h` against the sample's: squared colour difference (components in
                // [0, 1]) and squared texture-coordinate difference.
                auto differences = [&](const TriangleBvh::Hit& h, double& dc2, double& du2) {
                    const std::uint32_t* ti = &to.indices[3 * h.triangle];
                    dc2 = du2 = 0;
                    if (colors) {
                        const Vec4f ca = from.colors[i0], cb = from.colors[i1], cc = from.colors[i2];
                        const Vec4f ra = to.colors[ti[0]], rb = to.colors[ti[1]], rc = to.colors[ti[2]];
                        const double dr = (ca.x * w0 + cb.x * w1 + cc.x * w2) - (ra.x * h.bary[0] + rb.x * h.bary[1] + rc.x * h.bary[2]);
                        const double dg = (ca.y * w0 + cb.y * w1 + cc.y * w2) - (ra.y * h.bary[0] + rb.y * h.bary[1] + rc.y * h.bary[2]);
                        const double db = (ca.z * w0 + cb.z * w1 + cc.z * w2) - (ra.z * h.bary[0] + rb.z * h.bary[1] + rc.z * h.bary[2]);
                        dc2 = dr * dr + dg * dg + db * db;
                    }
                    if (uvs) {
                        const auto& fu = from.texcoords[0];
                        const auto& tu = to.texcoords[0];
                        const double du = (fu[i0].x * w0 + fu[i1].x * w1 + fu[i2].x * w2) -
                                          (tu[ti[0]].x * h.bary[0] + tu[ti[1]].x * h.bary[1] + tu[ti[2]].x * h.bary[2]);
                        const double dv = (fu[i0].y * w0 + fu[i1].y * w1 + fu[i2].y * w2) -
                                          (tu[ti[0]].y * h.bary[0] + tu[ti[1]].y * h.bary[1] + tu[ti[2]].y * h.bary[2]);
                        du2 = du * du + dv * dv;
                    }
                };
                double dc2, du2;
                differences(hit, dc2, du2);
                // Faces as close as the nearest one up to rounding (coincident layers, a seam's two sides
                // at a sample on the seam) are the same surface point with other attributes: the one that
                // matches the sample best is the attribute error there, as for the surface itself (compare
                // of a mesh with itself is zero; the milk truck's overlapping decal faces gave a UV RMS of
                // 0.005 when the first one found was taken).
                for (const TriangleBvh::Hit& h : ties) {
                    if (dc2 + du2 == 0) break;
                    double c2, u2;
                    differences(h, c2, u2);
                    if (c2 + u2 < dc2 + du2) {
                        dc2 = c2;
                        du2 = u2;
                    }
                }
                color_sum2 += dc2 * (255.0 * 255.0) / 3.0;
                uv_sum2 += du2;
                ++attr_count;
            }
            if ((++done & 0x3fff) == 0)
                check_progress(progress, progress_base + 0.5 * std::min(1.0, double(done) / double(wanted)), "compare");
        }
    }
    if (colors && attr_count) {
        result.has_color_error = true;
        result.color_rms = std::sqrt(color_sum2 / double(attr_count));
    }
    if (uvs && attr_count) {
        result.has_texcoord_error = true;
        result.texcoord_rms = std::sqrt(uv_sum2 / double(attr_count));
    }
    return acc;
}

// Both directions, with both trees built.
DistanceResult measure_both(const Mesh& reference, const TriangleBvh* ref_bvh, const Mesh& test,
                            const TriangleBvh* test_bvh, const DistanceParams& params, Progress* progress) {
    DistanceResult r;
    r.diagonal = reference.bounds().diagonal();
    const unsigned threads = std::max(1u, params.threads);

    // Each direction raises its own copy of the region field (they may run at once); merged by max.
    std::vector<float>* region = nullptr;
    std::vector<float> region_back;
    if (params.region_errors) {
        r.region_errors.assign(test.vertex_count(), 0.f);
        region_back.assign(test.vertex_count(), 0.f);
        region = &r.region_errors;
    }
    // Beside this thread the backward direction only polls for cancellation: one reporter at a time.
    struct CancelOnly final : Progress {
        Progress* parent;
        explicit CancelOnly(Progress* p) : parent(p) {}
        void report(double, std::string_view) override {}
        bool cancelled() const override { return parent && parent->cancelled(); }
    } cancel_only(progress);
    Progress* back_progress = threads > 1 ? &cancel_only : progress;

    Accumulator forward, backward;
    auto forward_side = [&] {
        forward = measure(test, *ref_bvh, reference, params, params.seed, true, r, progress, 0.0, region, true);
        // Vertices: samples for the maxima and the per-vertex field.
        if (!(params.include_vertices || params.vertex_errors || params.region_errors)) return;
        std::uint32_t hint = 0xffffffffu;
        if (params.vertex_errors) r.vertex_errors.assign(test.vertex_count(), 0.f);
        std::vector<std::uint8_t> used(test.vertex_count(), 0);
        for (std::uint32_t i : test.indices) used[i] = 1;
        for (std::size_t v = 0; v < test.vertex_count(); ++v) {
            const double d = std::sqrt(ref_bvh->closest(to_p3(test.positions[v]), hint).distance2);
            if (params.vertex_errors) r.vertex_errors[v] = static_cast<float>(d);
            if (used[v]) raise_to(region, static_cast<std::uint32_t>(v), d);
            if (params.include_vertices && used[v]) forward.max = std::max(forward.max, d);
        }
    };
    auto backward_side = [&] {
        DistanceResult ignored;
        backward = measure(reference, *test_bvh, test, params, params.seed ^ 0x9e3779b97f4a7c15ull, false, ignored,
                           back_progress, 0.5, region ? &region_back : nullptr, false);
        if (!params.include_vertices) return;
        std::uint32_t hint = 0xffffffffu;
        std::vector<std::uint8_t> ref_used(reference.vertex_count(), 0);
        for (std::uint32_t i : reference.indices) ref_used[i] = 1;
        for (std::size_t v = 0; v < reference.vertex_count(); ++v) {
            if (!ref_used[v]) continue;
            const TriangleBvh::Hit hit = test_bvh->closest(to_p3(reference.positions[v]), hint);
            const double d = std::sqrt(hit.distance2);
            backward.max = std::max(backward.max, d);
            if (region) {
                const int k = major_corner(hit.bary[0], hit.bary[1], hit.bary[2]);
                raise_to(&region_back, test.indices[3 * hit.triangle + k], d);
            }
        }
    };
    detail::run_beside(threads, forward_side, backward_side);
    r.test_to_reference = forward.finish();
    r.reference_to_test = backward.finish();
    if (region)
        for (std::size_t v = 0; v < region_back.size(); ++v) r.region_errors[v] = std::max(r.region_errors[v], region_back[v]);
    r.hausdorff = std::max(r.test_to_reference.max, r.reference_to_test.max);
    const double n = double(forward.count + backward.count);
    if (n > 0) {
        r.mean = (forward.sum + backward.sum) / n;
        r.rms = std::sqrt((forward.sum2 + backward.sum2) / n);
    }
    if (r.diagonal > 0) {
        r.hausdorff_relative = r.hausdorff / r.diagonal;
        r.mean_relative = r.mean / r.diagonal;
        r.rms_relative = r.rms / r.diagonal;
    }
    return r;
}

}  // namespace

struct DistanceReference::Tree {
    TriangleBvh bvh;
    explicit Tree(const Mesh& mesh) : bvh(mesh) {}
};

DistanceReference::DistanceReference(const Mesh& reference) : mesh_(&reference) {
    require_triangles(reference, "reference");
    tree_ = std::make_unique<Tree>(reference);
}

DistanceReference::~DistanceReference() = default;

DistanceResult compare(const Mesh& reference, const Mesh& test, const DistanceParams& params, Progress* progress) {
    require_triangles(reference, "reference");
    require_triangles(test, "test");
    check_progress(progress, 0.0, "compare");
    std::optional<TriangleBvh> ref_bvh, test_bvh;
    detail::run_beside(std::max(1u, params.threads), [&] { ref_bvh.emplace(reference); }, [&] { test_bvh.emplace(test); });
    DistanceResult r = measure_both(reference, &*ref_bvh, test, &*test_bvh, params, progress);
    check_progress(progress, 1.0, "compare");
    return r;
}

DistanceResult compare(const DistanceReference& reference, const Mesh& test, const DistanceParams& params,
                       Progress* progress) {
    require_triangles(test, "test");
    check_progress(progress, 0.0, "compare");
    const TriangleBvh test_bvh(test);
    DistanceResult r = measure_both(reference.mesh(), &reference.tree_->bvh, test, &test_bvh, params, progress);
    check_progress(progress, 1.0, "compare");
    return r;
}

}  // namespace lodforge
