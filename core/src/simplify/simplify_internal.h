// The collapse engine of simplify(): the Simplifier class, its heap and plans. Internal to the core; the
// engine is defined in simplify.cpp, its multi-frame extension (SimplifyParams::extra_frames) in
// simplify_frames.cpp.
#pragma once

#include "lodforge/simplify/simplify.h"
#include "lodforge/simplify/quadric.h"
#include "huge_pages.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace lodforge::simplify_detail {

constexpr std::uint32_t kNone = 0xffffffffu;
constexpr int kMaxClasses = 16;

// ---------------------------------------------------------------------------------------------------
// The collapse engine

// complex: on a non-manifold edge or where several fans meet; it may move along any edge the full link
// condition allows (the quadric keeps its shape).
enum class Kind : std::uint8_t { interior, border, complex, locked };

// Indexed binary min-heap of points keyed by the cost of their best collapse: O(log n) insert, update and
// remove of any point; ties go to the lower point id so runs are deterministic. Keys live in the heap
// array next to their point, so sifting compares without touching per-point memory (one cache miss per
// level instead of three).
class PointHeap {
public:
    void reset(std::size_t n) {
        slot_.assign(n, kNone);
        key_.assign(n, 0.0);
        heap_.clear();
        heap_.reserve(n);
    }
    bool empty() const { return heap_.empty(); }
    std::uint32_t top() const { return heap_[0].point; }
    bool contains(std::uint32_t p) const { return slot_[p] != kNone; }
    double key(std::uint32_t p) const { return key_[p]; }
    void prefetch(std::uint32_t p) const {
#if defined(__GNUC__)
        __builtin_prefetch(&slot_[p]);
        __builtin_prefetch(&key_[p]);
#else
        (void)p;
#endif
    }
    void set(std::uint32_t p, double k) {
        key_[p] = k;
        if (slot_[p] == kNone) {
            slot_[p] = static_cast<std::uint32_t>(heap_.size());
            heap_.push_back({k, p});
            up(slot_[p], {k, p});
            return;
        }
        const std::uint32_t i = slot_[p];
        const double old = heap_[i].key;
        if (k < old) up(i, {k, p});
        else down(i, {k, p});
    }
    void remove(std::uint32_t p) {
        const std::uint32_t i = slot_[p];
        if (i == kNone) return;
        slot_[p] = kNone;
        const Entry last = heap_.back();
        heap_.pop_back();
        if (last.point == p) return;
        // Sift the moved entry up, and down from wherever it settled.
        up(i, last);
        down(slot_[last.point], last);
    }

private:
    struct Entry {
        double key;
        std::uint32_t point;
    };
    static bool less(const Entry& a, const Entry& b) { return a.key < b.key || (a.key == b.key && a.point < b.point); }
    void up(std::uint32_t i, Entry e) {
        while (i > 0) {
            const std::uint32_t parent = (i - 1) / 2;
            if (!less(e, heap_[parent])) break;
            heap_[i] = heap_[parent];
            slot_[heap_[i].point] = i;
            i = parent;
        }
        heap_[i] = e;
        slot_[e.point] = i;
    }
    void down(std::uint32_t i, Entry e) {
        const auto n = static_cast<std::uint32_t>(heap_.size());
        while (true) {
            std::uint32_t c = 2 * i + 1;
            if (c >= n) break;
            if (c + 1 < n && less(heap_[c + 1], heap_[c])) ++c;
            if (!less(heap_[c], e)) break;
            heap_[i] = heap_[c];
            slot_[heap_[i].point] = i;
            i = c;
        }
        heap_[i] = e;
        slot_[e.point] = i;
    }

    std::vector<Entry> heap_;
    std::vector<std::uint32_t> slot_;
    std::vector<double> key_;
};

// How the (wedge, material) classes of the removed point map onto wedges of the kept point.
struct Plan {
    int count = 0;
    std::uint32_t wedge[kMaxClasses];
    std::uint32_t material[kMaxClasses];
    std::uint32_t target[kMaxClasses];
    int edge_faces = 0;
    Vec3d position;
};

inline Vec3d to3d(Vec3f p) { return {p.x, p.y, p.z}; }
inline Vec3d sub(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d crossd(Vec3d a, Vec3d b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double dotd(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

class Simplifier {
public:
    Simplifier(const Mesh& mesh, const SimplifyParams& params, Progress* progress)
        : mesh_(mesh), params_(params), progress_(progress) {}

    SimplifyResult run();

private:
    void setup();
    void classify_points();
    void add_edge_plane(std::uint32_t p, std::uint32_t q, double factor);
    bool is_seam_edge(std::uint32_t p, std::uint32_t q) const;
    std::uint32_t point(std::uint32_t wedge) const { return pid_[wedge]; }
    const double* attr(std::uint32_t wedge) const { return &attrs_[wedge * dims_]; }
    std::uint32_t material(std::uint32_t face) const {
        return mesh_.face_materials.empty() ? 0 : mesh_.face_materials[face];
    }
    // Faces of p. Greedy: per-point lists holding live faces only (collapse_greedy() removes dead faces
    // from every list that had them). Passes: a CSR rebuilt after every pass, exact for every point the
    // running pass has not locked (see run_passes()).
    std::span<const std::uint32_t> faces_of(std::uint32_t p) const {
        if (!greedy_) return {csr_faces_.data() + csr_begin_[p], csr_begin_[p + 1] - csr_begin_[p]};
        return {pfaces_[p].data(), pfaces_[p].size()};
    }
    void build_csr();
    // A face killed earlier in the running pass: its CSR entries stay until the pass ends, and collapse()
    // renamed its corners so that two coincide.
    static bool killed(const std::uint32_t* fp) { return fp[0] == fp[1] || fp[1] == fp[2] || fp[0] == fp[2]; }
    void neighbours(std::uint32_t p, std::vector<std::uint32_t>& out);
    // The greedy order jumps across the mesh, so most of a collapse's points and faces are cold: their
    // loads are issued together ahead of use instead of one miss after another.
    static void prefetch(const void* address) {
#if defined(__GNUC__)
        __builtin_prefetch(address);
#else
        (void)address;
#endif
    }
    void prefetch_point(std::uint32_t p) const {
        prefetch(&pts_[p]);
    }
    double evaluate(std::uint32_t u, std::uint32_t v, Plan& plan, bool full);
    // evaluate()'s checks and cost on a plan whose classes and targets are filled in.
    double plan_cost(std::uint32_t u, std::uint32_t v, Plan& plan);
    double merged_attribute_cost(std::uint32_t v, const Plan& plan) const;
    void merge_box(std::uint32_t wedge, const double* lo, const double* hi) {
        double* l = &attr_lo_[wedge * dims_];
        double* h = &attr_hi_[wedge * dims_];
        for (std::size_t j = 0; j < dims_; ++j) {
            l[j] = std::min(l[j], lo[j]);
            h[j] = std::max(h[j], hi[j]);
        }
    }
    void write_solved_attributes(Mesh& out, const std::vector<std::uint32_t>& vertex_map) const;
    // evaluate(p, n, plan, false) for every neighbour n of p, in neighbours() order, from one walk over
    // p's faces (evaluate() walks them once per neighbour): calls f(n, cost). False (nothing called) when
    // p has more classes or neighbours than the walk keeps on its stack; the caller then evaluates one by one.
    template <class F>
    bool for_each_cost(std::uint32_t p, F&& f);
    // Extra frames (SimplifyParams::extra_frames): per-frame quadrics and positions, [point * frames + f].
    void setup_frames();
    void add_frame_border_planes(std::uint32_t p, std::uint32_t q, std::uint32_t face, double factor);
    double frames_cost(std::uint32_t u, std::uint32_t v, double geometric, double attribute, double weight) const;
    bool frames_valid(std::uint32_t u, std::uint32_t v) const;
    bool valid(std::uint32_t u, std::uint32_t v, const Plan& plan);
    bool texture_kept(std::uint32_t u, std::uint32_t v, const Plan& plan) const;
    // Geometry only, half-edge: an interior or border point with one wedge onto a point with one wedge.
    // The mapping is trivial and the cost is Q_u(p_v) over u's area, so plain_plan() and plain_valid()
    // give evaluate(full) and valid() in one walk over u's faces (a border point's edge count, which
    // evaluate() checks, included).
    bool plain_pair(std::uint32_t u, std::uint32_t v) const {
        return plain_ && (pts_[u].kind == Kind::interior || pts_[u].kind == Kind::border) && pts_[u].one_wedge &&
               pts_[v].one_wedge;
    }
    std::uint32_t cheapest_plain_border(std::uint32_t p, double& best);
    template <bool pen>
    std::uint32_t cheapest_plain(std::uint32_t p, double& best, const Vec3d& nb);
    double plain_plan(std::uint32_t u, std::uint32_t v, Plan& plan) const;
    // evaluate(full) for a fused_pair(): the trivial mapping, attribute costs included (the edge count is
    // left to plain_valid<true>(), as for plain pairs).
    double fused_plan(std::uint32_t u, std::uint32_t v, Plan& plan);
    // plan_cost() of the trivial plan (u's only wedge onto v's, one material, half-edge, no frames):
    // the same arithmetic without the plan, the quadric copy and the class loops. Attribute runs cost
    // most candidates this way (perf: plan_cost() and the two evaluations were the largest extra of an
    // attribute-aware frag_115 run over a geometry-only one).
    double fused_cost(std::uint32_t u, std::uint32_t v) const {
        const Quadric& q = geo_[u];
        const Vec3d pv = pts_[v].pos;
        const double attribute = dims_ > 0 ? aq_.evaluate(pts_[u].wedge, pv, attr(pts_[v].wedge)) : 0.0;
        return combine(q.evaluate(pv), attribute, q.weight);
    }
    // A collapse's cost from its geometric quadric value (a sum over u's area) and its attribute quadric
    // value: the geometry as a mean over the area (a squared distance), the attributes *not* divided, so
    // they stay an integral over the area the collapse disturbs (meshoptimizer's choice). An attribute
    // change then costs in proportion to the size of the region it spans, like a geometric deviation
    // does: a normal that turns across a few small triangles is cheap, one that turns across a large
    // flat region is not. Divided by the area (as before) the same normal change cost the same
    // everywhere, so at fine scale it outweighed every geometric error and fine detail with curvature
    // was kept while flat-shaded regions collapsed (the Duck's mean error 2.3x geometry-only's).
    static double combine(double geometric, double attribute, double weight) {
        return (weight > 0 ? geometric / weight : geometric * 1e12) + attribute;
    }
    // A face's quadric weight from its area (SimplifyParams::area_weight).
    double face_weight(double area) const {
        return params_.area_weight == SimplifyParams::AreaWeight::sqrt_area ? std::sqrt(area) : area;
    }
    // A constraint plane's weight: |e|² (GH97) scaled as its face's weight is scaled from the face's area
    // (area > 0), so against that face it counts the same under either weighting.
    double constraint_weight(double e2, double area) const {
        return params_.area_weight == SimplifyParams::AreaWeight::area ? e2 : e2 * face_weight(area) / area;
    }
    // Height term of the pass schedule's order (SimplifyParams::height_weight; see penalty()).
    // fan_normal(p): the unit area-weighted normal of p's live faces (their summed cross products; zero
    // when they cancel).
    Vec3d fan_normal(std::uint32_t p) const {
        Vec3d s{0, 0, 0};
        for (std::uint32_t f : faces_of(p)) {
            const std::uint32_t* c = &fpt_[3 * f];
            if (killed(c)) continue;
            const Vec3d a = pts_[c[0]].pos;
            const Vec3d n = crossd(sub(pts_[c[1]].pos, a), sub(pts_[c[2]].pos, a));
            s = {s.x + n.x, s.y + n.y, s.z + n.z};
        }
        const double len = std::sqrt(dotd(s, s));
        if (!(len > 0)) return {0, 0, 0};
        return {s.x / len, s.y / len, s.z / len};
    }
    // The height of p_u over u's fan moved onto p_v: how far the removed point ends up from the surface
    // that replaces it (exact for a flat fan), measured along the fan's unit normal `nb`.
    double height(std::uint32_t u, std::uint32_t v, const Vec3d& nb) const {
        return std::abs(dotd(nb, sub(pts_[u].pos, pts_[v].pos)));
    }
    // Added to the cost of u -> v for the order only: height_weight x (u's bound + the height of p_u)^2.
    // The quadric's mean is diluted as a point's area grows, so a point that already stands for a region
    // far from its faces (bumps bridged by large flat triangles) would keep collapsing cheaply; the bound
    // carries that distance along undiluted (see PointRec::bound).
    double penalty(std::uint32_t u, std::uint32_t v, const Vec3d& nb) const {
        const double t = double(pts_[u].bound) + height(u, v, nb);
        return height_weight_ * t * t;
    }
    double height_weight_ = 0;  // params_.height_weight where it applies (run()), else 0
    // kFaceOrder: the flip test computes the normals as valid() does (edges from the face's first
    // corner), so it decides exactly as valid(); without, from u (the fused geometry path's arithmetic).
    template <bool kFaceOrder = false>
    bool plain_valid(std::uint32_t u, std::uint32_t v, const Plan& plan);
    // Attribute runs (one material, half-edge, no extra frames): a one-wedge interior or border point
    // onto a one-wedge point is checked by plain_valid<true>() (valid() in one face walk); the cost
    // still comes from evaluate().
    bool fused_pair(std::uint32_t u, std::uint32_t v) const {
        return fusable_ && (pts_[u].kind == Kind::interior || pts_[u].kind == Kind::border) && pts_[u].one_wedge &&
               pts_[v].one_wedge;
    }
    void collapse(std::uint32_t u, std::uint32_t v, const Plan& plan);
    std::uint32_t cheapest(std::uint32_t p, double& cost);
    std::uint32_t cheapest_valid(std::uint32_t p, std::uint32_t rejected, double& cost);
    void run_greedy(std::size_t target, double limit, double& max_cost);
    void run_passes(std::size_t target, double limit, double& max_cost);
    void update_best(std::uint32_t p);
    void report(std::size_t target);
    void reroute(std::uint32_t u, std::uint32_t rejected);
    void after_collapse(std::uint32_t u, std::uint32_t v);

    const Mesh& mesh_;
    const SimplifyParams& params_;
    Progress* progress_;

    std::vector<std::uint32_t> pid_;          // wedge → point
    std::vector<std::uint32_t> representative_;
    std::size_t points_ = 0;
    // Everything the walk and costing read or write of a *neighbour* in one cache line: its position and
    // kind, the round schedule's state (entry cost, gained point, lock) and the stamped marks of
    // neighbours() and valid(), so a neighbour touched by a collapse costs one cold line instead of four
    // (record, round state, two mark arrays). The quadric, read only for the point being costed (in
    // index order) or collapsed, lives apart. `constrained`: the point's entry is not its cheapest edge,
    // that one being invalid; it is fully re-costed when its neighbourhood changes.
    struct alignas(64) PointRec {
        Vec3d pos;
        std::uint32_t best_to = kNone;
        Kind kind = Kind::interior;
        std::uint8_t one_wedge = 0;
        std::uint8_t constrained = 0;
        std::uint8_t dirty = 0;  // pass schedule (see run_passes)
        double cost = std::numeric_limits<double>::infinity();  // pass schedule: cost of the entry
        std::uint32_t gained = kNone;  // pass schedule: the kept point of a collapse next to it (kGained)
        std::uint32_t lock = 0;        // pass schedule: the round that locked it
        std::uint32_t seen = 0;        // stamp of neighbours() / plain_valid() / classify_points()
        std::uint32_t ring = 0;        // stamp of valid() / plain_valid(): in v's ring
        float bound = 0;               // pass schedule with height_weight: how far the region this point
                                       // stands for may be from its faces (grown by each collapse onto it)
        std::uint32_t wedge = 0;       // its first wedge (the only one when one_wedge): the plain paths'
                                       // mapping without two dependent loads from the wedge CSR
    };
    static_assert(sizeof(PointRec) == 64);
    HugeVector<Quadric> geo_;
    HugeVector<PointRec> pts_;
    Vec3d centre_;
    double scale_ = 1;                        // model units per normalised unit (the diagonal)
    std::vector<std::uint32_t> corners_;      // per face, wedges
    HugeVector<std::uint32_t> fpt_;          // per face, points (pid_ of corners_, kept in step)
    std::vector<std::uint8_t> face_alive_;
    bool greedy_ = false;
    std::vector<std::vector<std::uint32_t>> pfaces_;          // greedy schedule
    HugeVector<std::uint32_t> csr_begin_, csr_faces_;         // pass schedule
    std::vector<std::uint32_t> live_faces_;                    // ascending; compacted by build_csr()
    bool live_listed_ = false;
    std::vector<std::uint32_t> wedge_begin_, wedge_list_;  // point → its wedges (CSR)
    std::vector<std::uint8_t> point_alive_;
    AttributeQuadrics aq_;
    std::size_t dims_ = 0;
    bool one_material_ = true;  // no face materials, or the same on every face
    bool fusable_ = false;  // one material, no extra frames, half-edge placement
    bool plain_ = false;    // fusable_ and no attribute cost
    std::vector<double> attrs_;               // per wedge, weighted attribute vector
    // Where each attribute channel lies in attrs_ (optimal placement unpacks the solved values).
    struct AttrChannel {
        enum class Kind { normal, color, texcoord } kind;
        std::size_t set, offset, count;
        double scale;  // attrs_ value = scale * attribute
    };
    std::vector<AttrChannel> attr_channels_;
    std::vector<const std::vector<Vec2f>*> uv_sets_;  // half-edge: the texcoord sets with a weight (texture_kept())
    // Optimal placement: per wedge, the box of the (weighted) attribute values at the corners of the
    // faces its quadric holds; the solved values are clamped into it, since the face planes extrapolate
    // once the point moves past a chart's edge (UVs outside the chart sample the atlas's gutter).
    std::vector<double> attr_lo_, attr_hi_;
    PointHeap heap_;
    std::size_t alive_faces_ = 0;
    std::size_t start_faces_ = 0;
    std::vector<std::uint32_t> scratch_a_, scratch_b_, scratch_n_, ring_, scratch_fill_;
    // Stamped membership marks in PointRec (no clearing between uses): neighbours() dedupes with
    // `seen`, valid() marks v's ring in `ring`.
    std::uint32_t seen_stamp_ = 0, ring_stamp_ = 0;
    std::uint32_t next_seen() {
        if (++seen_stamp_ == 0) {
            for (PointRec& r : pts_) r.seen = 0;
            seen_stamp_ = 1;
        }
        return seen_stamp_;
    }
    std::uint32_t next_ring() {
        if (++ring_stamp_ == 0) {
            for (PointRec& r : pts_) r.ring = 0;
            ring_stamp_ = 1;
        }
        return ring_stamp_;
    }
    // Artist control (SimplifyParams::importance, lock), per point; empty when not given.
    std::vector<float> importance_;
    std::vector<std::uint8_t> pinned_;
    bool pinned(std::uint32_t p) const { return !pinned_.empty() && pinned_[p]; }
    std::vector<float> seam_factor_;  // SimplifyParams::seam_weights per point; empty when none
    // The factor of a collapse u -> v's cost (1 without importance or seam weights).
    double importance_factor(std::uint32_t u, std::uint32_t v) const {
        const bool half_edge = params_.placement == Placement::half_edge;
        double f = 1.0;
        if (!importance_.empty())
            f = 1.0 + double(params_.importance_scale) * double(half_edge ? importance_[u] : std::max(importance_[u], importance_[v]));
        if (!seam_factor_.empty()) f *= double(half_edge ? seam_factor_[u] : std::max(seam_factor_[u], seam_factor_[v]));
        return f;
    }
    std::vector<std::pair<double, std::uint32_t>> options_;
    std::size_t frames_ = 0;                  // extra frames
    std::vector<Quadric> frame_geo_;
    std::vector<Vec3d> frame_pos_;
    SimplifyResult result_;
};

}  // namespace lodforge::simplify_detail
