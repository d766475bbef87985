// The leaf-cube flood of the marching-cube octree (see mc_leaf_flood.h).
//
// Follows Hasup Lee, "Efficient Level-of-Detail Model Generation of 3D Objects using Prioritized Marching
// Cube Octree" (doctoral thesis, KAIST, 2007, ch. 4): leaf cubes are the cubes whose corners' signed
// distances change sign; null cubes are never stored.
#include "mcoctree/mc_leaf_flood.h"

#include <algorithm>
#include <cmath>

namespace lodforge::mc {

std::uint64_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    auto spread = [](std::uint64_t v) {
        v &= 0x1fffff;
        v = (v | v << 32) & 0x1f00000000ffffULL;
        v = (v | v << 16) & 0x1f0000ff0000ffULL;
        v = (v | v << 8) & 0x100f00f00f00f00fULL;
        v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
        v = (v | v << 2) & 0x1249249249249249ULL;
        return v;
    };
    return spread(x) | (spread(y) << 1) | (spread(z) << 2);
}

LeafFlood::LeafFlood(Field& field_, std::uint32_t grid_, float cap_, unsigned threads_, Progress* progress_,
                     std::size_t expected)
    : visited(expected, grid_), field(field_), grid(grid_), cap(cap_), threads(threads_), progress(progress_) {}

void LeafFlood::seed(const std::vector<Vec3f>& points, Vec3f origin, double h) {
    for (const Vec3f& p : points) {
        const Vec3f r = (p - origin) * static_cast<float>(1.0 / h);
        std::uint32_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            const auto c = static_cast<std::uint32_t>(std::clamp(r[a], 0.f, float(grid - 1)));
            // A point on a lattice plane (as the field places that plane: `world`) also seeds the cube
            // on the plane's other side. The plane's lattice points are on the point's tangent plane
            // when the input is flat along that axis, so they count as outside (D1), and only the cube
            // on the normal's back side has a sign change: a flat, axis-aligned cloud got no seed.
            // The rounding of `r` may put the point in either cube, hence both tests.
            lo[a] = hi[a] = c;
            if (c > 0 && field.world(pack(c, c, c))[a] >= p[a]) lo[a] = c - 1;
            if (c + 1 < grid && field.world(pack(c + 1, c + 1, c + 1))[a] <= p[a]) hi[a] = c + 1;
        }
        for (std::uint32_t z = lo[2]; z <= hi[2]; ++z)
            for (std::uint32_t y = lo[1]; y <= hi[1]; ++y)
                for (std::uint32_t x = lo[0]; x <= hi[0]; ++x)
                    if (visited.insert(pack(x, y, z))) frontier.push_back(pack(x, y, z));
    }
    std::sort(frontier.begin(), frontier.end());  // lattice order: the queries' hints are near
}

void LeafFlood::run() {
    // The neighbour of cube `k` across face f (inside the grid: the caller checks).
    auto face_neighbour = [](std::uint64_t k, int f) {
        const int a = f / 2;
        const std::uint64_t step = std::uint64_t(1) << (17 * a);
        return f & 1 ? k + step : k - step;
    };
    // The faces of cube `k` with corner signs `inside` that the surface crosses towards a neighbour
    // inside the grid for which `wanted(neighbour)` holds.
    auto crossed_faces = [&](std::uint64_t k, std::uint32_t inside, auto&& wanted) {
        std::uint8_t faces = 0;
        for (int f = 0; f < 6; ++f) {
            const int a = f / 2, side = f & 1;
            std::uint32_t fm = 0, count = 0;
            for (int c = 0; c < 8; ++c)
                if (((c >> a) & 1) == side) fm |= ((inside >> c) & 1u) << count++;
            if (fm == 0 || fm == 15) continue;  // the surface does not cross this face
            const auto coord = std::int64_t((k >> (17 * a)) & mc::max_lattice) + (side ? 1 : -1);
            if (coord < 0 || coord >= std::int64_t(grid)) continue;
            if (wanted(face_neighbour(k, f))) faces = static_cast<std::uint8_t>(faces | 1u << f);
        }
        return faces;
    };
    while (!frontier.empty()) {
        check_progress(progress, 0.05 + 0.4 * (1.0 - 1.0 / double(++round + 1)), "mcoctree: leaf cubes");
        corner_keys.clear();
        for (std::uint64_t k : frontier)
            for (int c = 0; c < 8; ++c)
                corner_keys.push_back(k + pack(c & 1, (c >> 1) & 1, (c >> 2) & 1));
        field.evaluate(corner_keys);
        // Each cube's corner signs and the faces the surface crosses towards cubes not examined before
        // this round, on every thread (reads only); then, in frontier order, the leaves and the new
        // frontier. A neighbour examined before the round would not be inserted anyway, so leaving it
        // out changes nothing but the work.
        cube_states.resize(frontier.size());
        parallel_for(frontier.size(), threads, [&](std::size_t b, std::size_t e) {
            std::vector<Blocks::Cached> field_cache(Blocks::cache_size), visited_cache(Blocks::cache_size);
            for (std::size_t i = b; i < e; ++i) {
                const std::uint64_t k = frontier[i];
                CubeState& st = cube_states[i];
                st = {0, 0, 0};
                float far = 0;
                for (int c = 0; c < 8; ++c) {
                    float d = 0;
                    if (!field.peek_dist(k + pack(c & 1, (c >> 1) & 1, (c >> 2) & 1), field_cache.data(), d)) {
                        st.state = CubeState::serial;
                        break;
                    }
                    if (d < 0) st.inside = static_cast<std::uint8_t>(st.inside | 1u << c);
                    far = std::max(far, std::fabs(d));
                }
                if (st.state == CubeState::serial) continue;
                if (st.inside == 0 || st.inside == 255) continue;
                if (far > cap) {
                    st.state = CubeState::far;
                    continue;
                }
                st.state = CubeState::kept;
                st.faces = crossed_faces(k, st.inside, [&](std::uint64_t nk) {
                    return !visited.contains(nk, visited_cache.data());
                });
            }
        });
        next.clear();
        for (std::size_t i = 0; i < frontier.size(); ++i) {
            const std::uint64_t k = frontier[i];
            CubeState st = cube_states[i];
            if (st.state == CubeState::serial) {  // a corner not evaluated (none, in practice): as before
                st = {0, 0, CubeState::none};
                float far = 0;
                for (int c = 0; c < 8; ++c) {
                    const float d = field.dist(field.index(k + pack(c & 1, (c >> 1) & 1, (c >> 2) & 1)));
                    if (d < 0) st.inside = static_cast<std::uint8_t>(st.inside | 1u << c);
                    far = std::max(far, std::fabs(d));
                }
                if (st.inside != 0 && st.inside != 255) {
                    st.state = far > cap ? CubeState::far : CubeState::kept;
                    st.faces = crossed_faces(k, st.inside, [](std::uint64_t) { return true; });
                }
            }
            if (st.state == CubeState::far) ++dropped_far_cubes;
            if (st.state != CubeState::kept) continue;
            const auto x = std::uint32_t(k & mc::max_lattice), y = std::uint32_t((k >> 17) & mc::max_lattice),
                       z = std::uint32_t((k >> 34) & mc::max_lattice);
            leaves.push_back({morton(x, y, z), x, y, z, st.inside});
            for (int f = 0; f < 6; ++f) {
                if (!(st.faces & (1u << f))) continue;
                const std::uint64_t nk = face_neighbour(k, f);
                if (visited.insert(nk)) next.push_back(nk);
            }
        }
        frontier.swap(next);
    }
}

}  // namespace lodforge::mc
