// A thin open tube along z (a needle): a part far thinner than the cells or cubes a coarse target needs,
// for the cases where clustering or a marching-cube lattice loses it entirely.
#pragma once

#include "lodforge/mesh.h"

#include <cmath>
#include <cstdint>

namespace lodforge::test {

// `sides` around, `rings` + 1 rings of points from z = 0 to `length`, faces counter-clockwise seen from
// outside.
inline Mesh needle(int sides, int rings, float radius, float length) {
    Mesh m;
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i < sides; ++i) {
            const float a = 6.2831853f * float(i) / float(sides);
            m.positions.push_back({radius * std::cos(a), radius * std::sin(a), length * float(j) / float(rings)});
        }
    const auto s = static_cast<std::uint32_t>(sides);
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < sides; ++i) {
            const auto a = std::uint32_t(j) * s + std::uint32_t(i), b = std::uint32_t(j) * s + std::uint32_t((i + 1) % sides);
            m.indices.insert(m.indices.end(), {a, b, b + s, a, b + s, a + s});
        }
    return m;
}

}  // namespace lodforge::test
