// play_lodstrips FILE.lodstrips: loads the file with the header-only runtime (no LodForge library to
// link) and prints the triangles at full detail, half way and the coarsest level, as "T1 T2 T3".
#include <lodforge/runtime/lodstrips_runtime.h>
#include <lodforge/runtime/morph_lodstrips_runtime.h>  // the other runtime: header-only as well

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: play_lodstrips FILE.lodstrips\n");
        return 2;
    }
    lodstrips::LodStrips lod;
    std::string error;
    if (!lod.load_file(argv[1], &error)) {
        std::fprintf(stderr, "play_lodstrips: %s: %s\n", argv[1], error.c_str());
        return 1;
    }
    lod.go_to_lod(1.0);
    const std::size_t full = lod.triangle_count();
    lod.go_to_lod(0.5);
    const std::size_t half = lod.triangle_count();
    lod.go_to_lod(0.0);
    std::printf("%zu %zu %zu\n", full, half, lod.triangle_count());
    return 0;
}
