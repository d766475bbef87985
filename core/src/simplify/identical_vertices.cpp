// Joining identical vertices (what glTF tools call "indexing" a non-indexed primitive, assimp's
// JoinIdenticalVertices) with meshoptimizer's multi-stream remap: binary equality of every stream.
#include "lodforge/simplify/identical_vertices.h"

#include <meshoptimizer.h>

namespace lodforge {

// Binary equality reads padding too: the vector types have none.
static_assert(sizeof(Vec3f) == 12 && sizeof(Vec4f) == 16 && sizeof(Vec2f) == 8 && sizeof(Joints4) == 8);

IdenticalVertices find_identical_vertices(const Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    std::vector<meshopt_Stream> streams{{mesh.positions.data(), sizeof(Vec3f), sizeof(Vec3f)}};
    if (mesh.has_normals()) streams.push_back({mesh.normals.data(), sizeof(Vec3f), sizeof(Vec3f)});
    if (mesh.has_colors()) streams.push_back({mesh.colors.data(), sizeof(Vec4f), sizeof(Vec4f)});
    for (const auto& set : mesh.texcoords) streams.push_back({set.data(), sizeof(Vec2f), sizeof(Vec2f)});
    // Vertices that follow different joints are different vertices, however alike they look.
    for (const auto& set : mesh.joints) streams.push_back({set.data(), sizeof(Joints4), sizeof(Joints4)});
    for (const auto& set : mesh.weights) streams.push_back({set.data(), sizeof(Vec4f), sizeof(Vec4f)});
    IdenticalVertices r;
    r.merged_of.resize(n);
    if (n == 0) return r;
    // The identity as index buffer: every stored vertex counts (unused ones too) and is numbered in vertex
    // order, so a merged vertex's number follows its first input vertex. meshopt wants whole triangles:
    // the last vertex repeats to fill the final one.
    std::vector<std::uint32_t> order((n + 2) / 3 * 3, static_cast<std::uint32_t>(n - 1));
    for (std::uint32_t v = 0; v < n; ++v) order[v] = v;
    const std::size_t unique = meshopt_generateVertexRemapMulti(r.merged_of.data(), order.data(), order.size(), n,
                                                                streams.data(), streams.size());
    r.first_of.assign(unique, UINT32_MAX);
    for (std::uint32_t v = 0; v < n; ++v)
        if (r.first_of[r.merged_of[v]] == UINT32_MAX) r.first_of[r.merged_of[v]] = v;
    r.duplicates = n - unique;
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
    allocate_vertex_attributes(m, mesh, k);
    for (std::size_t i = 0; i < k; ++i) {
        const std::uint32_t v = first_of[i];
        m.positions[i] = mesh.positions[v];
        copy_vertex_attributes(m, i, mesh, v);
    }
    m.indices.resize(mesh.indices.size());
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) m.indices[i] = merged_of[mesh.indices[i]];
    return m;
}

}  // namespace lodforge
