#include "lodforge/io/mesh_io.h"

#include "lodforge/error.h"
#include "lodforge/io/input_file.h"
#include "lodforge/io/gltf_reader.h"
#include "lodforge/io/gltf_writer.h"
#include "lodforge/io/mesh_validate.h"
#include "lodforge/io/obj.h"
#include "lodforge/io/ply.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace lodforge {
namespace fs = std::filesystem;

namespace {

std::string lower_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

// Turns the usual reasons a file cannot be read into one clear sentence before any parser runs.
void check_readable(const std::string& path) {
    check_input_file(path, "a mesh file");
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw_error(Error::Kind::io, path, std::string("cannot open: ") + std::strerror(errno));
}

// The texture-coordinate set a one-set format (PLY, OBJ) should keep: the set the first base colour
// texture samples (glTF `texCoord`), else set 0.
int single_texcoord_set(const Mesh& mesh) {
    for (const Material& m : mesh.materials)
        if (!m.base_color_texture.empty())
            return m.base_color_texture.texcoord_set >= 0 &&
                           static_cast<std::size_t>(m.base_color_texture.texcoord_set) < mesh.texcoords.size()
                       ? m.base_color_texture.texcoord_set
                       : 0;
    return 0;
}

// A copy with texture-coordinate set `set` moved to the front; textures sampling it now say set 0.
Mesh with_texcoord_set_first(const Mesh& mesh, int set) {
    Mesh copy = mesh;
    std::swap(copy.texcoords[0], copy.texcoords[static_cast<std::size_t>(set)]);
    for (Material& m : copy.materials)
        for (TextureRef* t : {&m.base_color_texture, &m.normal_texture, &m.metallic_roughness_texture,
                              &m.occlusion_texture, &m.emissive_texture}) {
            if (t->texcoord_set == set) t->texcoord_set = 0;
            else if (t->texcoord_set == 0) t->texcoord_set = set;
        }
    return copy;
}

}  // namespace

FileFormat format_from_extension(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".ply") return FileFormat::ply;
    if (ext == ".obj") return FileFormat::obj;
    if (ext == ".gltf") return FileFormat::gltf;
    if (ext == ".glb") return FileFormat::glb;
    return FileFormat::unknown;
}

FileFormat detect_format(const std::string& path) {
    if (const FileFormat f = format_from_extension(path); f != FileFormat::unknown) return f;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return FileFormat::unknown;  // a FIFO would block the probe
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    if (in.gcount() == 4) {
        if (std::memcmp(magic, "ply", 3) == 0 && (magic[3] == '\n' || magic[3] == '\r')) return FileFormat::ply;
        if (std::memcmp(magic, "glTF", 4) == 0) return FileFormat::glb;
    }
    return FileFormat::unknown;
}

const char* format_name(FileFormat format) {
    switch (format) {
        case FileFormat::ply: return "PLY";
        case FileFormat::obj: return "OBJ";
        case FileFormat::gltf: return "glTF";
        case FileFormat::glb: return "GLB";
        case FileFormat::unknown: break;
    }
    return "unknown";
}

// LodForge's own files are the likeliest wrong input (an artist drops an asset on the reader): say what
// the file is and how to get a mesh out of it.
static std::string unknown_format_message(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const char* what = nullptr;
    if (ext == ".mco") what = "marching-cube octree (extract a mesh with `lodforge mcoctree extract`)";
    else if (ext == ".lfo") what = "out-of-core octree asset (extract a mesh with `lodforge octree extract`)";
    else if (ext == ".lodstrips") what = "LODStrips model (extract a mesh with `lodforge strips extract`)";
    else if (ext == ".lfmorph" || ext == ".lfmstrips") what = "morph LOD model (extract a mesh with `lodforge morph extract`)";
    std::string message = "unknown mesh format (supported: .ply, .obj, .gltf, .glb)";
    if (what) message = std::string("not a mesh: a LodForge ") + what + "; meshes are .ply, .obj, .gltf, .glb";
    return message;
}

Mesh read_mesh(const std::string& path, const ReadOptions& options, Progress* progress) {
    check_readable(path);
    Mesh mesh;
    switch (detect_format(path)) {
        case FileFormat::ply: mesh = read_ply(path, progress); break;
        case FileFormat::obj: mesh = read_obj(path, progress); break;
        case FileFormat::gltf:
        case FileFormat::glb: {
            GltfReadOptions gltf;
            gltf.place_every_instance = options.place_every_instance;
            mesh = read_gltf(path, progress, gltf);
            break;
        }
        case FileFormat::unknown:
            throw_error(Error::Kind::unsupported, path, unknown_format_message(path));
    }
    if (options.validate) {
        const ValidationReport report = validate(mesh);
        for (const auto& finding : report.findings)
            if (finding.severity == ValidationFinding::Severity::error)
                throw_error(Error::Kind::invalid, path, finding.message);
    }
    return mesh;
}

void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options, Progress* progress) {
    const FileFormat format = format_from_extension(path);
    if (format == FileFormat::ply || format == FileFormat::obj) {
        if (format == FileFormat::obj && mesh.point_count() == 0)
            throw_error(Error::Kind::invalid, path,
                        "no vertices to write to an .obj (an OBJ needs at least one 'v' line)");
        // PLY and OBJ store one texture-coordinate set; write the one the textures sample.
        if (const int set = single_texcoord_set(mesh); set > 0 && options.write_texcoords) {
            const Mesh one_set = with_texcoord_set_first(mesh, set);
            if (format == FileFormat::ply) write_ply(one_set, path, options, progress);
            else write_obj(one_set, path, options, progress);
            return;
        }
    }
    switch (format) {
        case FileFormat::ply: write_ply(mesh, path, options, progress); return;
        case FileFormat::obj: write_obj(mesh, path, options, progress); return;
        case FileFormat::glb: {
            if (mesh.triangle_count() == 0) throw_error(Error::Kind::invalid, path, "no triangles to write to a .glb");
            // One level, one node: the pack's writer (materials, embedded images, v flipped back). A
            // texture that cannot be read is dropped with a warning, as the OBJ writer keeps going
            // with a dangling reference: the geometry is what was asked for.
            GlbOptions glb;
            glb.name = std::filesystem::path(path).stem().string();
            if (glb.name.empty()) glb.name = "mesh";
            glb.skip_missing_textures = true;
            std::vector<Mesh> levels{mesh};  // the writer takes a list of levels
            if (!options.write_normals) levels[0].normals.clear();
            if (!options.write_colors) levels[0].colors.clear();
            if (!options.write_texcoords) levels[0].texcoords.clear();
            const GlbResult r = write_glb(levels, glb, path, progress);
            if (options.warnings)
                for (const std::string& w : r.warnings) options.warnings->push_back(path + ": " + w);
            return;
        }
        case FileFormat::gltf:
            throw_error(Error::Kind::unsupported, path,
                        ".gltf output is not written; use .glb (the same glTF 2.0 with its buffers and textures in one file)");
        case FileFormat::unknown: break;
    }
    throw_error(Error::Kind::unsupported, path, "unknown output format (use .ply, .obj or .glb)");
}

}  // namespace lodforge
