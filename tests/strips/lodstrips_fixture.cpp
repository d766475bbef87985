// Writes what the standalone runtime test reads: a .lodstrips file made by the core, and the reference
// triangles of the indexed mesh (replay_collapses) at a set of levels. Usage: lodstrips_fixture DIR
// Reference file: u32 level count, then per level u32 level, u32 triangle count, 3 x u32 per triangle
// (canonical vertex numbers, input winding, smallest index first, sorted); little-endian.
#include "strips/lodstrips_test_util.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: lodstrips_fixture DIR\n");
        return 2;
    }
    try {
        using namespace lodforge;
        std::filesystem::create_directories(argv[1]);
        for (const auto& [name, join] : {std::pair{"dragon_res4", StripJoin::restart},
                                         std::pair{"spot", StripJoin::degenerate}}) {
            test::BuiltModel m;
            m.mesh = read_mesh(test::lodstrips_mesh_path(name));
            LodStripsParams p;
            p.join = join;
            m.build = build_lodstrips(m.mesh, p);
            const std::string stem = std::string(argv[1]) + "/" + name;
            write_lodstrips(m.build.data, stem + ".lodstrips");
            const std::size_t K = m.build.data.collapse_count();
            std::vector<std::size_t> levels;
            for (std::size_t i = 0; i <= 16; ++i) levels.push_back(K * i / 16);
            std::ofstream out(stem + ".ref", std::ios::binary);
            auto u32 = [&](std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
            u32(static_cast<std::uint32_t>(levels.size()));
            for (std::size_t k : levels) {
                const std::vector<test::Tri> tris = test::reference_level(m, k);
                u32(static_cast<std::uint32_t>(k));
                u32(static_cast<std::uint32_t>(tris.size()));
                for (const test::Tri& t : tris)
                    for (std::uint32_t v : t) u32(v);
            }
            if (!out) throw std::runtime_error("cannot write " + stem + ".ref");
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lodstrips_fixture: %s\n", e.what());
        return 1;
    }
    return 0;
}
