// Small double-precision vector helpers for the sphere map and the overlay (internal to the core).
#pragma once

#include <array>
#include <cmath>

namespace lodforge::sphere {

using D3 = std::array<double, 3>;

inline D3 add(const D3& a, const D3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline D3 sub(const D3& a, const D3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline D3 mul(const D3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline D3 cross(const D3& a, const D3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const D3& a) { return std::sqrt(dot(a, a)); }
inline D3 normalized(const D3& a) {
    const double n = norm(a);
    return n > 0 ? mul(a, 1.0 / n) : D3{0, 0, 1};
}
// orient3d(centre, a, b, c) for the centre at the origin: > 0 when a, b, c turn counter-clockwise seen
// from outside the sphere.
inline double det3(const D3& a, const D3& b, const D3& c) { return dot(a, cross(b, c)); }
// The sign of det[a, b, c] for points on the unit sphere, or 0 when rounding could have decided it.
// Computed as det[a, b − a, c − a]: the differences are (nearly) exact, so the error is a small multiple
// of 1e-16·|b − a|·|c − a| and tiny triangles keep reliable signs.
inline int orient_sign(const D3& a, const D3& b, const D3& c)
{
    const D3 u = sub(b, a), v = sub(c, a);
    const double d = dot(a, cross(u, v));
    const double tol = 1e-13 * norm(u) * norm(v);
    return d > tol ? 1 : (d < -tol ? -1 : 0);
}

// Angle between unit vectors, accurate for small angles too.
inline double angle_between(const D3& a, const D3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

}  // namespace lodforge::sphere
