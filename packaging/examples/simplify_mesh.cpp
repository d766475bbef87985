// simplify_mesh IN OUT RATIO: reads IN (.ply, .obj, .gltf, .glb), keeps RATIO of its triangles with the
// edge-collapse simplifier and writes OUT. Prints "IN_TRIANGLES -> OUT_TRIANGLES".
#include <lodforge/error.h>
#include <lodforge/io/mesh_io.h>
#include <lodforge/simplify/simplify.h>

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: simplify_mesh IN OUT RATIO\n");
        return 2;
    }
    try {
        const lodforge::Mesh mesh = lodforge::read_mesh(argv[1]);
        lodforge::SimplifyParams params;
        params.target_ratio = static_cast<float>(std::atof(argv[3]));
        const lodforge::SimplifyResult r = lodforge::simplify(mesh, params);
        lodforge::write_mesh(r.mesh, argv[2]);
        std::printf("%zu -> %zu\n", mesh.triangle_count(), r.mesh.triangle_count());
    } catch (const lodforge::Error& e) {
        std::fprintf(stderr, "simplify_mesh: %s\n", e.what());
        return 1;
    }
    return 0;
}
