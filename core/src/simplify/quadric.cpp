// Plane quadrics (Garland & Heckbert 1997) and Hoppe's 1999 memory-efficient attribute quadrics.
// See lodforge/quadric.h for the definitions.
#include "lodforge/simplify/quadric.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace lodforge {
namespace {

Vec3d sub(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d crossd(Vec3d a, Vec3d b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dotd(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// add_triangle()'s register path: up to this many attributes and corners (more: the general loop).
constexpr std::size_t kMaxDimension = 32;
constexpr std::size_t kMaxCorners = 8;

}  // namespace

Quadric Quadric::from_plane(Vec3d n, double d, double weight) {
    Quadric q;
    q.a00 = weight * n.x * n.x;
    q.a01 = weight * n.x * n.y;
    q.a02 = weight * n.x * n.z;
    q.a11 = weight * n.y * n.y;
    q.a12 = weight * n.y * n.z;
    q.a22 = weight * n.z * n.z;
    q.b0 = weight * n.x * d;
    q.b1 = weight * n.y * d;
    q.b2 = weight * n.z * d;
    q.c = weight * d * d;
    q.weight = weight;
    return q;
}

std::optional<Quadric> Quadric::from_triangle(Vec3d p0, Vec3d p1, Vec3d p2, double& area) {
    const Vec3d e1{p1.x - p0.x, p1.y - p0.y, p1.z - p0.z}, e2{p2.x - p0.x, p2.y - p0.y, p2.z - p0.z};
    Vec3d n{e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x};
    const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    area = 0.5 * len;
    if (!(len > 0)) return std::nullopt;
    n = {n.x / len, n.y / len, n.z / len};
    return from_plane(n, -(n.x * p0.x + n.y * p0.y + n.z * p0.z), area);
}

AttributeQuadrics::AttributeQuadrics(std::size_t count, std::size_t dimension)
    : m_(dimension), data_(count * (11 + 4 * dimension), 0.0) {}

void AttributeQuadrics::add_triangle(std::size_t index, Vec3d p0, Vec3d p1, Vec3d p2, const double* s0,
                                     const double* s1, const double* s2, double weight) {
    add_triangle(&index, 1, p0, p1, p2, s0, s1, s2, weight);
}

void AttributeQuadrics::add_triangle(const std::size_t* indices, std::size_t count, Vec3d p0, Vec3d p1, Vec3d p2,
                                     const double* s0, const double* s1, const double* s2, double weight) {
    if (m_ == 0) return;
    const Vec3d e1 = sub(p1, p0), e2 = sub(p2, p0);
    const Vec3d n = crossd(e1, e2);
    const double nn = dotd(n, n);
    if (!(nn > 0) || !(weight > 0)) return;  // a degenerate face has no attribute gradient
    // g·e1 = Δs1, g·e2 = Δs2, g·n = 0  ⇒  g = (Δs1 (e2×n) + Δs2 (n×e1)) / |n|²
    const Vec3d u = crossd(e2, n), v = crossd(n, e1);
    // The terms of attribute j: A (6), b (3), c, G_j (3), D_j.
    auto terms = [&](std::size_t j, double* t) {
        const double d1 = s1[j] - s0[j], d2 = s2[j] - s0[j];
        const Vec3d g{(d1 * u.x + d2 * v.x) / nn, (d1 * u.y + d2 * v.y) / nn, (d1 * u.z + d2 * v.z) / nn};
        const double d = s0[j] - dotd(g, p0);
        t[0] = weight * g.x * g.x; t[1] = weight * g.x * g.y; t[2] = weight * g.x * g.z;
        t[3] = weight * g.y * g.y; t[4] = weight * g.y * g.z; t[5] = weight * g.z * g.z;
        t[6] = weight * d * g.x;   t[7] = weight * d * g.y;   t[8] = weight * d * g.z;
        t[9] = weight * d * d;     t[10] = weight * g.x;      t[11] = weight * g.y;
        t[12] = weight * g.z;      t[13] = weight * d;
    };
    bool distinct = count <= kMaxCorners && m_ <= kMaxDimension;
    if (distinct && count == 3)  // a face's three corners (the simplifier's call)
        distinct = indices[0] != indices[1] && indices[1] != indices[2] && indices[0] != indices[2];
    else
        for (std::size_t i = 0; distinct && i < count; ++i)
            for (std::size_t k = i + 1; k < count; ++k) distinct = distinct && indices[i] != indices[k];
    if (distinct) {
        // Each quadric receives the same additions in the same order as below (attribute by attribute,
        // then the weight), so the sums are the same bits; but A, b and c (summed over all m attributes)
        // stay in registers for one quadric instead of being loaded and stored m times per corner.
        // (Setup of an attribute-aware frag_115 run spent a sixth of all its instructions here.)
        double t[kMaxDimension][14];
        for (std::size_t j = 0; j < m_; ++j) terms(j, t[j]);
        for (std::size_t i = 0; i < count; ++i) {
            double* q = &data_[indices[i] * stride()];
            double* G = q + 11;  // Gx (m), Gy (m), Gz (m)
            double* D = q + 11 + 3 * m_;
            double acc[10];
            for (int k = 0; k < 10; ++k) acc[k] = q[k];
            for (std::size_t j = 0; j < m_; ++j)
                for (int k = 0; k < 10; ++k) acc[k] += t[j][k];
            for (int k = 0; k < 10; ++k) q[k] = acc[k];
            for (std::size_t j = 0; j < m_; ++j) {
                G[j] += t[j][10];
                G[m_ + j] += t[j][11];
                G[2 * m_ + j] += t[j][12];
                D[j] += t[j][13];
            }
            q[10] += weight;
        }
        return;
    }
    for (std::size_t j = 0; j < m_; ++j) {
        // The same terms for every target, in the same order as one call per target: identical sums.
        double t[14];
        terms(j, t);
        for (std::size_t i = 0; i < count; ++i) {
            double* q = &data_[indices[i] * stride()];
            double* G = q + 11;  // Gx (m), Gy (m), Gz (m)
            double* D = q + 11 + 3 * m_;
            for (int k = 0; k < 10; ++k) q[k] += t[k];
            G[j] += t[10];
            G[m_ + j] += t[11];
            G[2 * m_ + j] += t[12];
            D[j] += t[13];
        }
    }
    for (std::size_t i = 0; i < count; ++i) data_[indices[i] * stride() + 10] += weight;
}

void AttributeQuadrics::accumulate(std::size_t dst, std::size_t src) {
    if (m_ == 0 || dst == src) return;
    double* a = &data_[dst * stride()];
    const double* b = &data_[src * stride()];
    for (std::size_t i = 0; i < stride(); ++i) a[i] += b[i];
}

void AttributeQuadrics::add(std::size_t dst, const AttributeQuadrics& other, std::size_t src) {
    if (m_ == 0 || other.m_ != m_) return;
    double* a = &data_[dst * stride()];
    const double* b = &other.data_[src * stride()];
    for (std::size_t i = 0; i < stride(); ++i) a[i] += b[i];
}

bool AttributeQuadrics::optimal_attributes(std::size_t index, Vec3d p, double* s) const {
    if (m_ == 0) return true;
    const double* q = &data_[index * stride()];
    const double area = q[10];
    if (!(area > 0)) return false;
    const double* G = q + 11;
    const double* D = q + 11 + 3 * m_;
    for (std::size_t j = 0; j < m_; ++j)
        s[j] = (G[j] * p.x + G[m_ + j] * p.y + G[2 * m_ + j] * p.z + D[j]) / area;
    return true;
}

double AttributeQuadrics::minimum(const std::size_t* indices, std::size_t count, Vec3d p) const {
    if (m_ == 0 || count == 0) return 0;
    // Σ_i Q_i(p, s) = geo(p) + area |s|² − 2 s·lin(p), minimised by s = lin/area: geo − |lin|²/area.
    constexpr std::size_t kStack = 32;
    double stack[kStack];
    std::vector<double> heap;
    double* lin = stack;
    if (m_ > kStack) {
        heap.assign(m_, 0.0);
        lin = heap.data();
    } else {
        std::fill(stack, stack + m_, 0.0);
    }
    const double x = p.x, y = p.y, z = p.z;
    double geo = 0, area = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const double* q = &data_[indices[i] * stride()];
        geo += q[0] * x * x + q[3] * y * y + q[5] * z * z + 2 * (q[1] * x * y + q[2] * x * z + q[4] * y * z) +
               2 * (q[6] * x + q[7] * y + q[8] * z) + q[9];
        area += q[10];
        const double* G = q + 11;
        const double* D = q + 11 + 3 * m_;
        for (std::size_t j = 0; j < m_; ++j) lin[j] += G[j] * x + G[m_ + j] * y + G[2 * m_ + j] * z + D[j];
    }
    if (!(area > 0)) return geo > 0 ? geo : 0;
    double r = geo;
    for (std::size_t j = 0; j < m_; ++j) r -= lin[j] * lin[j] / area;
    return r > 0 ? r : 0;
}

Quadric AttributeQuadrics::eliminated(std::size_t index) const {
    Quadric r;
    if (m_ == 0) return r;
    const double* q = &data_[index * stride()];
    const double area = q[10];
    if (!(area > 0)) return r;
    r.a00 = q[0]; r.a01 = q[1]; r.a02 = q[2]; r.a11 = q[3]; r.a12 = q[4]; r.a22 = q[5];
    r.b0 = q[6]; r.b1 = q[7]; r.b2 = q[8];
    r.c = q[9];
    const double* G = q + 11;
    const double* D = q + 11 + 3 * m_;
    for (std::size_t j = 0; j < m_; ++j) {
        const double gx = G[j], gy = G[m_ + j], gz = G[2 * m_ + j], d = D[j];
        r.a00 -= gx * gx / area; r.a01 -= gx * gy / area; r.a02 -= gx * gz / area;
        r.a11 -= gy * gy / area; r.a12 -= gy * gz / area; r.a22 -= gz * gz / area;
        r.b0 -= d * gx / area; r.b1 -= d * gy / area; r.b2 -= d * gz / area;
        r.c -= d * d / area;
    }
    return r;
}

bool optimal_position(const Quadric& q, Vec3d& out) {
    Eigen::Matrix3d A;
    A << q.a00, q.a01, q.a02, q.a01, q.a11, q.a12, q.a02, q.a12, q.a22;
    const Eigen::Vector3d b(q.b0, q.b1, q.b2);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A, Eigen::EigenvaluesOnly);
    const Eigen::Vector3d ev = eig.eigenvalues();  // ascending
    const double largest = std::fabs(ev(2));
    if (!(largest > 0) || ev(0) < 1e-4 * largest) return false;
    const Eigen::Vector3d x = A.ldlt().solve(-b);
    if (!x.allFinite()) return false;
    out = {x(0), x(1), x(2)};
    return true;
}

Vec3d minimizer_near(const Quadric& q, Vec3d around, double relative_tolerance) {
    Eigen::Matrix3d A;
    A << q.a00, q.a01, q.a02, q.a01, q.a11, q.a12, q.a02, q.a12, q.a22;
    const Eigen::Vector3d b(q.b0, q.b1, q.b2);
    const Eigen::Vector3d xbar(around.x, around.y, around.z);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
    const Eigen::Vector3d ev = eig.eigenvalues();
    const double largest = std::max(std::fabs(ev(0)), std::fabs(ev(2)));
    Eigen::Vector3d inv = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a)
        if (largest > 0 && std::fabs(ev(a)) > relative_tolerance * largest) inv(a) = 1.0 / ev(a);
    const Eigen::Matrix3d& V = eig.eigenvectors();
    Eigen::Vector3d x = xbar + V * inv.asDiagonal() * V.transpose() * (-b - A * xbar);
    if (!x.allFinite()) x = xbar;
    return {x(0), x(1), x(2)};
}

}  // namespace lodforge
