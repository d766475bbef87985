// Reading and writing meshes by file name. The format comes from the extension (and, for reading, the
// file's first bytes): .ply, .obj, .gltf, .glb. Writers never leave a partial file behind: they write to
// a temporary file beside the target and rename it into place only when everything was written.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/progress.h"

#include <string>
#include <vector>

namespace lodforge {

enum class FileFormat { unknown, ply, obj, gltf, glb };

FileFormat format_from_extension(const std::string& path);
// Extension first; falls back to magic bytes ("ply\n", "glTF") for unknown or missing extensions.
FileFormat detect_format(const std::string& path);
const char* format_name(FileFormat format);

struct ReadOptions {
    // Triangulate polygons with a fan from the first corner (PLY, OBJ). Polygons are always accepted.
    bool validate = true;  // run validate() and throw on its errors (index range, NaN positions)
    bool place_every_instance = false;  // glTF: see GltfReadOptions
};

// Throws Error naming the file on any problem.
Mesh read_mesh(const std::string& path, const ReadOptions& options = {}, Progress* progress = nullptr);

enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

struct WriteOptions {
    PlyEncoding ply_encoding = PlyEncoding::binary_little_endian;
    bool ply_colors_as_uchar = true;  // false writes float colours
    bool write_normals = true;
    bool write_colors = true;
    bool write_texcoords = true;
    bool copy_textures = true;  // OBJ: copy/extract referenced textures next to the output
    // PLY: each face's Mesh::face_materials entry as a face `texnumber` (no `TextureFile` comments then:
    // the numbers index the mesh's materials, not a texture list). For the out-of-core octree, whose
    // soup reads them; off by default, so `convert` writes what it always wrote.
    bool ply_face_materials = false;
    // When set, receives what was left out without failing (.glb: a texture that could not be read is
    // not embedded), each message starting with the output path.
    std::vector<std::string>* warnings = nullptr;
};

// Writes PLY, OBJ (+MTL) or GLB (glTF 2.0 binary, one node; textures embedded) chosen by extension.
// Throws Error naming the file on failure.
void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options = {},
                Progress* progress = nullptr);

}  // namespace lodforge
