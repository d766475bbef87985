// The mesh model every algorithm of the core reads and writes.
//
// Struct of arrays. A *vertex* is a wedge in Hoppe's sense: one position plus one set of attributes.
// Where a surface point carries different attributes on different sides (UV seam, hard normal,
// material border) there are several vertices with the same position, and `position_ids` says they
// are the same point. Importers split wedges and record the identity; they never weld or drop
// attributes. Simplifiers use `position_ids` to keep seams intact (a seam may only move along
// itself, both sides move together).
#pragma once

#include "lodforge/skeleton.h"
#include "lodforge/types.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lodforge {

// An image a material refers to: either a file (path absolute, or relative to Mesh::source_dir)
// or bytes embedded in the source (glTF data URIs, GLB buffer views).
struct TextureRef {
    std::string path;                 // as written in the source file, may be empty when embedded
    std::vector<std::uint8_t> bytes;  // encoded image (PNG/JPEG) when embedded
    std::string mime_type;            // "image/png", "image/jpeg", or empty when unknown
    int texcoord_set = 0;             // which Mesh::texcoords set samples it

    bool empty() const { return path.empty() && bytes.empty(); }
};

struct Material {
    std::string name;
    Vec4f base_color{1, 1, 1, 1};  // linear RGBA factor (glTF baseColorFactor, MTL Kd + d)
    float metallic = 0.f;
    float roughness = 1.f;
    TextureRef base_color_texture;  // glTF baseColorTexture, MTL map_Kd, PLY `comment TextureFile`
    TextureRef normal_texture;      // glTF normalTexture, MTL bump/norm
    TextureRef metallic_roughness_texture;
    TextureRef occlusion_texture;
    TextureRef emissive_texture;
    Vec3f emissive{0, 0, 0};
    bool double_sided = false;
};

// Four joint indices of one JOINTS_n set: indices into Skeleton::joints.
using Joints4 = std::array<std::uint16_t, 4>;

struct Mesh {
    // Per vertex (wedge). `positions` defines the vertex count; every other per-vertex array is either
    // empty (attribute absent) or exactly that long.
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;
    std::vector<Vec4f> colors;                    // RGBA in [0, 1]
    std::vector<std::vector<Vec2f>> texcoords;    // texcoords[set][vertex]; each set full length
    // Skinning influences (glTF JOINTS_n / WEIGHTS_n): joints[set][vertex] with weights[set][vertex], the
    // same number of sets, each full length; empty when the mesh is not skinned. Positions and normals
    // are then in the bind pose. Influences are vertex data like a UV: a kept vertex keeps them
    // unchanged, they are never averaged (joint indices are labels), and vertices with different
    // influences are different vertices.
    std::vector<std::vector<Joints4>> joints;
    std::vector<std::vector<Vec4f>> weights;
    // Identity of the surface point each vertex sits on: vertices with equal ids are wedges of one point.
    // Ids are dense, 0 .. point_count()-1, and point i is the i-th vertex as stored in the source file
    // (so a stored vertex that no face uses still counts). Empty means every vertex is its own point.
    std::vector<std::uint32_t> position_ids;

    // Per triangle: three vertex indices, counter-clockwise seen from outside.
    std::vector<std::uint32_t> indices;
    std::vector<std::uint32_t> face_materials;    // empty, or one index into `materials` per triangle

    std::vector<Material> materials;
    // The skeleton and animations `joints` refer to; null when the mesh is not skinned. Levels built
    // from a mesh share its skeleton.
    std::shared_ptr<const Skeleton> skeleton;
    std::string source_dir;  // directory relative texture paths are resolved against
    // Notes from the importer a user should see but that did not stop the import (missing material
    // library, skipped line primitives, ...). Shown by `lodforge info` and the studio.
    std::vector<std::string> warnings;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t triangle_count() const { return indices.size() / 3; }
    // Number of distinct surface points (stored vertices of the source file).
    std::size_t point_count() const;

    bool has_normals() const { return !normals.empty(); }
    bool has_colors() const { return !colors.empty(); }
    bool has_texcoords() const { return !texcoords.empty(); }
    bool has_skin() const { return !joints.empty() && skeleton != nullptr; }

    Bounds bounds() const;
    // Resolve a texture's path against source_dir; empty when the texture is embedded or absent.
    std::string resolve_texture_path(const TextureRef& texture) const;
};

// Appends each non-empty line of `text` (a loader's warning text) to mesh.warnings.
void add_warning_lines(Mesh& mesh, const std::string& text);

// Adds a vertex copying every present attribute of `from` (used by importers splitting wedges):
// the new vertex has the same position_id. Returns its index.
std::uint32_t duplicate_vertex(Mesh& mesh, std::uint32_t from);

// The vertex order the Mesh contract asks for, for algorithms that build a new mesh from a subset of
// items (vertices, clusters) grouped into surface points: the first used item of each group, in item
// order, then the remaining used items (extra wedges). `point_of_group` gives each group its new dense
// point id, or UINT32_MAX where no used item belongs to it.
struct PointsFirstLayout {
    std::vector<std::uint32_t> order;           // output vertex i = item order[i]
    std::vector<std::uint32_t> point_of_group;  // group -> new point id
};
PointsFirstLayout points_first_layout(const std::vector<std::uint8_t>& used,
                                      const std::vector<std::uint32_t>& group_of, std::size_t group_count);

// Makes `to` carry the per-vertex attributes `from` has (normals, colors, texcoord sets, joints and
// weights), each `count` long and default-filled, for builders that then copy kept vertices with
// copy_vertex_attributes. Positions and position_ids are the caller's. Also shares the skeleton.
void allocate_vertex_attributes(Mesh& to, const Mesh& from, std::size_t count);
// Copies every per-vertex attribute (not position, not position_id) of vertex `src` of `from` to
// vertex `dst` of `to`, which allocate_vertex_attributes shaped.
void copy_vertex_attributes(Mesh& to, std::size_t dst, const Mesh& from, std::size_t src);
// True when vertices a and b of `mesh` have the same joints and weights in every set (true when the
// mesh is not skinned): welding must not merge vertices that follow different joints.
bool same_influences(const Mesh& mesh, std::size_t a, std::size_t b);

// Fills position_ids (when empty) with the identity, so code can index it unconditionally.
void ensure_position_ids(Mesh& mesh);

}  // namespace lodforge
