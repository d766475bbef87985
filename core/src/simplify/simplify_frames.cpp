// The multi-frame extension of the collapse simplifier (SimplifyParams::extra_frames): per-frame plane
// quadrics and positions, so that one half-edge collapse order serves every frame of a morphing mesh.
//
// Based on:
//  - J. F. Ramos, "LODStrips: Continuous Level of Detail using Triangle Strips", PhD thesis, Universitat
//    Jaume I, 2008, chapter 6 (collapse sequences shared by the frames of a morphing mesh);
//  - M. Garland, P. Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997
//    (plane quadrics and border constraint planes, here one set per frame).
#include "simplify/simplify_internal.h"

#include <cmath>

namespace lodforge::simplify_detail {

void Simplifier::setup_frames() {
    frames_ = params_.extra_frames.size();
    frame_pos_.resize(points_ * frames_);
    frame_geo_.assign(points_ * frames_, Quadric{});
    for (std::size_t f = 0; f < frames_; ++f) {
        const std::vector<Vec3f>* frame = params_.extra_frames[f];
        // Frame 0's normalisation for all: costs stay comparable across frames.
        for (std::size_t p = 0; p < points_; ++p) {
            const Vec3d q = to3d((*frame)[representative_[p]]);
            frame_pos_[p * frames_ + f] = {(q.x - centre_.x) / scale_, (q.y - centre_.y) / scale_, (q.z - centre_.z) / scale_};
        }
    }
    for (std::uint32_t face = 0; face < face_alive_.size(); ++face) {
        if (!face_alive_[face]) continue;
        const std::uint32_t* c = &fpt_[3 * face];
        for (std::size_t f = 0; f < frames_; ++f) {
            const Vec3d p0 = frame_pos_[c[0] * frames_ + f], p1 = frame_pos_[c[1] * frames_ + f],
                        p2 = frame_pos_[c[2] * frames_ + f];
            const Vec3d n = crossd(sub(p1, p0), sub(p2, p0));
            const double len = std::sqrt(dotd(n, n));
            if (!(len > 0)) continue;
            const Vec3d un{n.x / len, n.y / len, n.z / len};
            const Quadric q = Quadric::from_plane(un, -dotd(un, p0), face_weight(0.5 * len));
            for (int k = 0; k < 3; ++k) frame_geo_[c[k] * frames_ + f] += q;
        }
    }
}

// The border constraint plane of edge pq (see classify_points) in every extra frame.
void Simplifier::add_frame_border_planes(std::uint32_t p, std::uint32_t q, std::uint32_t face, double factor) {
    const std::uint32_t* cc = &fpt_[3 * face];
    for (std::size_t f = 0; f < frames_; ++f) {
        auto at = [&](std::uint32_t point) { return frame_pos_[point * frames_ + f]; };
        const Vec3d n = crossd(sub(at(cc[1]), at(cc[0])), sub(at(cc[2]), at(cc[0])));
        const Vec3d e = sub(at(q), at(p));
        Vec3d m = crossd(e, n);
        const double len = std::sqrt(dotd(m, m));
        if (!(len > 0)) continue;
        m = {m.x / len, m.y / len, m.z / len};
        Quadric bq = Quadric::from_plane(m, -dotd(m, at(p)), factor * constraint_weight(dotd(e, e), 0.5 * std::sqrt(dotd(n, n))));
        bq.weight = 0;
        frame_geo_[p * frames_ + f] += bq;
        frame_geo_[q * frames_ + f] += bq;
    }
}

// Frame 0's cost (combine() of its geometric and attribute values), with the excess geometric cost of
// u's region at v in every extra frame.
double Simplifier::frames_cost(std::uint32_t u, std::uint32_t v, double geometric, double attribute,
                               double weight) const {
    auto mean = [](double q, double w) { return w > 0 ? q / w : q * 1e12; };
    // Accumulated as the excess over frame 0's geometric cost, so that frames equal to frame 0 add
    // exactly nothing and the cost is bit for bit the one-frame cost (the greedy schedule's order
    // depends on every last bit; tested by MorphLod.SingleOrderWithIdenticalFramesIsTheOneFrameOrder).
    const double base = mean(geometric, weight);
    double excess = 0;
    for (std::size_t f = 0; f < frames_; ++f) {
        const Quadric& q = frame_geo_[u * frames_ + f];
        const double d = mean(q.evaluate(frame_pos_[v * frames_ + f]), q.weight) - base;
        if (params_.frame_cost == SimplifyParams::FrameCost::max) excess = std::max(excess, d);
        else excess += d;
    }
    if (params_.frame_cost == SimplifyParams::FrameCost::sum) excess /= double(frames_ + 1);
    return combine(geometric, attribute, weight) + double(params_.frame_weight) * excess;
}

// No face around u flips or becomes a needle in any extra frame when u moves onto v. Other frames only
// refuse real flips (normal turned past 90°): with the full normal limit in every pose of a strongly
// deforming sequence few collapses stay legal and the coarse levels get stuck (docs/morph.md).
constexpr double kFrameMinDot = 0.0;
bool Simplifier::frames_valid(std::uint32_t u, std::uint32_t v) const {
    const double min_dot = std::min(double(params_.min_normal_dot), kFrameMinDot);
    for (std::uint32_t face : faces_of(u)) {
        const std::uint32_t* c = &fpt_[3 * face];
        if (c[0] == v || c[1] == v || c[2] == v || killed(c)) continue;
        for (std::size_t f = 0; f < frames_; ++f) {
            Vec3d p[3], q[3];
            for (int k = 0; k < 3; ++k) {
                p[k] = frame_pos_[c[k] * frames_ + f];
                q[k] = c[k] == u ? frame_pos_[v * frames_ + f] : p[k];
            }
            const Vec3d n0 = crossd(sub(p[1], p[0]), sub(p[2], p[0]));
            const Vec3d n1 = crossd(sub(q[1], q[0]), sub(q[2], q[0]));
            const double l0 = dotd(n0, n0), l1 = dotd(n1, n1);
            if (!(l0 > 0)) continue;
            double longest = 0;
            for (int k = 0; k < 3; ++k) {
                const Vec3d e = sub(q[(k + 1) % 3], q[k]);
                longest = std::max(longest, dotd(e, e));
            }
            if (!(l1 > 1e-12 * longest * longest)) return false;
            if (dotd(n0, n1) < min_dot * std::sqrt(l0 * l1)) return false;
        }
    }
    return true;
}

}  // namespace lodforge::simplify_detail
