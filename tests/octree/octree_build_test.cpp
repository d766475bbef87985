#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/octree/octree_build.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/io/ply.h"
#include "lodforge/simplify/simplify.h"

#include "octree_test_util.h"
#include "support/icosphere.h"
#include "support/own_format_seal.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <map>
#include <set>
#include <tuple>

namespace lodforge {
namespace {

namespace fs = std::filesystem;
using test::edge_counts;
using test::ScratchDir;
using test::shared_data;

std::size_t files_in(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir)) n += !e.is_directory();
    return n;
}

// A triangle as its three input vertex ids, rotated so the smallest comes first (winding kept).
using Tri = std::array<std::uint64_t, 3>;
Tri canonical(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
    if (b < a && b <= c) return {b, c, a};
    if (c < a && c < b) return {c, a, b};
    return {a, b, c};
}

// A random cut mixing levels: descend with probability 1/2 per node, leaves raw or simplified.
Cut random_cut(const OctreeStore& store, std::mt19937& rng) {
    Cut cut;
    std::vector<std::uint32_t> stack{0};
    std::bernoulli_distribution coin(0.5);
    while (!stack.empty()) {
        const std::uint32_t i = stack.back();
        stack.pop_back();
        const OctreeNode& d = store.node(i);
        if (d.is_leaf()) cut.push_back({i, coin(rng)});
        else if (i != 0 && coin(rng)) cut.push_back({i, false});
        else
            for (std::uint32_t c : store.children(i)) stack.push_back(c);
    }
    return cut;
}

struct Built {
    ScratchDir dir;
    std::string asset;
    OctreeBuildResult result;
    Built(const std::string& name, const std::string& input, std::size_t max_tris, int depth, std::size_t memory = 64u << 20)
        : dir(name), asset(dir.file("out.lfo")) {
        OctreeBuildParams p;
        p.max_triangles = max_tris;
        p.max_depth = depth;
        p.memory_bytes = memory;
        result = build_octree(input, asset, p);
    }
};

TEST(OctreeBuild, EveryInputTriangleIsInExactlyOneLeaf) {
    const std::string input = shared_data("scan-dragon/dragon_vrip_res2.ply");
    Built b("octree-partition", input, 2000, 8, 4u << 20);  // 4 MB: the root is split by streaming
    EXPECT_GT(b.result.split_passes, 0u);
    const Mesh m = read_ply(input);
    std::multiset<Tri> expected;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        expected.insert(canonical(m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]));
    OctreeStore store(b.asset);
    std::multiset<Tri> got;
    std::uint64_t leaf_sum = 0;
    for (std::uint32_t i = 0; i < store.nodes().size(); ++i) {
        const OctreeNode& d = store.node(i);
        if (!d.is_leaf()) continue;
        EXPECT_LE(d.raw_triangles, 2000u) << "node " << i;
        leaf_sum += d.raw_triangles;
        const auto raw = store.load(i, true);
        for (std::size_t t = 0; t < raw->triangle_count(); ++t) {
            const std::uint32_t* x = &raw->indices[3 * t];
            got.insert(canonical(raw->keys[x[0]], raw->keys[x[1]], raw->keys[x[2]]));
            // The assignment rule: the centroid lies in the leaf's cell.
            for (int a = 0; a < 3; ++a) {
                const float c = (raw->vertex(x[0])[a] + raw->vertex(x[1])[a] + raw->vertex(x[2])[a]) / 3.f;
                EXPECT_GE(c, d.cell_min[a] - 1e-4f * d.cell_size);
                EXPECT_LE(c, d.cell_min[a] + d.cell_size * (1 + 1e-4f));
            }
        }
    }
    EXPECT_EQ(leaf_sum, m.triangle_count());
    EXPECT_TRUE(got == expected);
    const OctreeStats s = store.stats();
    EXPECT_EQ(s.leaves, b.result.stats.leaves);
    EXPECT_GT(s.leaves, m.triangle_count() / 2000);
    EXPECT_LE(s.depth_reached, 8);
    std::uint64_t per_depth = 0;
    for (std::uint64_t t : s.triangles_per_depth) per_depth += t;
    EXPECT_EQ(per_depth, m.triangle_count());
    // The root cube encloses the bounds.
    const OctreeHeader& h = store.header();
    EXPECT_LE(h.root_min[0], h.bounds.min.x);
    EXPECT_GT(h.root_min[2] + h.root_size, h.bounds.max.z);
}

TEST(OctreeBuild, ThreadsAndAnInMemorySoupGiveTheSameAssetByteForByte) {
    // Node ids (in representative keys) are fixed before any node is simplified, and chunks are
    // written in the serial order, so the thread count must not show in the asset; nor must a soup
    // that never went to disk (64 MB) against one split by streaming (4 MB).
    const std::string input = shared_data("scan-dragon/dragon_vrip_res3.ply");
    ScratchDir dir("octree-threads");
    struct Run {
        int threads;
        std::size_t memory;
        bool soup_in_memory;
    };
    const Run runs[] = {{1, 4u << 20, false}, {2, 4u << 20, false}, {2, 64u << 20, true}};
    std::vector<std::string> bytes;
    for (const Run& run : runs) {
        OctreeBuildParams p;
        p.max_triangles = 300;
        p.max_depth = 8;
        p.memory_bytes = run.memory;  // 4 MB: the root is split by streaming, its children held in memory
        p.threads = run.threads;
        const std::string asset = dir.file("t" + std::to_string(bytes.size()) + ".lfo");
        const OctreeBuildResult r = build_octree(input, asset, p);
        EXPECT_GT(r.stats.nodes, 40u);
        EXPECT_EQ(r.soup.kept_in_memory, run.soup_in_memory) << run.memory;
        EXPECT_TRUE(r.soup.memory.empty());  // freed once the builder is done
        EXPECT_EQ(r.split_passes > 0, !run.soup_in_memory);
        std::ifstream f(asset, std::ios::binary);
        bytes.emplace_back(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    }
    ASSERT_FALSE(bytes[0].empty());
    EXPECT_TRUE(bytes[0] == bytes[1]);
    EXPECT_TRUE(bytes[0] == bytes[2]);
}

TEST(OctreeBuild, ClosedInputsStayClosedAtEveryLevelAndAtMixedLevels) {
    std::mt19937 rng(7);
    for (const char* name : {"scan-dragon/dragon_vrip_res4.ply", "scan-happy-buddha/happy_vrip_res3.ply"}) {
        SCOPED_TRACE(name);
        const std::string input = shared_data(name);
        const Mesh m = read_ply(input);
        ASSERT_EQ(edge_counts(m).border, 0u) << "the test needs a closed input";
        const bool oriented = edge_counts(m).unpaired == 0;
        EXPECT_TRUE(oriented) << "both inputs are consistently oriented";
        Built b("octree-closed", input, 300, 10);
        OctreeStore store(b.asset, 1u << 20);
        ASSERT_GE(store.level_count(), 4);
        std::uint64_t previous = ~0ull;
        for (int level = 0; level < store.level_count(); ++level) {
            const Cut cut = level_cut(store, level);
            ASSERT_TRUE(is_valid_cut(store, cut));
            const Mesh lm = extract_mesh(store, cut);
            EXPECT_EQ(edge_counts(lm).border, 0u) << "level " << level;
            // Fans take their edge's direction from its source triangle: orientation survives too.
            if (oriented) {
                EXPECT_EQ(edge_counts(lm).unpaired, 0u) << "level " << level;
            }
            EXPECT_LE(lm.triangle_count(), previous) << "level " << level;
            EXPECT_EQ(lm.triangle_count(), store.stats().triangles_per_level[static_cast<std::size_t>(level)]);
            previous = lm.triangle_count();
        }
        EXPECT_EQ(store.stats().triangles_per_level[0], m.triangle_count());
        EXPECT_LT(store.stats().triangles_per_level[2], m.triangle_count() / 2);
        // The root of a closed model is one closed component: clustered, not a copy of the level below.
        const std::vector<std::uint64_t>& per_level = store.stats().triangles_per_level;
        EXPECT_LT(per_level.back(), per_level[per_level.size() - 2] / 2);
        for (int trial = 0; trial < 20; ++trial) {
            const Cut cut = random_cut(store, rng);
            ASSERT_TRUE(is_valid_cut(store, cut));
            const Mesh cm = extract_mesh(store, cut);
            const test::EdgeCounts ec = edge_counts(cm);
            ASSERT_EQ(ec.border, 0u) << "trial " << trial << ", " << cut.size() << " nodes";
            if (oriented) {
                ASSERT_EQ(ec.unpaired, 0u) << "trial " << trial;
            }
        }
        EXPECT_LE(store.cache_bytes(), store.cache_limit());
    }
}

TEST(OctreeBuild, OpenScanGainsNoBorderEdgesAtMixedLevels) {
    // The bunny has real holes: a cut's border edges must all be border edges of the input.
    const std::string input = shared_data("scan-bunny/bun_zipper.ply");
    const Mesh m = read_ply(input);
    std::set<std::pair<std::uint64_t, std::uint64_t>> input_border;
    {
        std::map<std::pair<std::uint64_t, std::uint64_t>, int> uses;
        for (std::size_t t = 0; t < m.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k) {
                std::uint64_t a = m.indices[3 * t + k], c = m.indices[3 * t + (k + 1) % 3];
                if (a != c) ++uses[{std::min(a, c), std::max(a, c)}];
            }
        for (const auto& [e, n] : uses)
            if (n == 1) input_border.insert(e);
    }
    ASSERT_GT(input_border.size(), 0u);
    std::set<std::uint64_t> border_vertices;
    for (const auto& [a, c] : input_border) {
        border_vertices.insert(a);
        border_vertices.insert(c);
    }
    Built b("octree-open", input, 500, 10);
    OctreeStore store(b.asset);
    std::mt19937 rng(3);
    for (int trial = 0; trial < 12; ++trial) {
        const Cut cut = trial < store.level_count() ? level_cut(store, trial) : random_cut(store, rng);
        std::vector<std::uint64_t> keys;
        const Mesh cm = extract_mesh(store, cut, nullptr, &keys);
        std::map<std::pair<std::uint64_t, std::uint64_t>, int> uses;
        for (std::size_t t = 0; t < cm.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k) {
                std::uint64_t a = keys[cm.indices[3 * t + k]], c = keys[cm.indices[3 * t + (k + 1) % 3]];
                ++uses[{std::min(a, c), std::max(a, c)}];
            }
        // Border chains are simplified (docs/octree.md, "Coarse levels"): a new border edge may only be
        // a chord between two input border vertices, never an edge next to a representative or inside.
        std::size_t new_border = 0, chords = 0, clustered = 0;
        constexpr std::uint64_t kClusterBit = kRepresentativeKey | std::uint64_t{1} << 62;
        for (const auto& [e, n] : uses) {
            if (n != 1 || input_border.count(e)) continue;
            if (!(e.first & kRepresentativeKey) && !(e.second & kRepresentativeKey) && border_vertices.count(e.first) &&
                border_vertices.count(e.second))
                ++chords;
            else if ((e.first & e.second & kClusterBit) && (e.first & 0xffffffffu) == (e.second & 0xffffffffu))
                ++clustered;  // a hole of a component clustered in one node (its borders all gone)
            else
                ++new_border;
        }
        EXPECT_EQ(new_border, 0u) << "trial " << trial;
        if (trial == 0) {
            EXPECT_EQ(chords + clustered, 0u);  // level 0 is the input
        }
    }
    // The root's border is free (shared with no node), so it shrinks: the document's operator keeps every
    // border edge. The root is one part collapsed with its border sliding, to the level ratio (35 % of the
    // level below): 159 border edges where the input has 220 (20 when the root collapsed as far as the
    // error bound let it, level_ratio 0).
    const Mesh root = extract_mesh(store, level_cut(store, store.level_count() - 1));
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> root_uses;
    for (std::size_t t = 0; t < root.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = root.indices[3 * t + k], c = root.indices[3 * t + (k + 1) % 3];
            ++root_uses[{std::min(a, c), std::max(a, c)}];
        }
    const auto root_border = std::count_if(root_uses.begin(), root_uses.end(), [](const auto& u) { return u.second == 1; });
    EXPECT_GT(root.triangle_count(), 0u);
    EXPECT_LT(static_cast<std::size_t>(root_border), input_border.size() * 3 / 4);
}

TEST(OctreeBuild, ColoursAndNormalsOfAColouredScanSurviveAtEveryLevel) {
    for (const char* name : {"color-open3d-frag115/frag_115.ply", "color-open3d-small/color.ply"}) {
        SCOPED_TRACE(name);
        const std::string input = shared_data(name);
        const Mesh m = read_ply(input);
        Built b("octree-colour", input, m.triangle_count() / 60, 10);
        OctreeStore store(b.asset);
        ASSERT_TRUE(store.header().layout.colors && store.header().layout.normals);
        ASSERT_GE(store.level_count(), 3);
        double baseline = 0;  // RMS distance of the input's colours from their mean, 0-255
        {
            double mean[3] = {0, 0, 0};
            for (const Vec4f& c : m.colors) {
                mean[0] += c.x;
                mean[1] += c.y;
                mean[2] += c.z;
            }
            for (double& x : mean) x /= static_cast<double>(m.colors.size());
            for (const Vec4f& c : m.colors)
                baseline += (c.x - mean[0]) * (c.x - mean[0]) + (c.y - mean[1]) * (c.y - mean[1]) + (c.z - mean[2]) * (c.z - mean[2]);
            baseline = 255.0 * std::sqrt(baseline / (3.0 * static_cast<double>(m.colors.size())));
        }
        DistanceParams dp;
        dp.samples = 5000;
        dp.vertex_errors = false;
        for (int level = 1; level < store.level_count(); ++level) {
            std::vector<std::uint64_t> keys;
            const Mesh lm = extract_mesh(store, level_cut(store, level), nullptr, &keys);
            ASSERT_EQ(lm.colors.size(), lm.positions.size());
            ASSERT_EQ(lm.normals.size(), lm.positions.size());
            // Representatives get renormalised normals; kept input vertices keep theirs (color.ply's
            // normals are not unit length).
            for (std::size_t v = 0; v < keys.size(); ++v) {
                if (keys[v] & kRepresentativeKey) {
                    ASSERT_NEAR(length(lm.normals[v]), 1.f, 1e-3f);
                } else {
                    ASSERT_EQ(lm.normals[v], m.normals[keys[v]]);
                    ASSERT_EQ(lm.colors[v], m.colors[keys[v]]);
                }
            }
            for (const Vec4f& c : lm.colors) ASSERT_TRUE(c.x >= 0 && c.x <= 1 && c.w >= 0 && c.w <= 1);
            const DistanceResult d = compare(m, lm, dp);
            ASSERT_TRUE(d.has_color_error);
            // RMS over R, G, B on the 0-255 scale, at samples of the level mesh against the input.
            // Leaves keep colours close; every level stays well below the error of painting the model
            // its mean colour (the input's colour spread, `baseline`).
            if (level == 1) {
                EXPECT_LT(d.color_rms, 15.0);
            }
            // The root of an open fragment is its border loop, cut to a few vertices, fanned to one point.
            EXPECT_LT(d.color_rms, (level + 1 < store.level_count() ? 0.9 : 1.2) * baseline) << "level " << level;
            // Geometric error grows with the level but stays a fraction of the model.
            EXPECT_LT(d.mean_relative, 0.05) << "level " << level;
        }
    }
}

TEST(OctreeBuild, TexcoordsSurvive) {
    // Spot as a PLY with per-vertex u v (the PLY writer stores wedges as vertices).
    ScratchDir dir("octree-uv");
    const Mesh spot = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
    write_ply(spot, dir.file("spot.ply"));
    OctreeBuildParams p;
    p.max_triangles = 200;
    build_octree(dir.file("spot.ply"), dir.file("spot.lfo"), p);
    OctreeStore store(dir.file("spot.lfo"));
    ASSERT_TRUE(store.header().layout.texcoords);
    const Mesh lm = extract_mesh(store, level_cut(store, 1));
    ASSERT_EQ(lm.texcoords.size(), 1u);
    ASSERT_EQ(lm.texcoords[0].size(), lm.positions.size());
    DistanceParams dp;
    dp.samples = 5000;
    const DistanceResult d = compare(read_ply(dir.file("spot.ply")), lm, dp);
    ASSERT_TRUE(d.has_texcoord_error);
    // Seams tear (docs/octree.md), so the UV error is real, but most of the surface keeps its mapping.
    EXPECT_LT(d.texcoord_rms, 0.2);
}

// The materials of every level: each triangle's, and which ones occur.
std::set<std::uint32_t> level_materials(const Mesh& m) {
    EXPECT_EQ(m.face_materials.size(), m.triangle_count());
    return {m.face_materials.begin(), m.face_materials.end()};
}

// Border edges counted after welding equal positions: what a viewer sees as a crack.
std::size_t welded_border_edges(const Mesh& m) {
    std::map<std::tuple<float, float, float>, std::uint32_t> ids;
    Mesh w = m;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const Vec3f& p = m.positions[v];
        ids.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<std::uint32_t>(ids.size()));
    }
    for (auto& i : w.indices) {
        const Vec3f& p = m.positions[i];
        i = ids.at(std::make_tuple(p.x, p.y, p.z));
    }
    return edge_counts(w).border;
}

TEST(OctreeBuild, SeamsOfSplitVerticesStayClosedAtEveryLevelAndAtMixedLevels) {
    // Spot as a PLY with per-vertex u v: its UV seams are vertices split at one position, so by index
    // the seams look like 576 border edges; they must not be shrunk like real borders (the coarse-level
    // chain rule would open them).
    ScratchDir dir("octree-seams");
    const Mesh spot = read_mesh(shared_data("tex-spot/spot_triangulated.obj"));
    write_ply(spot, dir.file("spot.ply"));
    const Mesh input = read_ply(dir.file("spot.ply"));
    ASSERT_GT(edge_counts(input).border, 100u) << "the test needs seams of split vertices";
    ASSERT_EQ(welded_border_edges(input), 0u);
    OctreeBuildParams p;
    p.max_triangles = 200;
    p.max_depth = 8;
    build_octree(dir.file("spot.ply"), dir.file("spot.lfo"), p);
    OctreeStore store(dir.file("spot.lfo"));
    ASSERT_GE(store.level_count(), 4);
    for (int level = 0; level < store.level_count(); ++level)
        EXPECT_EQ(welded_border_edges(extract_mesh(store, level_cut(store, level))), 0u) << "level " << level;
    std::mt19937 rng(3);
    for (int trial = 0; trial < 20; ++trial) {
        const Cut cut = random_cut(store, rng);
        ASSERT_TRUE(is_valid_cut(store, cut));
        ASSERT_EQ(welded_border_edges(extract_mesh(store, cut)), 0u) << "trial " << trial;
    }
}

TEST(OctreeBuild, WedgeTexcoordsSurviveAtEveryLevel) {
    // MeshLab PLYs whose UVs are per face corner (`texcoord` lists), with seams.
    for (const char* name : {"tex-ply-wedge-uv/laurana500.ply", "tex-ply-wedge-uv/matteonormb.ply"}) {
        SCOPED_TRACE(name);
        const std::string input = shared_data(name);
        std::vector<std::uint32_t> corner_vertex;
        std::vector<Vec2f> corner_uv;
        {
            PlyReader reader(input);
            PlyFaceChunk faces;
            while (reader.current_element()) {
                if (reader.at_faces()) reader.read_faces(1 << 20, faces);
                else reader.skip_element();
            }
            corner_vertex = faces.indices;
            corner_uv = faces.corner_texcoords;
        }
        ASSERT_EQ(corner_uv.size(), corner_vertex.size());
        // Every (vertex, uv) wedge of the input, and the input as a Mesh (wedges split into vertices).
        std::set<std::tuple<std::uint32_t, float, float>> wedges;
        for (std::size_t c = 0; c < corner_uv.size(); ++c) wedges.insert({corner_vertex[c], corner_uv[c].x, corner_uv[c].y});
        const Mesh m = read_ply(input);
        double baseline = 0;  // RMS distance of the input's UVs from their mean: painting one texel
        {
            double mean[2] = {0, 0};
            for (const Vec2f& t : m.texcoords[0]) {
                mean[0] += t.x;
                mean[1] += t.y;
            }
            for (double& x : mean) x /= static_cast<double>(m.texcoords[0].size());
            for (const Vec2f& t : m.texcoords[0]) baseline += (t.x - mean[0]) * (t.x - mean[0]) + (t.y - mean[1]) * (t.y - mean[1]);
            baseline = std::sqrt(baseline / (2.0 * static_cast<double>(m.texcoords[0].size())));
        }
        Built b("octree-wedge", input, 40, 8);
        OctreeStore store(b.asset);
        ASSERT_TRUE(store.header().layout.texcoords);
        ASSERT_TRUE(store.header().wedge_texcoords);
        ASSERT_GE(store.level_count(), 3);
        DistanceParams dp;
        dp.samples = 5000;
        dp.vertex_errors = false;
        for (int level = 0; level < store.level_count(); ++level) {
            SCOPED_TRACE(level);
            std::vector<std::uint64_t> keys;
            const Mesh lm = extract_mesh(store, level_cut(store, level), nullptr, &keys);
            ASSERT_EQ(lm.texcoords.size(), 1u);
            ASSERT_EQ(lm.texcoords[0].size(), lm.positions.size());
            std::size_t foreign = 0;
            for (std::size_t v = 0; v < keys.size(); ++v) {
                const Vec2f uv = lm.texcoords[0][v];
                ASSERT_TRUE(std::isfinite(uv.x) && std::isfinite(uv.y));
                if (keys[v] & kRepresentativeKey) continue;
                // A kept input vertex carries one of its own wedges' UVs, never a neighbour's or a mean.
                foreign += !wedges.count({static_cast<std::uint32_t>(keys[v]), uv.x, uv.y});
            }
            EXPECT_EQ(foreign, 0u);
            if (level == 0) {
                // The input itself: one output vertex per wedge, every corner's UV its own.
                EXPECT_EQ(lm.positions.size(), wedges.size());
                EXPECT_EQ(lm.triangle_count(), corner_vertex.size() / 3);
            }
            const DistanceResult d = compare(m, lm, dp);
            ASSERT_TRUE(d.has_texcoord_error);
            if (level == 0) {
                EXPECT_LT(d.texcoord_rms, 1e-5);
            }
            // Inside a node the representative's UV interpolates across charts (docs/octree.md, known
            // weaknesses), so coarse levels are only bounded loosely; the exact check is the one above.
            EXPECT_LT(d.texcoord_rms, 2.5 * baseline) << "level " << level;
        }
    }
}

class CancelAfter : public Progress {
public:
    explicit CancelAfter(int n) : n_(n) {}
    void report(double, std::string_view stage) override {
        if (stage.find("octree") != std::string_view::npos) --n_;
    }
    bool cancelled() const override { return n_ <= 0; }

private:
    int n_;
};

TEST(OctreeBuild, CancelMidBuildLeavesNoFiles) {
    ScratchDir dir("octree-cancel");
    OctreeBuildParams p;
    p.max_triangles = 200;
    p.memory_bytes = 4u << 20;
    CancelAfter cancel(30);
    try {
        build_octree(shared_data("scan-dragon/dragon_vrip_res2.ply"), dir.file("out.lfo"), p, &cancel);
        FAIL() << "not cancelled";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::cancelled);
    }
    EXPECT_EQ(files_in(dir.path()), 0u);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 0);
}

TEST(OctreeBuild, StreamingSplitsOnTwoThreadsGiveTheAssetOfOne) {
    // At 4 MB the 202K-triangle dragon is split by streaming at the root and again below it, so the
    // children of a two-thread split (one file region per thread) are themselves split on two threads.
    const std::string input = shared_data("scan-dragon/dragon_vrip_res2.ply");
    ScratchDir dir("octree-split2");
    std::vector<std::string> bytes;
    for (int threads : {1, 2}) {
        OctreeBuildParams p;
        p.max_triangles = 300;
        p.max_depth = 10;
        p.memory_bytes = 4u << 20;
        p.threads = threads;
        const std::string asset = dir.file("t" + std::to_string(threads) + ".lfo");
        const OctreeBuildResult r = build_octree(input, asset, p);
        EXPECT_GT(r.split_passes, 1u);
        EXPECT_EQ(r.stats.triangles_per_level.front(), 202520u);
        std::ifstream f(asset, std::ios::binary);
        bytes.emplace_back(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    }
    ASSERT_FALSE(bytes[0].empty());
    EXPECT_TRUE(bytes[0] == bytes[1]);
}

TEST(OctreeBuild, RootSplitInTheSoupPassGivesTheAssetOfAStreamedSplit) {
    // At 4 MB the 202K dragon's vertex table fits (in-memory soup) but its root does not: the soup pass
    // writes the root's octant files itself, guessing the root cube from all the vertices. The asset
    // must be the one built without a root split (256 MB: everything in memory), on one thread and two.
    // A copy with one unused vertex far away makes the guess wrong: the split is undone (the octant
    // files merged back into the soup) and the asset is again that of the 256 MB build.
    const Mesh mesh = read_mesh(shared_data("scan-dragon/dragon_vrip_res2.ply"));
    ScratchDir dir("octree-root-split");
    Mesh outlier = mesh;
    const Bounds b = mesh.bounds();
    outlier.positions.push_back(b.max + (b.max - b.min) * 3.f);
    write_mesh(mesh, dir.file("dragon.ply"));
    write_mesh(outlier, dir.file("outlier.ply"));
    auto build = [&](const std::string& name, std::size_t mb, int threads, bool* root_split) {
        OctreeBuildParams p;
        p.max_triangles = 2000;
        p.max_depth = 10;
        p.memory_bytes = mb << 20;
        p.threads = threads;
        const std::string asset = dir.file(name + "-" + std::to_string(mb) + "-" + std::to_string(threads) + ".lfo");
        const OctreeBuildResult r = build_octree(dir.file(name + ".ply"), asset, p);
        EXPECT_FALSE(r.soup.external);
        if (root_split) *root_split = r.soup.root_split;
        std::ifstream f(asset, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    };
    for (const char* name : {"dragon", "outlier"}) {
        SCOPED_TRACE(name);
        const bool guessed_right = std::string(name) == "dragon";
        const std::string whole = build(name, 256, 2, nullptr);
        ASSERT_GT(whole.size(), 1000u);
        for (int threads : {1, 2}) {
            bool root_split = !guessed_right;
            EXPECT_TRUE(build(name, 4, threads, &root_split) == whole) << threads;
            EXPECT_EQ(root_split, guessed_right) << threads;
        }
        EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()),
                  guessed_right ? 5 : 8);  // inputs and assets only: no temporary file left
    }
    // A bad vertex index three quarters into the faces, while the guessed split is writing octant files:
    // the error names the input and the face, and neither the asset nor any temporary file is left.
    {
        std::string bytes = [&] {
            std::ifstream f(dir.file("dragon.ply"), std::ios::binary);
            return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
        }();
        const std::size_t data = bytes.find("end_header\n") + 11;
        ASSERT_EQ(bytes.size(), data + mesh.positions.size() * 12 + mesh.triangle_count() * 13);  // float xyz, uchar 3 + 3 int
        const std::size_t face = mesh.triangle_count() * 3 / 4;
        const std::uint32_t bad = 0x7fffffff;
        std::memcpy(bytes.data() + data + mesh.positions.size() * 12 + face * 13 + 1, &bad, 4);
        ScratchDir cut_dir("octree-root-split-cut");
        const std::string cut = cut_dir.file("cut.ply");
        std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        OctreeBuildParams p;
        p.max_triangles = 2000;
        p.memory_bytes = 4u << 20;
        try {
            build_octree(cut, cut_dir.file("cut.lfo"), p);
            ADD_FAILURE() << "a truncated input was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("cut.ply"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("face " + std::to_string(face)), std::string::npos) << e.what();
        }
        EXPECT_EQ(std::distance(fs::directory_iterator(cut_dir.path()), fs::directory_iterator()), 1);  // the input
    }
    // The unused vertex counts in the header, not in the bounds.
    OctreeStore a(dir.file("dragon-256-2.lfo")), c(dir.file("outlier-256-2.lfo"));
    EXPECT_EQ(c.header().input_vertices, a.header().input_vertices + 1);
    EXPECT_EQ(c.header().bounds.min, a.header().bounds.min);
    EXPECT_EQ(c.header().bounds.max, a.header().bounds.max);
    EXPECT_EQ(c.header().root_size, a.header().root_size);
}

TEST(OctreeBuild, CancelDuringATwoThreadSplitLeavesNoFiles) {
    // Cancelled at the first, second and fifth progress report of the root's streaming split, while
    // the second thread is writing its half.
    for (int n : {1, 2, 5}) {
        ScratchDir dir("octree-cancel-split");
        OctreeBuildParams p;
        p.max_triangles = 300;
        p.memory_bytes = 4u << 20;
        p.threads = 2;
        CancelAfter cancel(n);
        try {
            build_octree(shared_data("scan-dragon/dragon_vrip_res2.ply"), dir.file("out.lfo"), p, &cancel);
            FAIL() << "not cancelled at " << n;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::cancelled) << n;
        }
        EXPECT_EQ(files_in(dir.path()), 0u) << n;
        EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 0) << n;
    }
}

TEST(OctreeBuild, CorruptInputAndAssetStopWithAClearError) {
    ScratchDir dir("octree-corrupt");
    const std::string bad = dir.file("nan.ply");
    std::ofstream(bad) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                          "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n";
    try {
        build_octree(bad, dir.file("out.lfo"));
        FAIL() << "NaN accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("nan.ply"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir.file("out.lfo")));
    EXPECT_EQ(files_in(dir.path()), 1u);  // only the input

    // A valid asset, then damaged copies of it.
    OctreeBuildParams p;
    p.max_triangles = 500;
    build_octree(shared_data("scan-dragon/dragon_vrip_res4.ply"), dir.file("good.lfo"), p);
    std::ifstream in(dir.file("good.lfo"), std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
    const std::string cut = dir.file("cut.lfo");
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() - 100));
    EXPECT_THROW(OctreeStore{cut}, Error);
    std::vector<char> flipped = bytes;
    flipped[16 + 8] ^= 0x7f;  // the first node chunk's triangle count (after the 16-byte lead)
    const std::string damaged = dir.file("damaged.lfo");
    std::ofstream(damaged, std::ios::binary).write(flipped.data(), static_cast<std::streamsize>(flipped.size()));
    OctreeStore store(damaged);
    bool thrown = false;
    try {
        for (std::uint32_t i = 0; i < store.nodes().size(); ++i) {
            store.load(i, false);
            if (store.node(i).is_leaf()) store.load(i, true);
        }
    } catch (const Error& e) {
        thrown = true;
        EXPECT_EQ(e.kind(), Error::Kind::format);
        EXPECT_NE(std::string(e.what()).find("damaged.lfo"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(thrown);
    EXPECT_THROW(level_cut(store, store.level_count()), Error);
}

// Before version 2 the asset had no checksum: 29 of 38 byte-flipped assets passed `octree info` and
// 24 `extract`. Now a flipped byte anywhere (lead, chunks, index, footer) stops the open or the load.
TEST(OctreeBuild, EveryFlippedByteIsDetected) {
    ScratchDir dir("octree-flip");
    OctreeBuildParams p;
    p.max_triangles = 2000;
    build_octree(shared_data("color-open3d-small/color.ply"), dir.file("good.lfo"), p);
    std::ifstream in(dir.file("good.lfo"), std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
    ASSERT_GT(bytes.size(), 1000u);
    std::vector<std::size_t> positions;
    for (std::size_t i = 0; i < 16; ++i) positions.push_back(i);  // the lead: magic, version, byte order
    for (std::size_t i = 16; i < bytes.size(); i += bytes.size() / 150) positions.push_back(i);
    // The index (container header, header fields, node table) densely: the footer says where it starts.
    std::uint64_t index_offset = 0;
    std::memcpy(&index_offset, bytes.data() + bytes.size() - 16, 8);
    ASSERT_LT(index_offset, bytes.size() - 16);
    for (std::size_t i = index_offset; i < index_offset + 200 && i < bytes.size() - 16; ++i) positions.push_back(i);
    for (std::size_t i = index_offset + 200; i < bytes.size() - 16; i += 7) positions.push_back(i);
    for (std::size_t i = bytes.size() - 16; i < bytes.size(); ++i) positions.push_back(i);  // the footer
    const std::string damaged = dir.file("damaged.lfo");
    std::size_t detected = 0;
    for (const std::size_t at : positions) {
        std::vector<char> flipped = bytes;
        flipped[at] ^= 0x10;
        std::ofstream(damaged, std::ios::binary).write(flipped.data(), static_cast<std::streamsize>(flipped.size()));
        try {
            OctreeStore store(damaged);
            for (std::uint32_t i = 0; i < store.nodes().size(); ++i) {
                store.load(i, false);
                if (store.node(i).is_leaf()) store.load(i, true);
            }
            ADD_FAILURE() << "byte " << at << " of " << bytes.size() << " flipped without an error";
        } catch (const Error& e) {
            ++detected;
            EXPECT_NE(std::string(e.what()).find("damaged.lfo"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(detected, positions.size());
    // The undamaged asset still opens and loads.
    OctreeStore good(dir.file("good.lfo"));
    for (std::uint32_t i = 0; i < good.nodes().size(); ++i) good.load(i, false);
}

// A crafted asset (checksums recomputed) whose node chunk offset is near 2^64: offset + bytes wrapped
// below the table offset, passed the bounds check, and the chunk was then read into a buffer sized by
// the lying byte count.
TEST(OctreeBuild, ChunkOffsetThatWrapsAroundIsRefused) {
    ScratchDir dir("octree-wrap");
    build_octree(shared_data("color-open3d-small/color.ply"), dir.file("good.lfo"));
    std::ifstream in(dir.file("good.lfo"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    // Version 3: the footer locates the index; its NODE section (the second) holds the records.
    ASSERT_GT(bytes.size(), ooc::kAssetLeadBytes + ooc::kAssetFooterBytes);
    std::uint64_t index = 0;
    std::memcpy(&index, bytes.data() + bytes.size() - ooc::kAssetFooterBytes, 8);
    // Container: 32-byte header, then per section a tag, a length and a CRC (12 bytes) before the payload.
    const std::size_t table = index + 32 + 12 + lodforge::test::seal_u32(bytes, index + 32 + 4) + 12;
    ASSERT_EQ(std::string(bytes.data() + table - 12, 4), "NODE");
    OctreeNode root;
    std::memcpy(&root, bytes.data() + table, sizeof root);
    root.mesh_bytes = std::uint64_t{1} << 40;
    root.mesh_offset = ~std::uint64_t{0} - root.mesh_bytes + 17;  // the sum wraps to 16
    std::memcpy(bytes.data() + table, &root, sizeof root);
    lodforge::test::seal_lfo(bytes);
    std::ofstream(dir.file("wrap.lfo"), std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    try {
        OctreeStore store(dir.file("wrap.lfo"));
        (void)store.load(0, false);
        ADD_FAILURE() << "the wrapped offset was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("wrap.lfo: damaged octree asset: node 0 points past the data section"),
                  std::string::npos)
            << e.what();
    }
}

// Versions 1 (no checksums) and 2 (header and table before the container index) are refused with a
// message that says to rebuild; a newer version is refused as unknown.
TEST(OctreeBuild, OlderAssetVersionsAreRefusedWithARebuildHint) {
    ScratchDir dir("octree-v1");
    build_octree(shared_data("color-open3d-small/color.ply"), dir.file("a.lfo"));
    for (const std::uint32_t version : {1u, 2u, 4u}) {
        std::fstream f(dir.file("a.lfo"), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(8);
        f.write(reinterpret_cast<const char*>(&version), 4);
        f.close();
        try {
            OctreeStore store(dir.file("a.lfo"));
            FAIL() << "a version-" << version << " asset opened";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::unsupported);
            const std::string m = e.what();
            EXPECT_NE(m.find("a.lfo"), std::string::npos) << m;
            EXPECT_NE(m.find("version " + std::to_string(version)), std::string::npos) << m;
            EXPECT_EQ(m.find("rebuild it") != std::string::npos, version < 3) << m;
        }
    }
}

}  // namespace
}  // namespace lodforge

namespace lodforge {
namespace {

TEST(OctreeBuild, OddNonManifoldEdgesKeepEveryUseInEveryCut) {
    // Three pages of a book share the spine 0-1; pages lie in different octants so they land in
    // different leaves. A per-node rule would drop or keep the spine unevenly; it must keep 3 uses.
    ScratchDir dir("octree-book");
    const std::string ply = dir.file("book.ply");
    std::ofstream(ply) << "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                          "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
                          "0 0 -1\n0 0 1\n1 0 0\n-0.5 0.9 0\n-0.5 -0.9 0\n3 0 1 2\n3 1 0 3\n3 0 1 4\n";
    OctreeBuildParams p;
    p.max_triangles = 1;
    p.max_depth = 6;
    const OctreeBuildResult r = build_octree(ply, dir.file("book.lfo"), p);
    EXPECT_EQ(r.soup.odd_non_manifold_edges.size(), 1u);
    OctreeStore store(dir.file("book.lfo"));
    EXPECT_GE(store.stats().leaves, 3u);
    std::mt19937 rng(11);
    for (int trial = 0; trial < 12; ++trial) {
        const Cut cut = trial < store.level_count() ? level_cut(store, trial) : random_cut(store, rng);
        std::vector<std::uint64_t> keys;
        const Mesh m = extract_mesh(store, cut, nullptr, &keys);
        int spine = 0;
        for (std::size_t t = 0; t < m.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t a = keys[m.indices[3 * t + k]], b = keys[m.indices[3 * t + (k + 1) % 3]];
                spine += (std::min(a, b) == 0 && std::max(a, b) == 1);
            }
        EXPECT_EQ(spine, 3) << "trial " << trial;
    }
}


// Builds an asset from a mesh written to a PLY in `dir`.
OctreeStore build_from(const ScratchDir& dir, const Mesh& m, std::size_t max_tris, int depth) {
    write_ply(m, dir.file("in.ply"));
    OctreeBuildParams p;
    p.max_triangles = max_tris;
    p.max_depth = depth;
    build_octree(dir.file("in.ply"), dir.file("in.lfo"), p);
    return OctreeStore(dir.file("in.lfo"));
}

Mesh flat_grid(int n) {
    Mesh m;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) m.positions.push_back({x / float(n - 1), y / float(n - 1), 0.f});
    for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
            const std::uint32_t a = static_cast<std::uint32_t>(y * n + x), b = a + 1, c = a + static_cast<std::uint32_t>(n), d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    return m;
}

double triangle_area(const Mesh& m, std::size_t t) {
    const Vec3f a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]], c = m.positions[m.indices[3 * t + 2]];
    return 0.5 * length(cross(b - a, c - a));
}

// Issue #32 row 10: a node's mesh is never larger than what it replaces, so no level has more
// triangles than the level below (one triangle used to become a fan of 3, a tetrahedron of 4 one of 8).
// Issue #27: levels an artist would ship shrink as asked. Where level L replaces nodes of level L - 1 (a
// parent instead of its children), the parents keep 30-50 % of their children's triangles (the default
// ratio 0.35; measured 35-37 %). Nodes shown at both levels (a leaf beside deeper siblings) are counted
// apart: they cannot change. Before the level ratio the bunny's leaves kept 18 % of the input and its
// coarse levels 45-56 %, the root 12 %. (Lucy's level 4 keeps 59 %: the depth-1 cells' cut lines, at full
// resolution for crack-free mixed cuts, are most of it.)
TEST(OctreeBuild, LevelsKeepTheAskedShareOfTheNodesTheyReplace) {
    for (const char* name : {"scan-bunny/bun_zipper.ply", "color-open3d-frag115/frag_115.ply"}) {
        SCOPED_TRACE(name);
        Built b("octree-ratio", shared_data(name), 2000, 8);
        OctreeStore store(b.asset);
        auto triangles = [&](const CutNode& c) {
            const OctreeNode& n = store.node(c.node);
            return std::uint64_t{c.raw ? n.raw_triangles : n.mesh_triangles};
        };
        ASSERT_GE(store.level_count(), 4);
        for (int level = 1; level < store.level_count(); ++level) {
            std::map<std::uint32_t, std::uint64_t> below, here;
            for (const CutNode& c : level_cut(store, level - 1)) below[c.node] += triangles(c);
            for (const CutNode& c : level_cut(store, level)) here[c.node] += triangles(c);
            std::uint64_t replaced = 0, replacing = 0;
            for (const auto& [node, t] : below)
                if (!here.count(node) || level == 1) replaced += t;  // level 1 replaces the raw leaves
            for (const auto& [node, t] : here)
                if (!below.count(node) || level == 1) replacing += t;
            ASSERT_GT(replaced, 0u) << level;
            const double share = double(replacing) / double(replaced);
            std::printf("%s level %d: %llu triangles replace %llu (%.0f %%)\n", name, level,
                        static_cast<unsigned long long>(replacing), static_cast<unsigned long long>(replaced), 100 * share);
            EXPECT_GE(share, 0.3) << level;
            EXPECT_LE(share, 0.5) << level;
        }
    }
}

TEST(OctreeBuild, NoLevelHasMoreTrianglesThanTheLevelBelow) {
    Mesh triangle;
    triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    triangle.indices = {0, 1, 2};
    Mesh tetrahedron;
    tetrahedron.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tetrahedron.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    const std::vector<std::tuple<const char*, Mesh, std::size_t, int>> cases = {
        {"triangle", triangle, 10, 4}, {"tetrahedron", tetrahedron, 1, 4}, {"tetrahedron, one leaf", tetrahedron, 10, 4},
        {"grid", flat_grid(40), 100, 8}, {"bunny", read_ply(shared_data("scan-bunny/bun_zipper.ply")), 500, 8}};
    for (const auto& [name, mesh, max_tris, depth] : cases) {
        SCOPED_TRACE(name);
        ScratchDir dir("octree-grow");
        OctreeStore store = build_from(dir, mesh, max_tris, depth);
        const std::vector<std::uint64_t>& per_level = store.stats().triangles_per_level;
        ASSERT_GE(per_level.size(), 2u);
        EXPECT_EQ(per_level[0], mesh.triangle_count());
        for (std::size_t level = 1; level < per_level.size(); ++level) {
            EXPECT_LE(per_level[level], per_level[level - 1]) << "level " << level;
            EXPECT_EQ(extract_mesh(store, level_cut(store, static_cast<int>(level))).triangle_count(), per_level[level]);
        }
    }
}

// Issue #32 row 10: on a flat grid, fans must not make zero-area triangles or non-manifold edges.
TEST(OctreeBuild, FlatGridLevelsHaveNoZeroAreaTrianglesOrNonManifoldEdges) {
    const Mesh grid = flat_grid(150);
    const double input_area = triangle_area(grid, 0);
    ScratchDir dir("octree-grid");
    OctreeStore store = build_from(dir, grid, 2000, 12);
    ASSERT_GE(store.level_count(), 3);
    for (int level = 1; level < store.level_count(); ++level) {
        const Mesh m = extract_mesh(store, level_cut(store, level));
        std::size_t flat = 0;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) flat += triangle_area(m, t) < 1e-3 * input_area;
        EXPECT_EQ(flat, 0u) << "level " << level << " of " << m.triangle_count() << " triangles";
        EXPECT_EQ(edge_counts(m).non_manifold, 0u) << "level " << level;
    }
}

// Issue #27: a node's fans stay on the surface they replace. A fan to one representative of a node
// holding several separate sheets (both sides of a tail, a claw beside a leg) crossed the empty space
// between them: on this dragon the level-1 fans reached 6.0 % of the diagonal away from the surface, 16
// times the Hausdorff distance of an edge collapse to the same size (13.6 times at level 2). What is
// left is lost relief inside one part (the reference side), which one apex per part cannot keep.
TEST(OctreeBuild, FansStayNearTheSurfaceTheyReplace) {
    const std::string input = shared_data("scan-dragon/dragon_vrip_res3.ply");
    const Mesh m = read_ply(input);
    Built b("octree-spikes", input, 300, 8);
    OctreeStore store(b.asset);
    ASSERT_GE(store.level_count(), 4);
    for (int level = 1; level <= 2; ++level) {
        const Mesh lm = extract_mesh(store, level_cut(store, level));
        SimplifyParams sp;
        sp.target_triangles = lm.triangle_count();
        const SimplifyResult collapse = simplify(m, sp);
        DistanceParams dp;
        dp.vertex_errors = false;
        const DistanceResult octree = compare(m, lm, dp);
        const double reference = compare(m, collapse.mesh, dp).hausdorff;
        std::printf("level %d: %zu triangles, fans to surface %.3g %% of the diagonal, surface to fans %.3g %%, "
                    "edge collapse Hausdorff %.3g %%\n",
                    level, lm.triangle_count(), 100 * octree.test_to_reference.max / octree.diagonal,
                    100 * octree.reference_to_test.max / octree.diagonal, 100 * reference / octree.diagonal);
        EXPECT_LE(octree.test_to_reference.max, 8 * reference) << "level " << level;
    }
}

}  // namespace
}  // namespace lodforge

namespace lodforge {
namespace {

// Per-face materials (a PLY face `texnumber`) ride in the soup records and split vertices at material
// borders: every level of the truck keeps each of its materials, and a sphere painted in two halves
// keeps both halves, its border crack-free, at every level and at mixed levels.
TEST(OctreeBuild, EveryMaterialSurvivesAtEveryLevel) {
    ScratchDir dir("octree-materials");
    WriteOptions w;
    w.ply_face_materials = true;

    const Mesh truck = read_mesh(shared_data("tex-cesium-milk-truck/CesiumMilkTruck.gltf"));
    const std::set<std::uint32_t> truck_materials(truck.face_materials.begin(), truck.face_materials.end());
    ASSERT_GT(truck_materials.size(), 1u);
    write_mesh(truck, dir.file("truck.ply"), w);
    OctreeBuildParams p;
    p.max_triangles = 500;
    build_octree(dir.file("truck.ply"), dir.file("truck.lfo"), p);
    OctreeStore store(dir.file("truck.lfo"));
    ASSERT_TRUE(store.header().layout.material);
    ASSERT_GE(store.level_count(), 3);
    for (int level = 0; level < store.level_count(); ++level) {
        const Mesh m = extract_mesh(store, level_cut(store, level));
        EXPECT_EQ(level_materials(m), truck_materials) << "level " << level;
        ASSERT_EQ(m.texcoords.size(), 1u);
    }
    const std::size_t coarsest = extract_mesh(store, level_cut(store, store.level_count() - 1)).triangle_count();
    EXPECT_LT(coarsest, truck.triangle_count());  // the levels do simplify

    Mesh sphere = test::icosphere(5);
    sphere.face_materials.resize(sphere.triangle_count());
    for (std::size_t t = 0; t < sphere.triangle_count(); ++t)
        sphere.face_materials[t] = sphere.positions[sphere.indices[3 * t]].z > 0 ? 1u : 0u;
    write_mesh(sphere, dir.file("sphere.ply"), w);
    p.max_triangles = 300;
    build_octree(dir.file("sphere.ply"), dir.file("sphere.lfo"), p);
    OctreeStore s(dir.file("sphere.lfo"));
    ASSERT_GE(s.level_count(), 3);
    for (int level = 0; level < s.level_count(); ++level) {
        const Mesh m = extract_mesh(s, level_cut(s, level));
        EXPECT_EQ(level_materials(m), (std::set<std::uint32_t>{0, 1})) << "level " << level;
        EXPECT_EQ(welded_border_edges(m), 0u) << "level " << level;
    }
    std::mt19937 rng(7);
    for (int i = 0; i < 4; ++i) {
        const Mesh m = extract_mesh(s, random_cut(s, rng));
        EXPECT_EQ(level_materials(m), (std::set<std::uint32_t>{0, 1}));
        EXPECT_EQ(welded_border_edges(m), 0u);
    }
}

}  // namespace
}  // namespace lodforge
