#include "lodforge/io/mesh_info.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <set>
#include <sstream>

namespace lodforge {

MeshInfo mesh_info(const Mesh& mesh, const std::string& path, const std::string& format) {
    MeshInfo info;
    info.path = path;
    info.format = format;
    info.vertices = mesh.point_count();
    info.wedges = mesh.vertex_count();
    info.triangles = mesh.triangle_count();
    info.attributes.push_back("position");
    if (mesh.has_normals()) info.attributes.push_back("normal");
    if (mesh.has_colors()) info.attributes.push_back("color");
    for (std::size_t s = 0; s < mesh.texcoords.size(); ++s) info.attributes.push_back("texcoord" + std::to_string(s));
    for (std::size_t s = 0; s < mesh.joints.size(); ++s) {
        info.attributes.push_back("joints" + std::to_string(s));
        info.attributes.push_back("weights" + std::to_string(s));
    }
    if (!mesh.face_materials.empty()) info.attributes.push_back("material");
    if (mesh.has_skin()) {
        info.joints = mesh.skeleton->joints.size();
        info.max_influences = max_influence_count(mesh);
        for (const Animation& a : mesh.skeleton->animations) {
            std::ostringstream s;
            s << (a.name.empty() ? "(unnamed)" : a.name) << " (" << a.duration() << " s, " << a.channels.size()
              << " channels)";
            info.animations.push_back(s.str());
        }
    }
    info.materials = mesh.materials.size();

    std::set<std::string> seen;
    for (const Material& m : mesh.materials) {
        for (const TextureRef* t : {&m.base_color_texture, &m.normal_texture, &m.metallic_roughness_texture,
                                    &m.occlusion_texture, &m.emissive_texture}) {
            if (t->empty()) continue;
            if (!t->bytes.empty()) {
                const std::string label = "<embedded " + (t->mime_type.empty() ? std::string("image") : t->mime_type) +
                                          ", " + std::to_string(t->bytes.size()) + " bytes>";
                info.textures.push_back(label);
                continue;
            }
            const std::string resolved = mesh.resolve_texture_path(*t);
            if (!seen.insert(resolved).second) continue;
            info.textures.push_back(resolved);
            std::error_code ec;
            if (!std::filesystem::is_regular_file(resolved, ec)) info.missing_textures.push_back(resolved);
        }
    }
    info.warnings = mesh.warnings;
    info.bounds = mesh.bounds();
    info.validation = validate(mesh);
    return info;
}

std::string to_json(const MeshInfo& info, int indent) {
    using nlohmann::json;
    auto vec = [](Vec3f v) { return json::array({v.x, v.y, v.z}); };
    json j;
    j["file"] = info.path;
    j["format"] = info.format;
    j["vertices"] = info.vertices;
    j["wedges"] = info.wedges;
    j["triangles"] = info.triangles;
    j["attributes"] = info.attributes;
    j["materials"] = info.materials;
    if (info.joints > 0)
        j["skin"] = {{"joints", info.joints}, {"max_influences", info.max_influences}, {"animations", info.animations}};
    j["textures"] = info.textures;
    j["missing_textures"] = info.missing_textures;
    j["warnings"] = info.warnings;
    if (info.bounds.empty()) {
        j["bounds"] = nullptr;
    } else {
        j["bounds"] = {{"min", vec(info.bounds.min)},
                       {"max", vec(info.bounds.max)},
                       {"size", vec(info.bounds.size())},
                       {"diagonal", info.bounds.diagonal()}};
    }
    json findings = json::array();
    for (const auto& f : info.validation.findings) {
        findings.push_back({{"code", f.code},
                            {"severity", f.severity == ValidationFinding::Severity::error ? "error" : "warning"},
                            {"count", f.count},
                            {"examples", f.examples},
                            {"message", f.message}});
    }
    j["validation"] = findings;
    return j.dump(indent);
}

std::string to_text(const MeshInfo& info) {
    std::ostringstream s;
    if (!info.path.empty()) s << "file:        " << info.path << '\n';
    if (!info.format.empty()) s << "format:      " << info.format << '\n';
    s << "vertices:    " << info.vertices;
    if (info.wedges != info.vertices) s << " (" << info.wedges << " with attribute seams split)";
    s << "\ntriangles:   " << info.triangles << '\n';
    s << "attributes:  ";
    for (std::size_t i = 0; i < info.attributes.size(); ++i) s << (i ? ", " : "") << info.attributes[i];
    s << "\nmaterials:   " << info.materials << '\n';
    if (info.joints > 0)
        s << "skin:        " << info.joints << " joints, up to " << info.max_influences << " influences per vertex\n";
    for (const auto& a : info.animations) s << "animation:   " << a << '\n';
    for (const auto& t : info.textures) s << "texture:     " << t << '\n';
    for (const auto& t : info.missing_textures) s << "MISSING:     " << t << '\n';
    for (const auto& w : info.warnings) s << "note:        " << w << '\n';
    if (info.bounds.empty()) {
        s << "bounds:      empty\n";
    } else {
        const Vec3f a = info.bounds.min, b = info.bounds.max;
        s << "bounds:      [" << a.x << ", " << a.y << ", " << a.z << "] .. [" << b.x << ", " << b.y << ", " << b.z
          << "], diagonal " << info.bounds.diagonal() << '\n';
    }
    if (info.validation.findings.empty()) s << "validation:  no problems found\n";
    for (const auto& f : info.validation.findings)
        s << (f.severity == ValidationFinding::Severity::error ? "error:       " : "warning:     ") << f.message << '\n';
    return s.str();
}

}  // namespace lodforge
