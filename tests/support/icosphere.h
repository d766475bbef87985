// An icosphere for tests that need a closed genus-0 mesh with known connectivity (the supermesh of two
// meshes, issue 8 case (b)): 10 · 4^s + 2 vertices, faces counter-clockwise seen from outside.
#pragma once

#include "lodforge/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace lodforge::test {

// Subdivided `subdivisions` times, on the sphere of `radius` around `centre`.
inline Mesh icosphere(int subdivisions, float radius = 1.f, Vec3f centre = {})
{
    const float t = (1.f + std::sqrt(5.f)) / 2.f;
    std::vector<Vec3f> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::uint32_t> f = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                                    3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    for (auto& q : p) q = q * (1.f / length(q));
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto middle = [&](std::uint32_t a, std::uint32_t b) {
            const auto k = std::minmax(a, b);
            auto it = mid.find(k);
            if (it != mid.end()) return it->second;
            Vec3f m = (p[a] + p[b]) * 0.5f;
            p.push_back(m * (1.f / length(m)));
            return mid[k] = std::uint32_t(p.size() - 1);
        };
        std::vector<std::uint32_t> g;
        for (std::size_t i = 0; i < f.size(); i += 3) {
            const std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
            const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
            g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f.swap(g);
    }
    Mesh m;
    for (auto q : p) m.positions.push_back(centre + q * radius);
    m.indices = f;
    return m;
}

}  // namespace lodforge::test
