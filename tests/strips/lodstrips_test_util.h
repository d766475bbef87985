// Shared by the LODStrips tests: built models cached per (mesh, join mode), triangle multisets.
#pragma once

#include "lodforge/strips/lodstrips.h"
#include "lodforge/io/mesh_io.h"
#include "support/test_paths.h"

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace lodforge {
// Readable test names in ctest (gtest prints parameters otherwise as raw bytes).
inline void PrintTo(StripJoin join, std::ostream* os) { *os << (join == StripJoin::restart ? "restart" : "degenerate"); }
}  // namespace lodforge

namespace lodforge::test {

struct BuiltModel {
    Mesh mesh;
    LodStripsBuild build;
};

inline std::string lodstrips_mesh_path(const std::string& name) {
    static const std::map<std::string, std::string> paths = {
        {"bunny", "scan-bunny/bun_zipper.ply"},
        {"spot", "tex-spot/spot_triangulated.obj"},
        {"frag_115", "color-open3d-frag115/frag_115.ply"},
        {"dragon_res3", "scan-dragon/dragon_vrip_res3.ply"},
        {"dragon_res4", "scan-dragon/dragon_vrip_res4.ply"},
        {"truck", "tex-cesium-milk-truck/CesiumMilkTruck.gltf"},
    };
    return shared_data(paths.at(name));
}

inline const BuiltModel& built(const std::string& name, StripJoin join, StripOrder order = StripOrder::run_off) {
    static std::map<std::pair<std::string, int>, std::unique_ptr<BuiltModel>> cache;
    auto& slot = cache[{name, static_cast<int>(join) * 2 + static_cast<int>(order == StripOrder::cache)}];
    if (!slot) {
        slot = std::make_unique<BuiltModel>();
        slot->mesh = read_mesh(lodstrips_mesh_path(name));
        LodStripsParams p;
        p.join = join;
        p.strip_order = order;
        slot->build = build_lodstrips(slot->mesh, p);
    }
    return *slot;
}

using Tri = std::array<std::uint32_t, 3>;

// Rotated so the smallest index comes first: equal for the same triangle with the same winding only.
inline Tri canonical_tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (b < a && b < c) return {b, c, a};
    if (c < a && c < b) return {c, a, b};
    return {a, b, c};
}

inline std::vector<Tri> sorted_tris(const std::vector<std::uint32_t>& list) {
    std::vector<Tri> t;
    t.reserve(list.size() / 3);
    for (std::size_t i = 0; i + 2 < list.size(); i += 3) t.push_back(canonical_tri(list[i], list[i + 1], list[i + 2]));
    std::sort(t.begin(), t.end());
    return t;
}

// Level k of the indexed mesh (replay_collapses), in canonical vertex numbers.
inline std::vector<Tri> reference_level(const BuiltModel& m, std::size_t k) {
    std::vector<std::uint32_t> list = replay_collapses(m.mesh, m.build.simplification, k);
    for (std::uint32_t& v : list) v = m.build.canonical[v];
    return sorted_tris(list);
}

}  // namespace lodforge::test
