// Mesh outputs of the commands (simplify, convert, lod, the extract subcommands): which extensions are
// written, checked before any long work, and the write itself with its warnings on stderr.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/progress.h"

#include <string>

namespace lodforge::cli {

// Throws Error(unsupported) "<command>: <path>: the output must be .ply, .obj or .glb" for anything else
// (exit 1, as write_mesh answers the same name),
// so a typo fails at once rather than after the work.
void check_mesh_output(const std::string& command, const std::string& path);

// write_mesh(), then "lodforge: warning: ..." on stderr for what the writer left out (a .glb's
// unreadable texture).
void write_mesh_output(const Mesh& mesh, const std::string& path, WriteOptions options = {},
                       Progress* progress = nullptr);

// read_mesh(), refusing a mesh without triangles (a point cloud, an empty file) with the file's name:
// "<path>: no triangles (N points): `<command>` needs a triangle mesh". The algorithms' own checks do not
// know the file, so their messages ("build_lod_chain: the mesh has no triangles") did not name it.
Mesh read_triangle_mesh(const std::string& command, const std::string& path, Progress* progress);

}  // namespace lodforge::cli
