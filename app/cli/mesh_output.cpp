#include "mesh_output.h"

#include "lodforge/error.h"

#include <cstdio>
#include <vector>

namespace lodforge::cli {

void check_mesh_output(const std::string& command, const std::string& path) {
    const FileFormat f = format_from_extension(path);
    if (f != FileFormat::ply && f != FileFormat::obj && f != FileFormat::glb)
        throw Error(Error::Kind::argument, command + ": " + path + ": the output must be .ply, .obj or .glb");
}

void write_mesh_output(const Mesh& mesh, const std::string& path, WriteOptions options, Progress* progress) {
    std::vector<std::string> warnings;
    options.warnings = &warnings;
    write_mesh(mesh, path, options, progress);
    for (const std::string& w : warnings) std::fprintf(stderr, "lodforge: warning: %s\n", w.c_str());
}

}  // namespace lodforge::cli
