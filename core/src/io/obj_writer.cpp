// Wavefront OBJ (+ MTL) writer.
//
// `v` lines are written per surface point (position_ids), `vt`/`vn` per vertex (wedge), and faces
// reference `point/vertex/vertex`, so reading the file back reproduces the same points and wedges.
// When wedges of one point disagree on position or colour (which position_ids forbid, but a broken
// producer could do it) the writer falls back to one `v` per vertex rather than weld them.
// Numbers use std::to_chars shortest round-trip form, so floats survive a write/read cycle exactly.
#include "lodforge/io/obj.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace lodforge {
namespace fs = std::filesystem;

namespace {

void append_float(std::string& out, float value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, result.ptr);
}

void append_uint(std::string& out, std::uint64_t value) {
    char buffer[24];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, result.ptr);
}

// MTL names and file names are whitespace-separated tokens.
std::string token_safe(const std::string& name) {
    std::string out;
    for (unsigned char c : name) out += (std::isspace(c) || c < 0x20) ? '_' : static_cast<char>(c);
    return out;
}

std::string extension_for(const TextureRef& texture) {
    const std::string& mime = texture.mime_type;
    if (mime == "image/png") return ".png";
    if (mime == "image/jpeg") return ".jpg";
    if (mime == "image/bmp") return ".bmp";
    if (mime == "image/gif") return ".gif";
    if (mime == "image/webp") return ".webp";
    const auto& b = texture.bytes;
    if (b.size() >= 4 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') return ".png";
    if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return ".jpg";
    if (b.size() >= 2 && b[0] == 'B' && b[1] == 'M') return ".bmp";
    if (b.size() >= 4 && b[0] == 'G' && b[1] == 'I' && b[2] == 'F') return ".gif";
    return ".bin";
}

void write_bytes_atomically(const std::string& target, const std::vector<std::uint8_t>& bytes) {
    AtomicFile file(target, true);
    file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.commit();
}

// Decides where each texture of the output lives and writes the copies.
class TextureExporter {
public:
    TextureExporter(const Mesh& mesh, const fs::path& output, const WriteOptions& options)
        : mesh_(mesh), out_dir_(output.parent_path().empty() ? fs::path(".") : output.parent_path()),
          stem_(token_safe(output.stem().string())), copy_(options.copy_textures) {
        std::error_code ec;
        fs::path absolute = fs::absolute(out_dir_, ec);
        out_dir_abs_ = ec ? out_dir_ : absolute.lexically_normal();
    }

    // The string to write after map_Kd / norm, or "" when the texture cannot be referenced.
    std::string reference(const TextureRef& texture, const std::string& label) {
        if (texture.empty()) return {};
        if (!texture.bytes.empty()) {
            if (!copy_) return {};  // embedded data has no file to point at unless it is extracted
            const auto key = reinterpret_cast<std::uintptr_t>(texture.bytes.data());
            if (auto it = extracted_.find(key); it != extracted_.end()) return it->second;
            const std::string name = unique_name(stem_ + "_" + token_safe(label) + extension_for(texture));
            write_bytes_atomically((out_dir_ / name).string(), texture.bytes);
            extracted_.emplace(key, name);
            return name;
        }
        const std::string resolved = mesh_.resolve_texture_path(texture);
        std::error_code ec;
        fs::path source = fs::absolute(resolved, ec);
        source = ec ? fs::path(resolved) : source.lexically_normal();
        if (auto it = copied_.find(source.string()); it != copied_.end()) return it->second;

        std::string result;
        const bool exists = fs::is_regular_file(source, ec);
        if (copy_ && exists) {
            if (source.parent_path() == out_dir_abs_) {
                result = source.filename().string();  // already beside the output
                taken_.insert(result);
            } else {
                result = unique_name(token_safe(source.filename().string()));
                std::ifstream in(source, std::ios::binary);
                if (!in) throw_error(Error::Kind::io, source.string(), "cannot read texture to copy it");
                std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
                if (in.bad()) throw_error(Error::Kind::io, source.string(), "read error while copying texture");
                write_bytes_atomically((out_dir_ / result).string(), bytes);
            }
        } else {
            // Not copied (by request, or the source is missing): point at the original so a reader
            // finds it, or reports exactly which file is missing.
            const fs::path relative = source.lexically_relative(out_dir_abs_);
            result = (!relative.empty() && source.is_absolute() == out_dir_abs_.is_absolute())
                         ? relative.generic_string()
                         : source.generic_string();
        }
        copied_.emplace(source.string(), result);
        return result;
    }

private:
    std::string unique_name(const std::string& wanted) {
        std::string name = wanted;
        const fs::path p(wanted);
        for (int i = 2; taken_.count(name) != 0; ++i)
            name = p.stem().string() + "_" + std::to_string(i) + p.extension().string();
        taken_.insert(name);
        return name;
    }

    const Mesh& mesh_;
    fs::path out_dir_;
    fs::path out_dir_abs_;
    std::string stem_;
    bool copy_;
    std::map<std::uintptr_t, std::string> extracted_;
    std::map<std::string, std::string> copied_;
    std::set<std::string> taken_;
};

std::vector<std::string> unique_material_names(const std::vector<Material>& materials) {
    std::vector<std::string> names;
    std::set<std::string> taken;
    for (std::size_t i = 0; i < materials.size(); ++i) {
        std::string base = token_safe(materials[i].name);
        if (base.empty()) base = "material_" + std::to_string(i);
        std::string name = base;
        for (int k = 2; taken.count(name) != 0; ++k) name = base + "_" + std::to_string(k);
        taken.insert(name);
        names.push_back(name);
    }
    return names;
}

void write_mtl(const Mesh& mesh, const std::string& mtl_path, const std::vector<std::string>& names,
               TextureExporter& textures) {
    std::string text = "# LodForge material library\n";
    for (std::size_t i = 0; i < mesh.materials.size(); ++i) {
        const Material& m = mesh.materials[i];
        auto line3 = [&](const char* key, float a, float b, float c) {
            text += key;
            for (float v : {a, b, c}) {
                text += ' ';
                append_float(text, v);
            }
            text += '\n';
        };
        auto line1 = [&](const char* key, float a) {
            text += key;
            text += ' ';
            append_float(text, a);
            text += '\n';
        };
        text += "\nnewmtl " + names[i] + "\n";
        line3("Kd", m.base_color.x, m.base_color.y, m.base_color.z);
        line1("d", m.base_color.w);
        if (m.emissive.x != 0 || m.emissive.y != 0 || m.emissive.z != 0)
            line3("Ke", m.emissive.x, m.emissive.y, m.emissive.z);
        line1("Pr", m.roughness);
        line1("Pm", m.metallic);
        const std::string prefix = names[i];
        if (std::string ref = textures.reference(m.base_color_texture, prefix + "_basecolor"); !ref.empty())
            text += "map_Kd " + ref + "\n";
        if (std::string ref = textures.reference(m.normal_texture, prefix + "_normal"); !ref.empty())
            text += "norm " + ref + "\n";
        if (std::string ref = textures.reference(m.emissive_texture, prefix + "_emissive"); !ref.empty())
            text += "map_Ke " + ref + "\n";
    }
    AtomicFile file(mtl_path, true);
    file.stream() << text;
    file.commit();
}

// Returns, per surface point, the vertex whose position/colour its `v` line carries; empty when the
// mesh's wedges cannot be expressed as shared points (then every vertex gets its own `v`).
std::vector<std::uint32_t> point_representatives(const Mesh& mesh) {
    if (mesh.position_ids.size() != mesh.positions.size()) return {};
    const std::size_t n = mesh.positions.size();
    std::size_t points = 0;
    for (std::uint32_t id : mesh.position_ids) points = std::max<std::size_t>(points, std::size_t{id} + 1);
    if (points > n) return {};
    constexpr std::uint32_t none = 0xFFFFFFFFu;
    std::vector<std::uint32_t> rep(points, none);
    for (std::size_t v = 0; v < n; ++v) {
        const std::uint32_t id = mesh.position_ids[v];
        if (rep[id] == none) {
            rep[id] = static_cast<std::uint32_t>(v);
            continue;
        }
        if (!(mesh.positions[rep[id]] == mesh.positions[v])) return {};
        if (mesh.has_colors() && !(mesh.colors[rep[id]] == mesh.colors[v])) return {};
    }
    if (std::find(rep.begin(), rep.end(), none) != rep.end()) return {};
    return rep;
}

}  // namespace

void write_obj(const Mesh& mesh, const std::string& path, const WriteOptions& options, Progress* progress) {
    check_progress(progress, 0.0, "Writing OBJ");
    const std::size_t n = mesh.vertex_count();
    for (const auto& set : mesh.texcoords)
        if (set.size() != n) throw_error(Error::Kind::invalid, path, "texcoord set size differs from vertex count");
    if ((mesh.has_normals() && mesh.normals.size() != n) || (mesh.has_colors() && mesh.colors.size() != n))
        throw_error(Error::Kind::invalid, path, "attribute array size differs from vertex count");
    if (!mesh.face_materials.empty() && mesh.face_materials.size() != mesh.triangle_count())
        throw_error(Error::Kind::invalid, path, "face_materials size differs from triangle count");
    for (std::uint32_t i : mesh.indices)
        if (i >= n) throw_error(Error::Kind::invalid, path, "triangle index " + std::to_string(i) + " out of range");

    const bool colors = options.write_colors && mesh.has_colors();
    const bool normals = options.write_normals && mesh.has_normals();
    const bool uvs = options.write_texcoords && mesh.has_texcoords();
    const bool materials = !mesh.materials.empty();
    const fs::path out(path);
    const std::string mtl_name = token_safe(out.stem().string()) + ".mtl";
    const std::vector<std::string> names = unique_material_names(mesh.materials);

    if (materials) {
        TextureExporter textures(mesh, out, options);
        write_mtl(mesh, (out.parent_path() / mtl_name).string(), names, textures);
    }

    const std::vector<std::uint32_t> rep = point_representatives(mesh);
    const bool shared_points = !rep.empty();

    AtomicFile file(path, true);
    std::ofstream& stream = file.stream();
    std::string text;
    text.reserve(1 << 20);
    auto flush = [&](bool force) {
        if (force || text.size() > (1u << 20) - 256) {
            stream.write(text.data(), static_cast<std::streamsize>(text.size()));
            text.clear();
        }
    };
    text += "# LodForge OBJ: ";
    append_uint(text, shared_points ? rep.size() : n);
    text += " points, ";
    append_uint(text, n);
    text += " wedges, ";
    append_uint(text, mesh.triangle_count());
    text += " triangles\n";
    if (materials) text += "mtllib " + mtl_name + "\n";

    auto write_v = [&](std::uint32_t v) {
        text += 'v';
        const Vec3f& p = mesh.positions[v];
        for (float c : {p.x, p.y, p.z}) {
            text += ' ';
            append_float(text, c);
        }
        if (colors) {
            const Vec4f& c = mesh.colors[v];
            for (float x : {c.x, c.y, c.z}) {
                text += ' ';
                append_float(text, x);
            }
        }
        text += '\n';
        flush(false);
    };
    if (shared_points)
        for (std::uint32_t v : rep) write_v(v);
    else
        for (std::size_t v = 0; v < n; ++v) write_v(static_cast<std::uint32_t>(v));
    check_progress(progress, 0.3, "Writing OBJ");
    if (uvs)
        for (const Vec2f& t : mesh.texcoords[0]) {
            text += "vt ";
            append_float(text, t.x);
            text += ' ';
            append_float(text, t.y);
            text += '\n';
            flush(false);
        }
    if (normals)
        for (const Vec3f& v : mesh.normals) {
            text += "vn";
            for (float c : {v.x, v.y, v.z}) {
                text += ' ';
                append_float(text, c);
            }
            text += '\n';
            flush(false);
        }
    check_progress(progress, 0.5, "Writing OBJ");

    const std::size_t triangles = mesh.triangle_count();
    std::size_t current_material = static_cast<std::size_t>(-1);
    for (std::size_t t = 0; t < triangles; ++t) {
        if (materials) {
            std::size_t m = mesh.face_materials.empty() ? 0 : mesh.face_materials[t];
            if (m >= mesh.materials.size())
                throw_error(Error::Kind::invalid, path,
                            "triangle " + std::to_string(t) + " uses material " + std::to_string(m) + " of " +
                                std::to_string(mesh.materials.size()));
            if (m != current_material) {
                text += "usemtl " + names[m] + "\n";
                current_material = m;
            }
        }
        text += 'f';
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.indices[3 * t + static_cast<std::size_t>(k)];
            text += ' ';
            append_uint(text, (shared_points ? std::uint64_t{mesh.position_ids[v]} : std::uint64_t{v}) + 1);
            if (uvs || normals) {
                text += '/';
                if (uvs) append_uint(text, std::uint64_t{v} + 1);
                if (normals) {
                    text += '/';
                    append_uint(text, std::uint64_t{v} + 1);
                }
            }
        }
        text += '\n';
        flush(false);
        if ((t & 0xFFFF) == 0xFFFF)
            check_progress(progress, 0.5 + 0.5 * static_cast<double>(t) / static_cast<double>(triangles), "Writing OBJ");
    }
    flush(true);
    file.commit();
    check_progress(progress, 1.0, "Writing OBJ");
}

}  // namespace lodforge
