// Small value types shared by the whole core. Plain aggregates on purpose: they are stored by the
// million in struct-of-arrays meshes and streamed to disk, so they must stay trivially copyable.
#pragma once

#include <cmath>
#include <cstdint>

namespace lodforge {

struct Vec2f {
    float x = 0, y = 0;
    friend bool operator==(const Vec2f&, const Vec2f&) = default;
};

struct Vec3f {
    float x = 0, y = 0, z = 0;
    friend bool operator==(const Vec3f&, const Vec3f&) = default;
    friend Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

// RGBA, each channel in [0, 1]. Importers convert uchar colours with c / 255.
struct Vec4f {
    float x = 0, y = 0, z = 0, w = 0;
    friend bool operator==(const Vec4f&, const Vec4f&) = default;
};

inline float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3f cross(Vec3f a, Vec3f b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
inline bool is_finite(Vec3f a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

// Axis-aligned box; empty() until the first point is added.
struct Bounds {
    Vec3f min{INFINITY, INFINITY, INFINITY};
    Vec3f max{-INFINITY, -INFINITY, -INFINITY};

    bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
    void add(Vec3f p) {
        min = {std::fmin(min.x, p.x), std::fmin(min.y, p.y), std::fmin(min.z, p.z)};
        max = {std::fmax(max.x, p.x), std::fmax(max.y, p.y), std::fmax(max.z, p.z)};
    }
    Vec3f size() const { return empty() ? Vec3f{} : max - min; }
    Vec3f center() const { return empty() ? Vec3f{} : (min + max) * 0.5f; }
    float diagonal() const { return empty() ? 0.f : length(max - min); }
};

}  // namespace lodforge
