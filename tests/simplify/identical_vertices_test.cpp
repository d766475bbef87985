// Triangle soups (every face with its own copies of its vertices, as non-indexed glTF primitives and
// per-face OBJ/PLY exports store them) simplify like the indexed mesh they came from.
#include "lodforge/simplify/identical_vertices.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/simplify/simplify.h"

#include "simplify/simplify_test_util.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

using namespace lodforge;
using lodforge::test::count_edges;

namespace {

// The mesh with one vertex per face corner (attributes copied), position_ids empty.
Mesh as_soup(const Mesh& in) {
    Mesh s;
    s.materials = in.materials;
    s.face_materials = in.face_materials;
    s.source_dir = in.source_dir;
    s.texcoords.resize(in.texcoords.size());
    for (std::uint32_t v : in.indices) {
        s.indices.push_back(static_cast<std::uint32_t>(s.positions.size()));
        s.positions.push_back(in.positions[v]);
        if (in.has_normals()) s.normals.push_back(in.normals[v]);
        if (in.has_colors()) s.colors.push_back(in.colors[v]);
        for (std::size_t t = 0; t < in.texcoords.size(); ++t) s.texcoords[t].push_back(in.texcoords[t][v]);
    }
    return s;
}

SimplifyParams ratio(float r) {
    SimplifyParams p;
    p.target_ratio = r;
    return p;
}

bool same_vertex(const Mesh& a, std::uint32_t va, const Mesh& b, std::uint32_t vb) {
    if (!(a.positions[va] == b.positions[vb])) return false;
    if (a.has_normals() && !(a.normals[va] == b.normals[vb])) return false;
    for (std::size_t t = 0; t < a.texcoords.size(); ++t)
        if (!(a.texcoords[t][va] == b.texcoords[t][vb])) return false;
    return true;
}

}  // namespace

TEST(IdenticalVertices, FindsEveryCopyAndKeepsDistinctAttributesApart) {
    const Mesh in = read_mesh(test::shared_data("tex-duck/glTF/Duck.gltf"));
    const Mesh soup = as_soup(in);
    const IdenticalVertices iv = find_identical_vertices(soup);
    // Each corner copy goes back to one vertex; the Duck's used vertices are all distinct wedges.
    EXPECT_EQ(iv.first_of.size() + iv.duplicates, soup.vertex_count());
    EXPECT_LE(iv.first_of.size(), in.vertex_count());
    EXPECT_GT(iv.duplicates * 2, soup.vertex_count());
    const Mesh merged = iv.merged(soup);
    ASSERT_EQ(merged.indices.size(), soup.indices.size());
    for (std::size_t i = 0; i < soup.indices.size(); ++i)
        ASSERT_TRUE(same_vertex(soup, soup.indices[i], merged, merged.indices[i])) << i;
    // A vertex differing in one UV bit is its own vertex.
    Mesh changed = soup;
    changed.texcoords[0][7].x = std::nextafter(changed.texcoords[0][7].x, 2.f);
    const IdenticalVertices iv2 = find_identical_vertices(changed);
    EXPECT_NE(iv2.merged_of[7], iv.merged_of[7] == iv2.merged_of[7] ? UINT32_MAX : iv2.merged_of[7] + 1);
    for (std::uint32_t v = 0; v < changed.vertex_count(); ++v)
        if (v != 7 && iv2.merged_of[v] == iv2.merged_of[7]) ADD_FAILURE() << "vertex " << v << " joined 7";
    // Unused vertices count too, and a merged vertex is numbered after its first input vertex.
    Mesh loose;
    loose.positions = {{1.f, 0.f, 0.f}, {0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 0.f, 0.f}};  // not 3k
    const IdenticalVertices li = find_identical_vertices(loose);
    EXPECT_EQ(li.duplicates, 2u);
    EXPECT_EQ(li.merged_of, (std::vector<std::uint32_t>{0, 1, 0, 1}));
    EXPECT_EQ(li.first_of, (std::vector<std::uint32_t>{0, 1}));
}

TEST(IdenticalVertices, SoupsSimplifyLikeTheIndexedMesh) {
    for (const char* file : {"tex-duck/glTF/Duck.gltf", "scan-bunny/bun_zipper.ply"}) {
        SCOPED_TRACE(file);
        const Mesh in = read_mesh(test::shared_data(file));
        const Mesh soup = as_soup(in);
        const SimplifyResult indexed = simplify(in, ratio(0.1f));
        const SimplifyResult s = simplify(soup, ratio(0.1f));
        EXPECT_EQ(s.reason, SimplifyResult::StopReason::target_reached);
        EXPECT_NEAR(double(s.triangles), 0.1 * double(soup.triangle_count()), 0.01 * 0.1 * soup.triangle_count() + 1);
        // Seams stay closed: no more border edges than the indexed mesh's result.
        EXPECT_LE(count_edges(s.mesh).border, count_edges(indexed.mesh).border);
        // The result speaks the soup's numbering: replaying every collapse gives the output's faces,
        // each corner on the vertex vertex_map names or on an identical copy of it (a face never touched
        // keeps its own copies).
        ASSERT_EQ(s.input_points.size(), soup.vertex_count());
        const std::vector<std::uint32_t> all = replay_collapses(soup, s, s.collapses.size());
        ASSERT_EQ(all.size(), s.mesh.indices.size());
        for (std::size_t i = 0; i < all.size(); ++i) {
            ASSERT_LT(s.vertex_map[s.mesh.indices[i]], soup.vertex_count());
            ASSERT_TRUE(same_vertex(soup, all[i], soup, s.vertex_map[s.mesh.indices[i]])) << i;
            ASSERT_TRUE(soup.positions[all[i]] == s.mesh.positions[s.mesh.indices[i]]) << i;
            ASSERT_EQ(s.input_points[all[i]], s.input_points[s.vertex_map[s.mesh.indices[i]]]) << i;
        }
        // Prefixes shrink monotonically.
        std::size_t previous = soup.triangle_count();
        for (std::size_t k : {std::size_t{0}, s.collapses.size() / 2, s.collapses.size()}) {
            const std::size_t t = replay_collapses(soup, s, k).size() / 3;
            EXPECT_LE(t, previous);
            previous = t;
        }
    }
}
