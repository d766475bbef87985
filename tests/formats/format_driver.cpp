// Sanitizer driver for the format matrix (docs/import-obj-gltf.md): every file on the command line is
// read (no validation), summarised, validated and written as PLY, OBJ and GLB into OUT_DIR, so an
// -fsanitize=address,undefined build exercises the importers and writers on each variant without the
// whole CLI. Errors are printed and the next file follows; a sanitizer report or a signal is a bug.
// Usage: format_driver OUT_DIR FILE...
#include "lodforge/error.h"
#include "lodforge/io/mesh_info.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/mesh_validate.h"
#include <cstdio>
#include <filesystem>
int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: format_driver OUT_DIR FILE...\n");
        return 2;
    }
    const std::string out = argv[1];
    std::filesystem::create_directories(out);
    for (int i = 2; i < argc; ++i) {
        try {
            lodforge::ReadOptions ro;
            ro.validate = false;
            lodforge::Mesh m = lodforge::read_mesh(argv[i], ro);
            (void)lodforge::mesh_info(m, argv[i], "x");
            (void)lodforge::validate(m);
            for (const char* ext : {".ply", ".obj", ".glb"}) {
                try {
                    lodforge::write_mesh(m, out + "/x" + ext);
                } catch (const lodforge::Error& e) {
                    std::printf("  write %s: %s\n", ext, e.what());
                }
            }
            std::printf("ok %s %zu %zu\n", argv[i], m.point_count(), m.triangle_count());
        } catch (const lodforge::Error& e) {
            std::printf("err %s\n", e.what());
        }
    }
}
