// Error quadrics for edge-collapse simplification.
//
// Geometry: plane quadrics of Garland & Heckbert, "Surface Simplification Using Quadric Error Metrics"
// (SIGGRAPH 1997), area weighted. Attributes: the memory-efficient generalized quadric of Hoppe, "New
// Quadric Metric for Simplifying Meshes with Appearance Attributes" (IEEE Visualization 1999), which
// measures the same thing as the (3+m)-dimensional quadric of Garland & Heckbert 1998 but keeps the
// geometric error a true distance and stores 11 + 4m numbers instead of (3+m)(4+m)/2 + (3+m) + 1.
//
// All values are doubles: quadric sums over thousands of faces lose too much in float.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace lodforge {

struct Vec3d {
    double x = 0, y = 0, z = 0;
};

// Q(p) = pᵀ A p + 2 bᵀ p + c with A symmetric; `weight` is the summed weight (area) of what was added, so
// Q(p) / weight is a weighted mean of squared distances.
struct Quadric {
    double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
    double b0 = 0, b1 = 0, b2 = 0;
    double c = 0;
    double weight = 0;

    // weight * (n·p + d)² for a unit normal n.
    static Quadric from_plane(Vec3d n, double d, double weight);
    // The plane of triangle p0 p1 p2 weighted by its area (GH97's face quadric); `area` receives the
    // area. Empty when the triangle has no area (no normal).
    static std::optional<Quadric> from_triangle(Vec3d p0, Vec3d p1, Vec3d p2, double& area);
    // Inline: the simplifier's costing and setup call these millions of times.
    Quadric& operator+=(const Quadric& q) {
        a00 += q.a00; a01 += q.a01; a02 += q.a02; a11 += q.a11; a12 += q.a12; a22 += q.a22;
        b0 += q.b0; b1 += q.b1; b2 += q.b2;
        c += q.c;
        weight += q.weight;
        return *this;
    }
    double evaluate(Vec3d p) const {
        const double x = p.x, y = p.y, z = p.z;
        const double r = a00 * x * x + a11 * y * y + a22 * z * z + 2 * (a01 * x * y + a02 * x * z + a12 * y * z) +
                         2 * (b0 * x + b1 * y + b2 * z) + c;
        return r > 0 ? r : 0;  // rounding can push a sum of squares slightly negative
    }
};

// A set of per-vertex attribute quadrics of one dimension m (number of scalar attributes), stored flat.
// For every face added to a vertex: area * Σ_j (g_j·p + d_j − s_j)², where s_j(p) = g_j·p + d_j is the
// linear interpolation of attribute j over the face (its gradient lies in the face plane).
class AttributeQuadrics {
public:
    AttributeQuadrics() = default;
    AttributeQuadrics(std::size_t count, std::size_t dimension);

    std::size_t dimension() const { return m_; }
    std::size_t size() const { return m_ ? data_.size() / stride() : 0; }

    // Adds the quadric of triangle (p0, p1, p2) with attribute vectors s0, s1, s2 (each `dimension()`
    // long) weighted by `weight` (usually the area) to quadric `index`.
    void add_triangle(std::size_t index, Vec3d p0, Vec3d p1, Vec3d p2, const double* s0, const double* s1,
                      const double* s2, double weight);
    // The same triangle added to `count` quadrics (e.g. the wedges of its three corners): the gradients are
    // computed once; for distinct indices the sums are exactly those of `count` single-index calls.
    void add_triangle(const std::size_t* indices, std::size_t count, Vec3d p0, Vec3d p1, Vec3d p2,
                      const double* s0, const double* s1, const double* s2, double weight);
    // quadric[dst] += quadric[src]
    void accumulate(std::size_t dst, std::size_t src);
    // quadric[dst] += other's quadric[src] (same dimension; for sums kept in separate sets)
    void add(std::size_t dst, const AttributeQuadrics& other, std::size_t src);
    // Error of placing the vertex at p with attribute vector s. Inline: attribute-aware costing calls it
    // once per neighbour of every re-costed point.
    double evaluate(std::size_t index, Vec3d p, const double* s) const {
        const double* q = &data_[index * stride()];
        // The usual dimensions (normal 3, colour 4, texcoord 2 per set) with the loop unrolled: the
        // same arithmetic in the same order as the general loop, so the same bits.
        switch (m_) {
            case 0: return 0;
            case 2: return evaluate_at<2>(q, p, s);
            case 3: return evaluate_at<3>(q, p, s);
            case 4: return evaluate_at<4>(q, p, s);
            case 5: return evaluate_at<5>(q, p, s);
            case 7: return evaluate_at<7>(q, p, s);
            case 9: return evaluate_at<9>(q, p, s);
            default: return evaluate_at<0>(q, p, s);
        }
    }
    // The attribute vector minimising the error at p (s_j = (G_j·p + D_j) / area); false when empty.
    bool optimal_attributes(std::size_t index, Vec3d p, double* s) const;
    // min over s of Σ_i quadric[indices[i]](p, s): the error when the quadrics are merged and the
    // attributes re-solved at p (optimal placement's cost; the minimiser is optimal_attributes() of the
    // sum). 0 when the sum is empty.
    double minimum(const std::size_t* indices, std::size_t count, Vec3d p) const;
    double weight(std::size_t index) const { return m_ ? data_[index * stride() + 10] : 0.0; }
    // The quadric in p alone obtained by setting the attributes to their optimum for every p
    // (Hoppe 1999, §4): A − Σ G_j G_jᵀ/α, b − Σ D_j G_j/α, c − Σ D_j²/α. Its weight is 0.
    Quadric eliminated(std::size_t index) const;

private:
    // evaluate() for dimension M (0: m_, a runtime loop).
    template <std::size_t M>
    double evaluate_at(const double* q, Vec3d p, const double* s) const {
        const std::size_t m = M ? M : m_;
        const double x = p.x, y = p.y, z = p.z;
        double r = q[0] * x * x + q[3] * y * y + q[5] * z * z + 2 * (q[1] * x * y + q[2] * x * z + q[4] * y * z) +
                   2 * (q[6] * x + q[7] * y + q[8] * z) + q[9];
        const double area = q[10];
        const double* G = q + 11;
        const double* D = q + 11 + 3 * m;
        if constexpr (M > 0) {
            // The terms first (independent, contiguous per component: vectorised), then summed in
            // attribute order, as the loop below does.
            double term[M];
            for (std::size_t j = 0; j < M; ++j) {
                const double lin = G[j] * x + G[M + j] * y + G[2 * M + j] * z + D[j];
                term[j] = area * s[j] * s[j] - 2 * s[j] * lin;
            }
            for (std::size_t j = 0; j < M; ++j) r += term[j];
        } else {
            for (std::size_t j = 0; j < m; ++j) {
                const double lin = G[j] * x + G[m + j] * y + G[2 * m + j] * z + D[j];
                r += area * s[j] * s[j] - 2 * s[j] * lin;
            }
        }
        return r > 0 ? r : 0;
    }
    // Layout per quadric: A (6), b (3), c, area, G (3m, as Gx[m], Gy[m], Gz[m]), D (m).
    std::size_t stride() const { return 11 + 4 * m_; }
    std::size_t m_ = 0;
    std::vector<double> data_;
};

// The position minimising q (add AttributeQuadrics::eliminated() terms to include attributes). Solved
// with Eigen; false when the system is singular or ill-conditioned (flat or straight neighbourhoods,
// whose minimisers form a plane or line), in which case `out` is untouched.
bool optimal_position(const Quadric& q, Vec3d& out);

// The minimiser of q closest to `around` (Lindstrom 2000): a pseudo-inverse that drops eigenvalues below
// `relative_tolerance` times the largest, so flat or straight neighbourhoods keep the directions they do
// not constrain at `around`. Never fails; `around` when q is empty. Used where one representative must be
// placed for a whole cell or node (vertex clustering, the out-of-core octree operator), before clamping.
Vec3d minimizer_near(const Quadric& q, Vec3d around, double relative_tolerance = 1e-3);

}  // namespace lodforge
