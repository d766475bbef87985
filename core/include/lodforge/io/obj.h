// Wavefront OBJ (+ MTL) import through tinyobjloader and an in-house writer.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/progress.h"

#include <string>

namespace lodforge {

// Positions as stored become the first vertices (position_ids = their OBJ index); every distinct
// (v, vt, vn) corner beyond the first use of a position adds a wedge. Polygons are fan-triangulated.
// Materials from the MTL with map_Kd/bump/norm textures; a missing MTL or texture is not fatal
// (the mesh opens untextured, the texture keeps its path so callers can report it missing).
Mesh read_obj(const std::string& path, Progress* progress = nullptr);

// Writes one `v` per surface point (so wedges of a point stay one point) and `vt`/`vn` per vertex, `usemtl` groups per face material and a
// sibling .mtl when the mesh has materials; textures are copied (or extracted, when embedded) next to
// the output when options.copy_textures is set.
void write_obj(const Mesh& mesh, const std::string& path, const WriteOptions& options = {},
               Progress* progress = nullptr);

}  // namespace lodforge
