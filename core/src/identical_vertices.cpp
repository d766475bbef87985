// Joining identical vertices (what glTF tools call "indexing" a non-indexed primitive, assimp's
// JoinIdenticalVertices): an open-addressing hash over the bits of every attribute.
#include "lodforge/identical_vertices.h"

#include <bit>
#include <cstring>

namespace lodforge {

namespace {

std::uint32_t bits_of(float f) { return f == 0.f ? 0u : std::bit_cast<std::uint32_t>(f); }  // -0 as +0

struct Key {
    const Mesh& m;
    void append(std::vector<std::uint32_t>& out, std::uint32_t v) const {
        out.clear();
        const Vec3f& p = m.positions[v];
        out.insert(out.end(), {bits_of(p.x), bits_of(p.y), bits_of(p.z)});
        if (m.has_normals()) {
            const Vec3f& n = m.normals[v];
            out.insert(out.end(), {bits_of(n.x), bits_of(n.y), bits_of(n.z)});
        }
        if (m.has_colors()) {
            const Vec4f& c = m.colors[v];
            out.insert(out.end(), {bits_of(c.x), bits_of(c.y), bits_of(c.z), bits_of(c.w)});
        }
        for (const auto& set : m.texcoords) out.insert(out.end(), {bits_of(set[v].x), bits_of(set[v].y)});
    }
};

std::uint64_t hash_words(const std::vector<std::uint32_t>& w) {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (std::uint32_t x : w) h = (h ^ x) * 0xFF51AFD7ED558CCDull, h ^= h >> 29;
    return h;
}

}  // namespace

IdenticalVertices find_identical_vertices(const Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    IdenticalVertices r;
    r.merged_of.resize(n);
    std::size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    std::vector<std::uint32_t> slot(cap, UINT32_MAX);  // merged vertex in the slot
    const Key key{mesh};
    std::vector<std::uint32_t> a, b;
    for (std::uint32_t v = 0; v < n; ++v) {
        key.append(a, v);
        std::size_t s = hash_words(a) & (cap - 1);
        for (;; s = (s + 1) & (cap - 1)) {
            if (slot[s] == UINT32_MAX) {
                slot[s] = static_cast<std::uint32_t>(r.first_of.size());
                r.merged_of[v] = slot[s];
                r.first_of.push_back(v);
                break;
            }
            key.append(b, r.first_of[slot[s]]);
            if (a == b) {
                r.merged_of[v] = slot[s];
                ++r.duplicates;
                break;
            }
        }
    }
    return r;
}

Mesh IdenticalVertices::merged(const Mesh& mesh) const {
    Mesh m;
    m.materials = mesh.materials;
    m.source_dir = mesh.source_dir;
    m.warnings = mesh.warnings;
    m.face_materials = mesh.face_materials;
    const std::size_t k = first_of.size();
    m.positions.resize(k);
    if (mesh.has_normals()) m.normals.resize(k);
    if (mesh.has_colors()) m.colors.resize(k);
    m.texcoords.assign(mesh.texcoords.size(), std::vector<Vec2f>(k));
    for (std::size_t i = 0; i < k; ++i) {
        const std::uint32_t v = first_of[i];
        m.positions[i] = mesh.positions[v];
        if (mesh.has_normals()) m.normals[i] = mesh.normals[v];
        if (mesh.has_colors()) m.colors[i] = mesh.colors[v];
        for (std::size_t s = 0; s < mesh.texcoords.size(); ++s) m.texcoords[s][i] = mesh.texcoords[s][v];
    }
    m.indices.resize(mesh.indices.size());
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) m.indices[i] = merged_of[mesh.indices[i]];
    return m;
}

}  // namespace lodforge
