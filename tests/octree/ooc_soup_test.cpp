#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/octree/ooc_soup.h"
#include "lodforge/io/ply.h"
#include "lodforge/progress.h"

#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

namespace lodforge {
namespace {

namespace fs = std::filesystem;
using test::ScratchDir;
using test::shared_data;

// Every soup triangle must carry exactly the records of the PLY's triangle at the same position.
void expect_soup_matches(const std::string& ply, const SoupResult& r) {
    const Mesh m = read_ply(ply);
    ASSERT_EQ(r.triangles, m.triangle_count());
    SoupReader reader(r.path);
    EXPECT_EQ(reader.triangles(), m.triangle_count());
    EXPECT_EQ(reader.layout(), r.layout);
    const VertexLayout& L = r.layout;
    EXPECT_EQ(L.normals, m.has_normals());
    EXPECT_EQ(L.colors, m.has_colors());
    const std::size_t cb = soup_corner_bytes(L);
    std::vector<std::byte> buf;
    std::size_t t = 0, mismatches = 0;
    while (std::size_t n = reader.read(10000, buf)) {
        for (std::size_t i = 0; i < n; ++i, ++t)
            for (int k = 0; k < 3; ++k) {
                const std::byte* c = buf.data() + (i * 3 + static_cast<std::size_t>(k)) * cb;
                std::uint32_t id;
                float f[12];
                std::memcpy(&id, c, 4);
                std::memcpy(f, c + 4, 4 * L.floats());
                const std::uint32_t v = m.indices[3 * t + static_cast<std::size_t>(k)];
                const Vec3f p = m.positions[v];
                bool ok = id == v && f[0] == p.x && f[1] == p.y && f[2] == p.z;
                if (L.normals) ok = ok && f[L.normal_offset()] == m.normals[v].x && f[L.normal_offset() + 2] == m.normals[v].z;
                if (L.colors) ok = ok && f[L.color_offset()] == m.colors[v].x && f[L.color_offset() + 3] == m.colors[v].w;
                if (!ok) ++mismatches;
            }
    }
    EXPECT_EQ(t, m.triangle_count());
    EXPECT_EQ(mismatches, 0u);
    const Bounds b = m.bounds();
    EXPECT_EQ(reader.bounds().min, b.min);
    EXPECT_EQ(reader.bounds().max, b.max);
}

TEST(OocSoup, InCoreAsciiMatchesTheMesh) {
    ScratchDir dir("soup-ascii");
    const std::string ply = shared_data("scan-dragon/dragon_vrip_res3.ply");
    SoupParams p;
    p.memory_bytes = 16u << 20;
    const SoupResult r = convert_to_soup(ply, dir.file("soup"), p);
    EXPECT_FALSE(r.external);
    EXPECT_EQ(r.passes, 1);
    expect_soup_matches(ply, r);
}

TEST(OocSoup, ExternalSortOfAColouredBinaryScanMatchesTheMesh) {
    // 64K vertices × 40 bytes do not fit in half of 4 MB: the three-pass distribution sort runs.
    ScratchDir dir("soup-external");
    const std::string ply = shared_data("color-open3d-frag115/frag_115.ply");
    SoupParams p;
    p.memory_bytes = 4u << 20;
    const SoupResult r = convert_to_soup(ply, dir.file("soup"), p);
    EXPECT_TRUE(r.external);
    EXPECT_EQ(r.passes, 3);
    EXPECT_TRUE(r.layout.normals && r.layout.colors);
    expect_soup_matches(ply, r);
    // Only the soup is left: the sort's temporary files are gone.
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir.path())) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
}

TEST(OocSoup, FacesBeforeVerticesTakeTheExternalPath) {
    ScratchDir dir("soup-order");
    const std::string ply = dir.file("faces_first.ply");
    {
        std::ofstream f(ply);
        f << "ply\nformat ascii 1.0\nelement face 2\nproperty list uchar int vertex_indices\n"
             "element vertex 4\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
             "3 0 1 2\n4 0 2 3 1\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    }
    const SoupResult r = convert_to_soup(ply, dir.file("soup"));
    EXPECT_TRUE(r.external);
    EXPECT_EQ(r.triangles, 3u);  // the quad is fanned
    expect_soup_matches(ply, r);
}

// The wedge (face-corner) texcoords of a MeshLab PLY, straight from the reader.
std::vector<Vec2f> corner_texcoords_of(const std::string& ply) {
    PlyReader reader(ply);
    PlyFaceChunk faces;
    while (reader.current_element()) {
        if (reader.at_faces()) reader.read_faces(1 << 20, faces);
        else reader.skip_element();
    }
    return faces.corner_texcoords;
}

std::string file_text(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// Cancels at the n-th report of a stage.
class CancelInStage : public Progress {
public:
    CancelInStage(std::string stage, int n) : stage_(std::move(stage)), n_(n) {}
    void report(double, std::string_view stage) override {
        if (stage == stage_) --n_;
    }
    bool cancelled() const override { return n_ <= 0; }

private:
    std::string stage_;
    int n_;
};

TEST(OocSoup, ExternalPassesOnTwoThreadsGiveTheSoupOfOne) {
    // At 4 MB frag_115 has 2 (one thread) or 4 (two) vertex ranges and 11 or 21 corner ranges, so both
    // threads dereference and assemble several ranges each; the soup and the edge lists must not change.
    const std::string ply = shared_data("color-open3d-frag115/frag_115.ply");
    ScratchDir dir("soup-external-threads");
    std::vector<SoupResult> results;
    for (int threads : {1, 2}) {
        SoupParams p;
        p.memory_bytes = 4u << 20;
        p.threads = threads;
        results.push_back(convert_to_soup(ply, dir.file("soup" + std::to_string(threads)), p));
        EXPECT_TRUE(results.back().external);
    }
    const std::string one = file_text(results[0].path);
    ASSERT_GT(one.size(), 64u + 3 * 44 * 100000);
    EXPECT_TRUE(one == file_text(results[1].path));
    EXPECT_EQ(results[0].odd_non_manifold_edges, results[1].odd_non_manifold_edges);
    EXPECT_EQ(results[0].border_edges, results[1].border_edges);
    EXPECT_FALSE(results[0].border_edges.empty());

    // Cancelled while the two threads dereference or assemble: an error, and no file is left.
    for (const char* stage : {"soup: dereferencing", "soup: assembling"}) {
        for (int n : {1, 2}) {
            ScratchDir cancel_dir("soup-external-cancel");
            SoupParams p;
            p.memory_bytes = 4u << 20;
            CancelInStage cancel(stage, n);
            try {
                convert_to_soup(ply, cancel_dir.file("soup"), p, &cancel);
                ADD_FAILURE() << "not cancelled in " << stage;
            } catch (const Error& e) {
                EXPECT_EQ(e.kind(), Error::Kind::cancelled) << stage;
            }
            EXPECT_EQ(std::distance(fs::directory_iterator(cancel_dir.path()), fs::directory_iterator()), 0) << stage << n;
        }
    }
}

TEST(OocSoup, ExternalAssemblyWritesTheRootSplitOfTheSoup) {
    // SoupParams::root_split: instead of the soup file, the assembly pass writes each triangle into the
    // file of its centroid's octant. Octant o, read region after region, must be exactly the soup's
    // triangles of octant o in soup order (what the octree's streaming split of the soup writes), on one
    // thread and on two, and the bounds and edge lists must be those of the soup.
    const std::string ply = shared_data("color-open3d-frag115/frag_115.ply");
    ScratchDir dir("soup-root-split");
    SoupParams plain;
    plain.memory_bytes = 4u << 20;
    const SoupResult soup = convert_to_soup(ply, dir.file("soup"), plain);
    ASSERT_TRUE(soup.external);
    const std::size_t tb = soup_triangle_bytes(soup.layout), cb = soup_corner_bytes(soup.layout);
    const std::string text = file_text(soup.path);
    ASSERT_EQ(text.size(), 64 + soup.triangles * tb);
    double mid[3];
    for (int a = 0; a < 3; ++a) mid[a] = 0.5 * (static_cast<double>(soup.bounds.min[a]) + soup.bounds.max[a]);
    std::array<std::string, 8> expected;
    for (std::uint64_t t = 0; t < soup.triangles; ++t) {
        const char* tri = text.data() + 64 + t * tb;
        int o = 0;
        for (int a = 0; a < 3; ++a) {
            float p[3];
            for (int k = 0; k < 3; ++k) std::memcpy(&p[k], tri + k * cb + 4 + 4 * a, 4);
            if ((static_cast<double>(p[0]) + p[1] + p[2]) / 3.0 >= mid[a]) o |= 1 << a;
        }
        expected[o].append(tri, tb);
    }
    for (int threads : {1, 2}) {
        SCOPED_TRACE(threads);
        SoupParams p = plain;
        p.threads = threads;
        Bounds asked;
        p.root_split = [&](const Bounds& b, std::uint64_t triangles, const VertexLayout& layout) {
            asked = b;
            EXPECT_EQ(triangles, soup.triangles);
            EXPECT_EQ(layout, soup.layout);
            return SoupRootSplit{true, {mid[0], mid[1], mid[2]}};
        };
        ScratchDir split_dir("soup-root-split-" + std::to_string(threads));
        const SoupResult r = convert_to_soup(ply, split_dir.file("soup"), p);
        ASSERT_TRUE(r.root_split);
        EXPECT_FALSE(fs::exists(r.path));
        EXPECT_EQ(asked.min, soup.bounds.min);
        EXPECT_EQ(asked.max, soup.bounds.max);
        EXPECT_EQ(r.bounds.min, soup.bounds.min);
        EXPECT_EQ(r.bounds.max, soup.bounds.max);
        EXPECT_EQ(r.triangles, soup.triangles);
        EXPECT_EQ(r.border_edges, soup.border_edges);
        EXPECT_EQ(r.odd_non_manifold_edges, soup.odd_non_manifold_edges);
        std::size_t nonempty = 0, regions = 0;
        for (int o = 0; o < 8; ++o) {
            std::string got;
            for (const SoupRegion& region : r.octants[o]) {
                const std::string f = file_text(region.path);
                ASSERT_LE(region.offset + region.count * tb, f.size());
                got.append(f, region.offset, region.count * tb);
            }
            EXPECT_EQ(r.octant_counts[o] * tb, got.size()) << o;
            EXPECT_TRUE(got == expected[o]) << "octant " << o;
            nonempty += !got.empty();
            regions += r.octants[o].size();
        }
        EXPECT_GE(nonempty, 4u);
        // One thread's runs of a file coalesce into one region per octant; two threads alternate ranges.
        if (threads == 1) EXPECT_EQ(regions, nonempty);
        else EXPECT_GT(regions, nonempty);
    }
    // Cancelled while assembling into octant files: an error, and no file is left.
    ScratchDir cancel_dir("soup-root-split-cancel");
    SoupParams p = plain;
    p.root_split = [&](const Bounds&, std::uint64_t, const VertexLayout&) { return SoupRootSplit{true, {mid[0], mid[1], mid[2]}}; };
    CancelInStage cancel("soup: assembling", 3);
    EXPECT_THROW(convert_to_soup(ply, cancel_dir.file("soup"), p, &cancel), Error);
    EXPECT_EQ(std::distance(fs::directory_iterator(cancel_dir.path()), fs::directory_iterator()), 0);
}

TEST(OocSoup, WedgeTexcoordsTravelWithTheirCornerOnBothPaths) {
    ScratchDir dir("soup-wedge");
    const std::string ply = shared_data("tex-ply-wedge-uv/laurana500.ply");
    const SoupResult r = convert_to_soup(ply, dir.file("soup"));
    EXPECT_FALSE(r.external);
    ASSERT_TRUE(r.wedge_texcoords);
    ASSERT_TRUE(r.layout.texcoords);
    const std::vector<Vec2f> uv = corner_texcoords_of(ply);
    ASSERT_EQ(uv.size(), 3 * r.triangles);
    SoupReader reader(r.path);
    EXPECT_TRUE(reader.wedge_texcoords());
    std::vector<std::byte> buf;
    ASSERT_EQ(reader.read(r.triangles, buf), r.triangles);
    const std::size_t cb = soup_corner_bytes(r.layout);
    std::size_t mismatches = 0, seams = 0;
    std::map<std::uint32_t, Vec2f> first_uv;
    for (std::size_t c = 0; c < uv.size(); ++c) {
        std::uint32_t id;
        float f[2];
        std::memcpy(&id, buf.data() + c * cb, 4);
        std::memcpy(f, buf.data() + c * cb + 4 + 4 * r.layout.texcoord_offset(), 8);
        mismatches += !(f[0] == uv[c].x && f[1] == uv[c].y);
        const auto [it, fresh] = first_uv.emplace(id, uv[c]);
        seams += !fresh && !(it->second == uv[c]);
    }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GT(seams, 0u);  // the file has real seams: one vertex, several UVs

    // The same file with the faces first takes the external sort, which must give the same bytes.
    const std::string text = file_text(ply);
    const std::size_t body = text.find("end_header\n") + 11;
    std::vector<std::string> lines;
    for (std::size_t at = body; at < text.size();) {
        const std::size_t end = text.find('\n', at);
        lines.push_back(text.substr(at, end - at + 1));
        at = end == std::string::npos ? text.size() : end + 1;
    }
    ASSERT_GE(lines.size(), 266u + 494u);
    const std::string reordered = dir.file("faces_first.ply");
    {
        std::ofstream f(reordered, std::ios::binary);
        f << "ply\nformat ascii 1.0\nelement face 494\nproperty list uchar int vertex_indices\n"
             "property list uchar float texcoord\nelement vertex 266\nproperty float x\nproperty float y\n"
             "property float z\nend_header\n";
        for (std::size_t i = 266; i < 266 + 494; ++i) f << lines[i];
        for (std::size_t i = 0; i < 266; ++i) f << lines[i];
    }
    const SoupResult e = convert_to_soup(reordered, dir.file("soup-external"));
    EXPECT_TRUE(e.external);
    EXPECT_TRUE(e.wedge_texcoords);
    EXPECT_EQ(file_text(e.path), file_text(r.path));
}

// A face `texnumber` (the pack's per-face material) goes into each of the face's corner records, on the
// in-memory path and, with the faces first, on the external sort (corner references grow by 4 bytes):
// the same bytes either way.
TEST(OocSoup, FaceMaterialsTravelWithTheirTriangleOnBothPaths) {
    ScratchDir dir("soup-material");
    const Mesh truck = read_mesh(shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"));
    ASSERT_EQ(truck.face_materials.size(), truck.triangle_count());
    WriteOptions w;
    w.ply_face_materials = true;
    w.ply_encoding = PlyEncoding::ascii;
    const std::string ply = dir.file("truck.ply");
    write_mesh(truck, ply, w);
    const SoupResult r = convert_to_soup(ply, dir.file("soup"));
    EXPECT_FALSE(r.external);
    ASSERT_TRUE(r.layout.material);
    ASSERT_EQ(r.triangles, truck.triangle_count());
    SoupReader reader(r.path);
    EXPECT_TRUE(reader.layout().material);
    std::vector<std::byte> buf;
    ASSERT_EQ(reader.read(r.triangles, buf), r.triangles);
    const std::size_t cb = soup_corner_bytes(r.layout);
    std::size_t wrong = 0;
    std::set<float> seen;
    for (std::size_t c = 0; c < 3 * r.triangles; ++c) {
        std::uint32_t id;
        float material;
        std::memcpy(&id, buf.data() + c * cb, 4);
        std::memcpy(&material, buf.data() + c * cb + 4 + 4 * r.layout.material_offset(), 4);
        wrong += id != truck.indices[c] || material != static_cast<float>(truck.face_materials[c / 3]);
        seen.insert(material);
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(seen.size(), 4u);

    // Faces first: the external path.
    const std::string text = file_text(ply);
    const std::size_t vertex_at = text.find("element vertex"), face_at = text.find("element face"),
                      end_at = text.find("end_header\n");
    std::string reordered = text.substr(0, vertex_at) + text.substr(face_at, end_at - face_at) +
                            text.substr(vertex_at, face_at - vertex_at) + "end_header\n";
    std::size_t at = end_at + 11;
    for (std::size_t v = 0; v < truck.vertex_count(); ++v) at = text.find('\n', at) + 1;
    reordered += text.substr(at) + text.substr(end_at + 11, at - (end_at + 11));
    {
        std::ofstream f(dir.file("faces_first.ply"), std::ios::binary);
        f << reordered;
    }
    const SoupResult e = convert_to_soup(dir.file("faces_first.ply"), dir.file("soup-external"));
    EXPECT_TRUE(e.external);
    EXPECT_TRUE(e.layout.material);
    EXPECT_EQ(file_text(e.path), file_text(r.path));
}

// The soup's border list by brute force: index border edges (one use by a non-degenerate triangle,
// degenerate triangles' edges counting as further uses) whose two positions no other such use joins.
std::vector<std::uint64_t> expected_borders(const Mesh& m) {
    std::map<std::uint64_t, int> uses, proper;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const std::uint32_t* v = &m.indices[3 * t];
        const bool degenerate = v[0] == v[1] || v[1] == v[2] || v[0] == v[2];
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = v[k], b = v[(k + 1) % 3];
            if (a == b) continue;
            if (a > b) std::swap(a, b);
            ++uses[std::uint64_t{a} << 32 | b];
            if (!degenerate) ++proper[std::uint64_t{a} << 32 | b];
        }
    }
    std::map<std::array<float, 6>, int> at;
    std::vector<std::pair<std::array<float, 6>, std::uint64_t>> border;
    for (const auto& [e, n] : proper) {
        if (n != 1) continue;
        Vec3f pa = m.positions[e >> 32], pb = m.positions[e & 0xffffffffu];
        std::array<float, 3> a{pa.x, pa.y, pa.z}, b{pb.x, pb.y, pb.z};
        if (b < a) std::swap(a, b);
        const std::array<float, 6> key{a[0], a[1], a[2], b[0], b[1], b[2]};
        at[key] += uses[e];
        border.emplace_back(key, e);
    }
    std::vector<std::uint64_t> out;
    for (const auto& [key, e] : border)
        if (at[key] == 1) out.push_back(e);
    std::sort(out.begin(), out.end());
    return out;
}

// Writes `m` (positions and faces) as an ASCII PLY, the faces first when `faces_first` (the external path).
void write_positions_ply(const Mesh& m, const std::string& path, bool faces_first) {
    std::ofstream f(path);
    const std::string vh = "element vertex " + std::to_string(m.vertex_count()) + "\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string fh = "element face " + std::to_string(m.triangle_count()) + "\nproperty list uchar int vertex_indices\n";
    f << "ply\nformat ascii 1.0\n" << (faces_first ? fh + vh : vh + fh) << "end_header\n";
    f.precision(9);
    auto vertices = [&] {
        for (const Vec3f& p : m.positions) f << p.x << ' ' << p.y << ' ' << p.z << '\n';
    };
    auto faces = [&] {
        for (std::size_t t = 0; t < m.triangle_count(); ++t)
            f << "3 " << m.indices[3 * t] << ' ' << m.indices[3 * t + 1] << ' ' << m.indices[3 * t + 2] << '\n';
    };
    if (faces_first) faces(), vertices();
    else vertices(), faces();
}

TEST(OocSoup, BorderEdgesDropSeamsOfSplitVerticesOnBothPaths) {
    // Spot's UV seams are vertices split at one position (index borders, not real ones); the bunny has
    // real holes. Both paths must give the brute-force list (the in-memory path looks positions up in the
    // vertex table, the external one makes a pass over the soup).
    ScratchDir dir("soup-borders");
    for (const std::string& name : {std::string("tex-spot/spot_triangulated.obj"), std::string("scan-bunny/bun_zipper.ply")}) {
        const Mesh mesh = read_mesh(shared_data(name));
        const std::string in_memory = dir.file("vertices_first.ply"), external = dir.file("faces_first.ply");
        write_positions_ply(mesh, in_memory, false);
        write_positions_ply(mesh, external, true);
        const Mesh input = read_ply(in_memory);
        const std::vector<std::uint64_t> expected = expected_borders(input);
        // Spot: 576 index borders, all seams; the bunny: real holes.
        EXPECT_EQ(expected.empty(), name.starts_with("tex-spot")) << name;
        const SoupResult r = convert_to_soup(in_memory, dir.file("soup"));
        const SoupResult e = convert_to_soup(external, dir.file("soup-external"));
        EXPECT_FALSE(r.external);
        EXPECT_TRUE(e.external);
        EXPECT_EQ(r.border_edges, expected) << name;
        EXPECT_EQ(e.border_edges, expected) << name;
        EXPECT_EQ(r.odd_non_manifold_edges, e.odd_non_manifold_edges) << name;
    }
}

TEST(OocSoup, TruncatedAndLyingInputsStopWithTheFileName) {
    ScratchDir dir("soup-bad");
    const std::string src = shared_data("scan-lucy100k/Lucy100k.ply");
    const std::string cut = dir.file("truncated.ply");
    {
        std::ifstream in(src, std::ios::binary);
        std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
        bytes.resize(bytes.size() * 2 / 3);
        std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    for (std::size_t budget : {std::size_t{4} << 20, std::size_t{64} << 20}) {
        SoupParams p;
        p.memory_bytes = budget;
        try {
            convert_to_soup(cut, dir.file("soup"), p);
            FAIL() << "a truncated file was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::format);
            EXPECT_NE(std::string(e.what()).find("truncated.ply"), std::string::npos) << e.what();
        }
        EXPECT_FALSE(fs::exists(dir.file("soup")));
    }
    const std::string bad_index = dir.file("bad_index.ply");
    std::ofstream(bad_index) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
    EXPECT_THROW(convert_to_soup(bad_index, dir.file("soup")), Error);
    const std::string no_faces = dir.file("points.ply");
    std::ofstream(no_faces) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                               "property float z\nend_header\n0 0 0\n";
    EXPECT_THROW(convert_to_soup(no_faces, dir.file("soup")), Error);
    EXPECT_THROW(convert_to_soup(dir.file("missing.ply"), dir.file("soup")), Error);
    std::size_t leftovers = 0;
    for (const auto& e : fs::directory_iterator(dir.path()))
        leftovers += e.path().filename().string().find(".ply") == std::string::npos;
    EXPECT_EQ(leftovers, 0u);
}

// An ASCII file is parsed on two threads (segments of whole lines, docs/octree.md): the soup, the odd
// and the border edges must be those of one reader, on a real scan and on a rewrite of it with blank
// lines, leading blanks, CRLF line ends and polygons.
std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

// The dragon at res 2 (7 MB ASCII) with its body lines rewritten: `edit(i, line)` returns the new text
// of data line i (without its '\n').
template <class Edit>
std::string rewrite_dragon(const ScratchDir& dir, const std::string& name, Edit edit) {
    const std::string text = read_all(shared_data("scan-dragon/dragon_vrip_res2.ply"));
    const std::size_t body = text.find("end_header\n") + 11;
    std::string out = text.substr(0, body);
    std::size_t i = 0;
    for (std::size_t at = body; at < text.size(); ++i) {
        const std::size_t nl = text.find('\n', at);
        out += edit(i, text.substr(at, nl - at));
        at = nl + 1;
    }
    const std::string path = dir.file(name);
    std::ofstream(path, std::ios::binary) << out;
    return path;
}

SoupResult soup_with_threads(const std::string& ply, const std::string& soup, int threads) {
    SoupParams p;
    p.memory_bytes = 4u << 20;  // 128 KB segments: dozens of them
    p.threads = threads;
    return convert_to_soup(ply, soup, p);
}

TEST(OocSoup, AsciiOnTwoThreadsGivesTheSoupOfOneReader) {
    ScratchDir dir("soup-ascii-threads");
    const std::string odd = rewrite_dragon(dir, "odd.ply", [](std::size_t i, std::string line) {
        if (i % 50 == 49 && line.rfind("3 ", 0) == 0) {  // a quad
            line.erase(line.find_last_not_of(' ') + 1);
            line = "4" + line.substr(1) + line.substr(line.rfind(' '));
        }
        if (i % 7 == 0) line = "  " + line;
        if (i % 11 == 0) line += "\r";
        if (i % 13 == 0) line += "\n \t\n";
        return line + "\n";
    });
    for (const std::string& ply : {shared_data("scan-dragon/dragon_vrip_res2.ply"), odd}) {
        const SoupResult one = soup_with_threads(ply, dir.file("one"), 1);
        const SoupResult two = soup_with_threads(ply, dir.file("two"), 2);
        EXPECT_FALSE(two.external);
        EXPECT_EQ(one.triangles, two.triangles);
        EXPECT_GT(one.triangles, 200000u);
        EXPECT_EQ(one.skipped_faces, two.skipped_faces);
        EXPECT_EQ(one.odd_non_manifold_edges, two.odd_non_manifold_edges);
        EXPECT_EQ(one.border_edges, two.border_edges);
        EXPECT_TRUE(read_all(dir.file("one")) == read_all(dir.file("two"))) << ply;
        if (ply == odd) expect_soup_matches(ply, two);
        // The edge lists sorted in the background (as the octree builder asks) are the same once waited for.
        SoupParams p;
        p.memory_bytes = 4u << 20;
        p.background_edges = true;
        SoupResult later = convert_to_soup(ply, dir.file("later"), p);
        EXPECT_TRUE(later.edge_job != nullptr);
        later.wait_edges();
        EXPECT_TRUE(later.edge_job == nullptr);
        EXPECT_EQ(later.odd_non_manifold_edges, one.odd_non_manifold_edges);
        EXPECT_EQ(later.border_edges, one.border_edges);
    }
    // And on the open bunny, which has border edges.
    const std::string bunny = shared_data("scan-bunny/bun_zipper.ply");
    const SoupResult now = soup_with_threads(bunny, dir.file("now"), 2);
    SoupParams p;
    p.background_edges = true;
    SoupResult later = convert_to_soup(bunny, dir.file("later"), p);
    later.wait_edges();
    EXPECT_FALSE(now.border_edges.empty());
    EXPECT_EQ(later.border_edges, now.border_edges);
    EXPECT_EQ(later.odd_non_manifold_edges, now.odd_non_manifold_edges);
}

// Errors in any segment (the helper's included) and a cut-off file give one reader's message.
TEST(OocSoup, AsciiErrorsOnTwoThreadsAreThoseOfOneReader) {
    ScratchDir dir("soup-ascii-errors");
    auto message = [&](const std::string& ply, int threads) {
        try {
            soup_with_threads(ply, dir.file("soup"), threads);
        } catch (const Error& e) {
            EXPECT_FALSE(fs::exists(dir.file("soup")));
            return std::string(e.what());
        }
        return std::string("no error");
    };
    std::vector<std::string> bad;
    for (std::size_t at : {60000u, 90000u, 250000u, 300000u})  // vertex and face lines, both threads' segments
        bad.push_back(rewrite_dragon(dir, "bad" + std::to_string(at) + ".ply",
                                     [at](std::size_t i, const std::string& line) { return (i == at ? line + " 7" : line) + "\n"; }));
    bad.push_back(rewrite_dragon(dir, "index.ply", [](std::size_t i, const std::string& line) {
        return (i == 280000 ? std::string("3 0 1 99999999") : line) + "\n";
    }));
    const std::string cut = dir.file("cut.ply");
    {
        const std::string text = read_all(shared_data("scan-dragon/dragon_vrip_res2.ply"));
        std::ofstream(cut, std::ios::binary) << text.substr(0, text.size() * 4 / 5);
    }
    bad.push_back(cut);
    for (const std::string& ply : bad) {
        const std::string one = message(ply, 1);
        EXPECT_NE(one, "no error") << ply;
        EXPECT_NE(one.find(fs::path(ply).filename().string()), std::string::npos) << one;
        EXPECT_EQ(message(ply, 2), one);
    }
}

}  // namespace
}  // namespace lodforge
