// Quantisation shared by the morph file writers (.lfmorph, .lfmstrips): octahedral normals in 2 × 16 bits
// (Meyer et al., "On Floating-Point Normal Vectors", EGSR 2010; Cigolle et al., JCGT 2014).
#pragma once

#include "lodforge/types.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lodforge {

// Octahedral mapping of a unit vector to two values in [-1, 1].
inline void oct_encode(Vec3f n, std::int16_t out[2]) {
    const float s = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
    float u = s > 0 ? n.x / s : 0.f, v = s > 0 ? n.y / s : 0.f;
    if (n.z < 0) {
        const float a = (1.f - std::fabs(v)) * (u >= 0 ? 1.f : -1.f);
        const float b = (1.f - std::fabs(u)) * (v >= 0 ? 1.f : -1.f);
        u = a;
        v = b;
    }
    out[0] = static_cast<std::int16_t>(std::lround(std::clamp(u, -1.f, 1.f) * 32767.f));
    out[1] = static_cast<std::int16_t>(std::lround(std::clamp(v, -1.f, 1.f) * 32767.f));
}

inline Vec3f oct_decode(std::int16_t a, std::int16_t b) {
    const float u = std::max(float(a) / 32767.f, -1.f), v = std::max(float(b) / 32767.f, -1.f);
    Vec3f n{u, v, 1.f - std::fabs(u) - std::fabs(v)};
    if (n.z < 0) {
        const float x = (1.f - std::fabs(v)) * (u >= 0 ? 1.f : -1.f);
        const float y = (1.f - std::fabs(u)) * (v >= 0 ? 1.f : -1.f);
        n.x = x;
        n.y = y;
    }
    const float len = length(n);
    return len > 0 ? n * (1.f / len) : Vec3f{0, 0, 1};
}

}  // namespace lodforge
