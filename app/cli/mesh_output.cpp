#include "mesh_output.h"

#include "lodforge/error.h"

#include <cstdio>
#include <string>
#include <vector>

namespace lodforge::cli {

void check_mesh_output(const std::string& command, const std::string& path) {
    const FileFormat f = format_from_extension(path);
    if (f != FileFormat::ply && f != FileFormat::obj && f != FileFormat::glb)
        throw Error(Error::Kind::unsupported, command + ": " + path + ": the output must be .ply, .obj or .glb");
}

void write_mesh_output(const Mesh& mesh, const std::string& path, WriteOptions options, Progress* progress) {
    std::vector<std::string> warnings;
    options.warnings = &warnings;
    write_mesh(mesh, path, options, progress);
    for (const std::string& w : warnings) std::fprintf(stderr, "lodforge: warning: %s\n", w.c_str());
}

Mesh read_triangle_mesh(const std::string& command, const std::string& path, Progress* progress) {
    Mesh mesh = read_mesh(path, {}, progress);
    if (mesh.triangle_count() == 0)
        throw_error(Error::Kind::invalid, path, "no triangles (" + std::to_string(mesh.point_count()) +
                                                    " points): '" + command + "' needs a triangle mesh");
    return mesh;
}

}  // namespace lodforge::cli
