#include "lodforge/mesh.h"

#include <algorithm>
#include <filesystem>
#include <numeric>

namespace lodforge {

std::size_t Mesh::point_count() const {
    if (position_ids.empty()) return positions.size();
    // Ids are dense by contract, so the largest id names the count without building a set.
    return static_cast<std::size_t>(*std::max_element(position_ids.begin(), position_ids.end())) + 1;
}

Bounds Mesh::bounds() const {
    Bounds b;
    for (const Vec3f& p : positions) b.add(p);
    return b;
}

std::string Mesh::resolve_texture_path(const TextureRef& texture) const {
    if (texture.path.empty() || !texture.bytes.empty()) return {};
    std::filesystem::path p(texture.path);
    if (p.is_absolute() || source_dir.empty()) return p.string();
    return (std::filesystem::path(source_dir) / p).lexically_normal().string();
}

void add_warning_lines(Mesh& mesh, const std::string& text) {
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (!line.empty()) mesh.warnings.push_back(std::move(line));
        start = end + 1;
    }
}

std::uint32_t duplicate_vertex(Mesh& mesh, std::uint32_t from) {
    ensure_position_ids(mesh);
    const auto index = static_cast<std::uint32_t>(mesh.positions.size());
    // Copy through a value first: push_back of an element of the same vector may reallocate under it.
    const Vec3f p = mesh.positions[from];
    mesh.positions.push_back(p);
    if (!mesh.normals.empty()) { const Vec3f n = mesh.normals[from]; mesh.normals.push_back(n); }
    if (!mesh.colors.empty()) { const Vec4f c = mesh.colors[from]; mesh.colors.push_back(c); }
    for (auto& set : mesh.texcoords) { const Vec2f t = set[from]; set.push_back(t); }
    for (auto& set : mesh.joints) { const Joints4 j = set[from]; set.push_back(j); }
    for (auto& set : mesh.weights) { const Vec4f w = set[from]; set.push_back(w); }
    const std::uint32_t id = mesh.position_ids[from];
    mesh.position_ids.push_back(id);
    return index;
}

PointsFirstLayout points_first_layout(const std::vector<std::uint8_t>& used,
                                      const std::vector<std::uint32_t>& group_of, std::size_t group_count) {
    constexpr std::uint32_t none = UINT32_MAX;
    PointsFirstLayout layout;
    layout.point_of_group.assign(group_count, none);
    std::vector<std::uint32_t> extras;
    std::uint32_t points = 0;
    for (std::uint32_t item = 0; item < used.size(); ++item) {
        if (!used[item]) continue;
        std::uint32_t& point = layout.point_of_group[group_of[item]];
        if (point == none) {
            point = points++;
            layout.order.push_back(item);
        } else {
            extras.push_back(item);
        }
    }
    layout.order.insert(layout.order.end(), extras.begin(), extras.end());
    return layout;
}

void allocate_vertex_attributes(Mesh& to, const Mesh& from, std::size_t count) {
    if (from.has_normals()) to.normals.assign(count, Vec3f{});
    if (from.has_colors()) to.colors.assign(count, Vec4f{});
    to.texcoords.assign(from.texcoords.size(), std::vector<Vec2f>(count));
    to.joints.assign(from.joints.size(), std::vector<Joints4>(count));
    to.weights.assign(from.weights.size(), std::vector<Vec4f>(count));
    to.skeleton = from.skeleton;
}

void copy_vertex_attributes(Mesh& to, std::size_t dst, const Mesh& from, std::size_t src) {
    if (from.has_normals()) to.normals[dst] = from.normals[src];
    if (from.has_colors()) to.colors[dst] = from.colors[src];
    for (std::size_t s = 0; s < from.texcoords.size(); ++s) to.texcoords[s][dst] = from.texcoords[s][src];
    for (std::size_t s = 0; s < from.joints.size(); ++s) to.joints[s][dst] = from.joints[s][src];
    for (std::size_t s = 0; s < from.weights.size(); ++s) to.weights[s][dst] = from.weights[s][src];
}

bool same_influences(const Mesh& mesh, std::size_t a, std::size_t b) {
    for (const auto& set : mesh.joints)
        if (set[a] != set[b]) return false;
    for (const auto& set : mesh.weights)
        if (!(set[a] == set[b])) return false;
    return true;
}

void ensure_position_ids(Mesh& mesh) {
    if (mesh.position_ids.size() == mesh.positions.size()) return;
    mesh.position_ids.resize(mesh.positions.size());
    std::iota(mesh.position_ids.begin(), mesh.position_ids.end(), 0u);
}

}  // namespace lodforge
