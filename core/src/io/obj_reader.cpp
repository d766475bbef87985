// Wavefront OBJ (+ MTL) import through tinyobjloader.
//
// tinyobjloader parses the text (including relative indices and the `v x y z r g b` colour extension);
// this file turns its corner lists into the wedge mesh: stored `v` entries are the first vertices
// (position_ids = OBJ index), every further distinct (v, vt, vn) corner adds a wedge. Polygons are
// fan-triangulated here (tinyobjloader's own triangulation picks diagonals, which would change which
// triangles exist). Decisions are documented in docs/import-obj-gltf.md.
#include "lodforge/io/obj.h"

#include "lodforge/error.h"
#include "lodforge/io/input_file.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace lodforge {
namespace fs = std::filesystem;

namespace {

constexpr std::array<const char*, 5> kImageExtensions = {".png", ".jpg", ".jpeg", ".tga", ".bmp"};
constexpr std::array<const char*, 5> kTextureSuffixes = {"", "_texture", "_diffuse", "_albedo", "_basecolor"};

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool is_image_file(const fs::path& p) {
    const std::string ext = lower(p.extension().string());
    return std::find(kImageExtensions.begin(), kImageExtensions.end(), ext) != kImageExtensions.end();
}

// tinyobjloader separates messages with newlines; fold them into one line for an exception message.
std::string one_line(const std::string& text) {
    std::string out;
    bool pending_space = false;
    for (char c : text) {
        if (c == '\n' || c == '\r') {
            pending_space = !out.empty();
            continue;
        }
        if (pending_space) {
            out += "; ";
            pending_space = false;
        }
        out += c;
    }
    return out;
}

// MTL texture names may come from Windows tools with backslashes.
std::string normalise_texture_path(std::string path) {
    std::replace(path.begin(), path.end(), '\\', '/');
    return path;
}

// Material names may hold spaces (`newmtl my red`): tinyobjloader keeps the whole `newmtl` name but
// only the first word of a `usemtl`, so the material was lost. Both sides get this byte for their inner
// spaces while tinyobjloader runs, and the names get their spaces back afterwards.
constexpr char kNameSpace = '\x1f';

// `usemtl` lines with their name's inner spaces and tabs replaced by kNameSpace.
std::string protect_material_names(std::string text) {
    std::size_t line = 0;
    while (line < text.size()) {
        std::size_t end = text.find('\n', line);
        if (end == std::string::npos) end = text.size();
        std::size_t b = text.find_first_not_of(" \t", line);
        if (b < end && text.compare(b, 6, "usemtl") == 0 && b + 6 < end && (text[b + 6] == ' ' || text[b + 6] == '\t')) {
            std::size_t first = text.find_first_not_of(" \t", b + 6);
            std::size_t last = end;
            while (last > first && std::isspace(static_cast<unsigned char>(text[last - 1]))) --last;
            for (std::size_t i = first; i < last; ++i)
                if (text[i] == ' ' || text[i] == '\t') text[i] = kNameSpace;
        }
        line = end + 1;
    }
    return text;
}

std::string with_spaces(std::string name) {
    std::replace(name.begin(), name.end(), kNameSpace, ' ');
    return name;
}

// Resolves `mtllib` names against the OBJ's directory (tinyobjloader's own reader splits its search
// path at ':', which breaks on directories containing one) and remembers the ones that are missing.
class MtlReader : public tinyobj::MaterialReader {
public:
    explicit MtlReader(fs::path dir) : dir_(std::move(dir)) {}

    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* material_map, std::string* warn, std::string* err) override {
        const fs::path path = dir_ / fs::path(normalise_texture_path(name));
        std::ifstream in(path);
        if (!in) {
            missing.push_back(path.string());
            if (warn) *warn += "material library " + path.string() + " not found\n";
            return false;
        }
        const std::size_t before = materials->size();
        tinyobj::LoadMtl(material_map, materials, &in, warn, err);
        if (protect_names) {
            for (std::size_t i = before; i < materials->size(); ++i) {
                std::string& material = (*materials)[i].name;
                const std::string protected_name = protect_material_names("usemtl " + material).substr(7);
                if (protected_name == material) continue;
                material_map->erase(material);
                (*material_map)[protected_name] = static_cast<int>(i);
                material = protected_name;
            }
        }
        return true;
    }

    std::vector<std::string> missing;
    bool protect_names = false;  // the OBJ's usemtl names were protected (protect_material_names)

private:
    fs::path dir_;
};

// The documented discovery rule for OBJ files that have UVs but no material library: look beside the
// file for <stem>{,_texture,_diffuse,_albedo,_basecolor}.<image ext>, then the same with the stem cut
// at each '_' from the right, then the only image of the directory. Returns the file name or "".
std::string discover_texture(const fs::path& obj_path) {
    const fs::path dir = obj_path.parent_path().empty() ? fs::path(".") : obj_path.parent_path();
    std::vector<fs::path> images;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code type_ec;
        if (it->is_regular_file(type_ec) && is_image_file(it->path())) images.push_back(it->path().filename());
    }
    if (images.empty()) return {};
    std::sort(images.begin(), images.end());

    std::vector<std::string> stems;
    std::string stem = obj_path.stem().string();
    while (!stem.empty()) {
        stems.push_back(stem);
        const auto cut = stem.find_last_of('_');
        if (cut == std::string::npos || cut == 0) break;
        stem.resize(cut);
    }
    for (const std::string& s : stems)
        for (const char* suffix : kTextureSuffixes) {
            const std::string wanted = lower(s + suffix);
            for (const fs::path& image : images)
                if (lower(image.stem().string()) == wanted) return image.string();
        }
    return images.size() == 1 ? images.front().string() : std::string();
}

Material to_material(const tinyobj::material_t& m) {
    Material out;
    out.name = m.name;
    out.base_color = {m.diffuse[0], m.diffuse[1], m.diffuse[2], m.dissolve};
    out.emissive = {m.emission[0], m.emission[1], m.emission[2]};
    out.metallic = m.metallic;
    // tinyobjloader cannot tell an absent `Pr` from `Pr 0`; absent is far more common, so 0 keeps
    // the Material default (fully rough), which is what a plain Kd material looks like.
    if (m.roughness > 0) out.roughness = m.roughness;
    if (!m.diffuse_texname.empty()) out.base_color_texture.path = normalise_texture_path(m.diffuse_texname);
    if (!m.normal_texname.empty())
        out.normal_texture.path = normalise_texture_path(m.normal_texname);
    else if (!m.bump_texname.empty())
        out.normal_texture.path = normalise_texture_path(m.bump_texname);
    if (!m.emissive_texname.empty()) out.emissive_texture.path = normalise_texture_path(m.emissive_texname);
    return out;
}

// Key of one OBJ corner: position, texcoord and normal index (-1 = absent).
struct CornerKey {
    int v, vt, vn;
    bool operator==(const CornerKey&) const = default;
};
struct CornerKeyHash {
    std::size_t operator()(const CornerKey& k) const noexcept {
        std::uint64_t h = static_cast<std::uint32_t>(k.v);
        h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(k.vt);
        h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(k.vn);
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

// Rejects binary input early (tinyobjloader skips unknown lines, so garbage would otherwise "load"
// empty) and positions the stream after a UTF-8 byte order mark.
void check_text(const std::string& path, std::istream& in) {
    char buffer[4096];
    in.read(buffer, sizeof buffer);
    const auto n = static_cast<std::size_t>(in.gcount());
    for (std::size_t i = 0; i < n; ++i)
        if (buffer[i] == '\0')
            throw_error(Error::Kind::format, path,
                        "not a text OBJ file (binary data at byte " + std::to_string(i) + ")");
    in.clear();
    // A UTF-8 byte order mark would hide the first line (usually a `v`) from tinyobjloader.
    const bool bom = n >= 3 && static_cast<unsigned char>(buffer[0]) == 0xEF &&
                     static_cast<unsigned char>(buffer[1]) == 0xBB && static_cast<unsigned char>(buffer[2]) == 0xBF;
    in.seekg(bom ? 3 : 0);
}

// One pass over the text before tinyobjloader sees it, for what tinyobjloader gets silently wrong:
// a `\` at the end of a line continues it (tinyobjloader does not join lines), and `nan`/`inf` in a
// `v`/`vt`/`vn` line (tinyobjloader reads them as 0, which would move the vertex without a word), and
// face indices beyond the int range (tinyobjloader's atoi wraps them: `f 1 2 4294967299` became a
// triangle on vertex 3, accepted as valid).
struct TextScan {
    bool continuation = false;
    bool spaced_material = false;  // a `usemtl` name with a space (tinyobjloader keeps its first word)
    std::size_t non_finite_line = 0;  // 1-based; 0 = none
    std::string non_finite_token;
    std::size_t overflow_line = 0;  // 1-based; 0 = none
    std::string overflow_token;
};

// True when one `f` corner (`v`, `v/vt`, `v//vn`, `v/vt/vn`, signs allowed) has an index whose
// magnitude does not fit tinyobjloader's int.
bool index_overflows(std::string_view corner) {
    std::size_t start = 0;
    while (start <= corner.size()) {
        std::size_t end = corner.find('/', start);
        if (end == std::string_view::npos) end = corner.size();
        std::size_t i = start;
        if (i < end && (corner[i] == '-' || corner[i] == '+')) ++i;
        while (i < end && corner[i] == '0') ++i;  // leading zeros do not overflow
        std::size_t digits = 0;
        std::uint64_t value = 0;
        for (; i < end && std::isdigit(static_cast<unsigned char>(corner[i])); ++i, ++digits)
            if (digits < 11) value = value * 10 + static_cast<std::uint64_t>(corner[i] - '0');
        if (digits > 10 || value > 2147483647ull) return true;
        start = end + 1;
    }
    return false;
}

// The next space- or tab-separated word of `line` from `pos` (empty at the end); no copies, since
// this runs on every line of files with millions of faces.
std::string_view next_word(std::string_view line, std::size_t& pos) {
    const std::size_t b = line.find_first_not_of(" \t", pos);
    if (b == std::string_view::npos) {
        pos = line.size();
        return {};
    }
    std::size_t e = line.find_first_of(" \t", b);
    if (e == std::string_view::npos) e = line.size();
    pos = e;
    return line.substr(b, e - b);
}

TextScan scan_text(std::istream& in) {
    const auto start = in.tellg();
    TextScan scan;
    std::string text_line;
    for (std::size_t number = 1; std::getline(in, text_line); ++number) {
        std::string_view line = text_line;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (!line.empty() && line.back() == '\\') scan.continuation = true;
        std::size_t pos = 0;
        const std::string_view key = next_word(line, pos);
        if (key == "usemtl") {
            next_word(line, pos);
            scan.spaced_material = scan.spaced_material || !next_word(line, pos).empty();
        } else if (key == "f") {
            if (scan.overflow_line) continue;
            for (std::string_view w = next_word(line, pos); !w.empty(); w = next_word(line, pos))
                if (index_overflows(w)) {
                    scan.overflow_line = number;
                    scan.overflow_token = std::string(w);
                    break;
                }
        } else if (key == "v" || key == "vt" || key == "vn") {
            if (scan.non_finite_line) continue;
            for (std::string_view w = next_word(line, pos); !w.empty(); w = next_word(line, pos)) {
                const std::size_t first = (w[0] == '-' || w[0] == '+') && w.size() > 1 ? 1 : 0;
                const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(w[first])));
                if (c == 'n' || c == 'i') {
                    scan.non_finite_line = number;
                    scan.non_finite_token = std::string(w);
                    break;
                }
            }
        }
    }
    in.clear();
    in.seekg(start);
    return scan;
}

std::string join_continued_lines(std::string text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '\\') {
            std::size_t j = i + 1;
            if (j < text.size() && text[j] == '\r') ++j;
            if (j < text.size() && text[j] == '\n') {
                out += ' ';
                i = j;
                continue;
            }
        }
        out += text[i];
    }
    return out;
}


// NaN or infinite numbers make every later step meaningless (docs/decisions.md): refused at import.
void check_finite(const std::string& path, const std::vector<tinyobj::real_t>& values, std::size_t per_item,
                  const char* what) {
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
            throw_error(Error::Kind::invalid, path, std::string(what) + " " + std::to_string(i / per_item + 1) +
                                                        " is not finite (NaN or infinity)");
}

}  // namespace

Mesh read_obj(const std::string& path, Progress* progress) {
    check_progress(progress, 0.0, "Reading OBJ");
    check_input_file(path, "an OBJ file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_error(Error::Kind::io, path, std::string("cannot open: ") + std::strerror(errno));
    check_text(path, in);

    const fs::path obj_path(path);
    const fs::path dir = obj_path.parent_path().empty() ? fs::path(".") : obj_path.parent_path();

    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> obj_materials;
    std::string warn, err;
    MtlReader mtl_reader(dir);
    // tinyobjloader does not join `\` line continuations; files that use them are joined in memory.
    std::istringstream joined;
    std::istream* source = &in;
    const TextScan scan = scan_text(in);
    if (scan.non_finite_line)
        throw_error(Error::Kind::invalid, path, "line " + std::to_string(scan.non_finite_line) + ": '" +
                                                    scan.non_finite_token + "' is not a finite number");
    if (scan.overflow_line)
        throw_error(Error::Kind::invalid, path, "line " + std::to_string(scan.overflow_line) + ": face corner '" +
                                                    scan.overflow_token + "' has an index out of range");
    if (scan.continuation || scan.spaced_material) {
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (scan.continuation) text = join_continued_lines(std::move(text));
        if (scan.spaced_material) text = protect_material_names(std::move(text));
        joined.str(std::move(text));
        source = &joined;
        mtl_reader.protect_names = scan.spaced_material;
    }
    bool ok = false;
    try {
        ok = tinyobj::LoadObj(&attrib, &shapes, &obj_materials, &warn, &err, source, &mtl_reader,
                              /*triangulate=*/false, /*default_vcols_fallback=*/false);
    } catch (const std::exception& e) {  // allocation failure on absurd input
        throw_error(Error::Kind::format, path, std::string("cannot parse OBJ: ") + e.what());
    }
    if (in.bad()) throw_error(Error::Kind::io, path, "read error");
    if (!ok) throw_error(Error::Kind::format, path, "cannot parse OBJ: " + one_line(err));
    check_progress(progress, 0.5, "Reading OBJ");

    const std::size_t point_count = attrib.vertices.size() / 3;
    const std::size_t uv_count = attrib.texcoords.size() / 2;
    const std::size_t normal_count = attrib.normals.size() / 3;
    if (point_count == 0)
        throw_error(Error::Kind::format, path,
                    "no vertices ('v' lines) found; not an OBJ file" + (warn.empty() ? "" : " (" + one_line(warn) + ")"));
    if (point_count > 0xFFFFFFFEull) throw_error(Error::Kind::unsupported, path, "more than 4 billion vertices");
    check_finite(path, attrib.vertices, 3, "vertex ('v')");
    check_finite(path, attrib.texcoords, 2, "texture coordinate ('vt')");
    check_finite(path, attrib.normals, 3, "normal ('vn')");
    check_finite(path, attrib.colors, 3, "vertex colour ('v')");

    // Which attributes exist: any corner referencing a vt / vn. Colours only when every `v` has them.
    bool any_uv = false, any_normal = false;
    std::size_t corner_total = 0, face_total = 0;
    auto check_index = [&](std::size_t face, const char* what, int value, std::size_t count, bool optional) {
        if (value >= 0 && static_cast<std::size_t>(value) < count) return;
        if (optional && value == -1) return;  // absent vt / vn
        throw_error(Error::Kind::invalid, path,
                    "face " + std::to_string(face + 1) + " refers to " + what + " " +
                        (value >= 0 ? std::to_string(value + 1) : std::string("before the first")) +
                        " but the file has " + std::to_string(count) +
                        (warn.empty() ? "" : " (" + one_line(warn) + ")"));
    };
    for (const auto& shape : shapes) {
        const tinyobj::mesh_t& sm = shape.mesh;
        corner_total += sm.indices.size();
        std::size_t listed = 0;
        for (unsigned char n : sm.num_face_vertices) listed += n;
        if (listed != sm.indices.size())  // tinyobjloader stores corner counts in a byte
            throw_error(Error::Kind::unsupported, path, "a polygon has more than 255 corners");
        std::size_t corner = 0;
        for (std::size_t f = 0; f < sm.num_face_vertices.size(); ++f, ++face_total) {
            const std::size_t n = sm.num_face_vertices[f];
            for (std::size_t k = 0; k < n; ++k) {
                const tinyobj::index_t& idx = sm.indices[corner + k];
                check_index(face_total, "vertex", idx.vertex_index, point_count, false);
                check_index(face_total, "texcoord", idx.texcoord_index, uv_count, true);
                check_index(face_total, "normal", idx.normal_index, normal_count, true);
                any_uv = any_uv || idx.texcoord_index >= 0;
                any_normal = any_normal || idx.normal_index >= 0;
            }
            corner += n;
        }
    }
    const bool has_colors = attrib.colors.size() == attrib.vertices.size();

    Mesh mesh;
    std::error_code ec;
    mesh.source_dir = fs::absolute(dir, ec).lexically_normal().string();
    if (ec) mesh.source_dir = dir.string();
    mesh.positions.resize(point_count);
    for (std::size_t i = 0; i < point_count; ++i)
        mesh.positions[i] = {attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]};
    if (has_colors) {
        mesh.colors.resize(point_count);
        for (std::size_t i = 0; i < point_count; ++i)
            mesh.colors[i] = {attrib.colors[3 * i], attrib.colors[3 * i + 1], attrib.colors[3 * i + 2], 1.f};
    }
    if (any_normal) mesh.normals.assign(point_count, Vec3f{});
    // A point cloud (no faces) with one `vn` per `v`, as MeshLab and our writer store it: normal i
    // belongs to vertex i (faces are the only other way OBJ ties a normal to a vertex).
    if (face_total == 0 && normal_count == point_count) {
        mesh.normals.resize(point_count);
        for (std::size_t i = 0; i < point_count; ++i)
            mesh.normals[i] = {attrib.normals[3 * i], attrib.normals[3 * i + 1], attrib.normals[3 * i + 2]};
    }
    if (any_uv) mesh.texcoords.assign(1, std::vector<Vec2f>(point_count));
    mesh.position_ids.resize(point_count);
    for (std::size_t i = 0; i < point_count; ++i) mesh.position_ids[i] = static_cast<std::uint32_t>(i);

    // Materials: every MTL material in file order; faces without one (no usemtl, or a name the MTL
    // does not define) get an appended "default" material. No materials at all: none are created.
    for (const tinyobj::material_t& m : obj_materials) {
        mesh.materials.push_back(to_material(m));
        mesh.materials.back().name = with_spaces(mesh.materials.back().name);
    }
    bool any_unassigned = false;
    for (const auto& shape : shapes)
        for (int id : shape.mesh.material_ids)
            any_unassigned = any_unassigned || id < 0 || static_cast<std::size_t>(id) >= obj_materials.size();
    std::uint32_t default_material = 0;
    if (mesh.materials.empty() && any_uv) {
        if (std::string found = discover_texture(obj_path); !found.empty()) {
            Material m;
            m.name = "default";
            m.base_color_texture.path = found;
            mesh.materials.push_back(std::move(m));
        }
    }
    if (!mesh.materials.empty() && any_unassigned) {
        if (obj_materials.empty()) {
            default_material = 0;  // the discovered-texture material
        } else {
            Material m;
            m.name = "default";
            default_material = static_cast<std::uint32_t>(mesh.materials.size());
            mesh.materials.push_back(std::move(m));
        }
    }
    const bool per_face_materials = !mesh.materials.empty();

    // Corners → vertices. First use of a stored vertex takes its corner's vt/vn; a different
    // combination later becomes a wedge (deduplicated by the full corner key).
    std::vector<std::uint8_t> assigned(point_count, 0);
    std::vector<std::array<int, 2>> first_use(point_count, {-1, -1});
    std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> wedges;
    auto vertex_for = [&](const tinyobj::index_t& idx) -> std::uint32_t {
        const auto v = static_cast<std::size_t>(idx.vertex_index);
        auto set_attributes = [&](std::size_t target) {
            if (idx.texcoord_index >= 0) {
                const auto t = static_cast<std::size_t>(idx.texcoord_index);
                mesh.texcoords[0][target] = {attrib.texcoords[2 * t], attrib.texcoords[2 * t + 1]};
            }
            if (idx.normal_index >= 0) {
                const auto n = static_cast<std::size_t>(idx.normal_index);
                mesh.normals[target] = {attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2]};
            }
        };
        if (!assigned[v]) {
            assigned[v] = 1;
            first_use[v] = {idx.texcoord_index, idx.normal_index};
            set_attributes(v);
            return static_cast<std::uint32_t>(v);
        }
        if (first_use[v][0] == idx.texcoord_index && first_use[v][1] == idx.normal_index)
            return static_cast<std::uint32_t>(v);
        const CornerKey key{idx.vertex_index, idx.texcoord_index, idx.normal_index};
        if (auto it = wedges.find(key); it != wedges.end()) return it->second;
        const std::size_t w = mesh.positions.size();
        if (w >= 0xFFFFFFFFull) throw_error(Error::Kind::unsupported, path, "more than 4 billion wedges");
        mesh.positions.push_back(mesh.positions[v]);
        mesh.position_ids.push_back(static_cast<std::uint32_t>(v));
        if (has_colors) mesh.colors.push_back(mesh.colors[v]);
        if (any_normal) mesh.normals.push_back(Vec3f{});
        if (any_uv) mesh.texcoords[0].push_back(Vec2f{});
        set_attributes(w);
        wedges.emplace(key, static_cast<std::uint32_t>(w));
        return static_cast<std::uint32_t>(w);
    };

    mesh.indices.reserve(3 * (corner_total >= 2 * face_total ? corner_total - 2 * face_total : 0));
    std::size_t corners_done = 0;
    for (const auto& shape : shapes) {
        const tinyobj::mesh_t& sm = shape.mesh;
        std::size_t corner = 0;
        for (std::size_t f = 0; f < sm.num_face_vertices.size(); ++f) {
            const std::size_t n = sm.num_face_vertices[f];
            const std::uint32_t first = vertex_for(sm.indices[corner]);
            std::uint32_t previous = vertex_for(sm.indices[corner + 1]);
            std::uint32_t material = default_material;
            if (per_face_materials && f < sm.material_ids.size()) {
                const int id = sm.material_ids[f];
                if (id >= 0 && static_cast<std::size_t>(id) < obj_materials.size())
                    material = static_cast<std::uint32_t>(id);
            }
            for (std::size_t k = 2; k < n; ++k) {
                const std::uint32_t current = vertex_for(sm.indices[corner + k]);
                mesh.indices.insert(mesh.indices.end(), {first, previous, current});
                if (per_face_materials) mesh.face_materials.push_back(material);
                previous = current;
            }
            corner += n;
            corners_done += n;
            if ((f & 0xFFFF) == 0xFFFF)
                check_progress(progress, 0.5 + 0.5 * static_cast<double>(corners_done) /
                                                   static_cast<double>(std::max<std::size_t>(corner_total, 1)),
                               "Reading OBJ");
        }
    }
    add_warning_lines(mesh, with_spaces(warn));
    check_progress(progress, 1.0, "Reading OBJ");
    return mesh;
}

}  // namespace lodforge
