// The .mco file: round trip, and every truncated prefix and byte flip rejected with an Error.
#include "lodforge/error.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "mc_test_support.h"
#include "support/test_files.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

using namespace lodforge;

namespace {

std::vector<char> bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_bytes(const std::string& path, const std::vector<char>& b, std::size_t n) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(b.data(), std::streamsize(n));
}

McOctree small_tree() {
    McOctreeParams p;
    p.resolution = 10;
    return build_mc_octree(lodforge::test::sphere_points(2000, 1.f, true), p).tree;
}

}  // namespace

TEST(McOctreeIo, RoundTripKeepsEverything) {
    lodforge::test::ScratchDir dir("mco-io");
    const McOctree t = small_tree();
    write_mc_octree(t, dir.file("a.mco"));
    const McOctree r = read_mc_octree(dir.file("a.mco"));
    lodforge::test::expect_same_tree(t, r, "read back");
    const McExtraction a = extract_mc_octree(t, t.max_priority() / 2), b = extract_mc_octree(r, r.max_priority() / 2);
    EXPECT_EQ(a.mesh.indices, b.mesh.indices);
    EXPECT_EQ(a.mesh.positions, b.mesh.positions);
    // no temporary left beside the output
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path())) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
}

TEST(McOctreeIo, TruncatedPrefixesAndByteFlipsAreRejected) {
    lodforge::test::ScratchDir dir("mco-corrupt");
    write_mc_octree(small_tree(), dir.file("a.mco"));
    const std::vector<char> good = bytes_of(dir.file("a.mco"));
    ASSERT_GT(good.size(), 1000u);
    const std::string bad = dir.file("bad.mco");
    std::size_t step = std::max<std::size_t>(1, good.size() / 120);
    for (std::size_t n = 0; n < good.size(); n += (n < 64 ? 1 : step)) {
        write_bytes(bad, good, n);
        EXPECT_THROW(read_mc_octree(bad), Error) << "prefix of " << n << " bytes";
    }
    for (std::size_t pos = 0; pos < good.size(); pos += (pos < 64 ? 1 : step)) {
        std::vector<char> b = good;
        b[pos] = char(b[pos] ^ 0x10);
        write_bytes(bad, b, b.size());
        EXPECT_THROW(read_mc_octree(bad), Error) << "flip at byte " << pos;
    }
    try {
        write_bytes(bad, good, good.size() - 3);
        read_mc_octree(bad);
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.mco"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
    EXPECT_THROW(read_mc_octree(dir.file("missing.mco")), Error);
}

TEST(McOctreeIo, StructuralChecksCatchLyingTables) {
    McOctree t = small_tree();
    EXPECT_NO_THROW(validate_mc_octree(t, "t"));
    McOctree a = t;
    a.vertex_ids[3] = std::uint32_t(a.positions.size());
    EXPECT_THROW(validate_mc_octree(a, "t"), Error);
    McOctree b = t;
    b.nodes[0].first_child = std::uint32_t(b.nodes.size());
    EXPECT_THROW(validate_mc_octree(b, "t"), Error);
    McOctree c = t;
    std::swap(c.order[0], c.order[1]);
    EXPECT_THROW(validate_mc_octree(c, "t"), Error);
    McOctree d = t;  // a decreasing table would break the budget inverse's binary search
    d.triangle_counts[d.triangle_counts.size() / 2] = d.triangle_counts.back() + 1;
    EXPECT_THROW(validate_mc_octree(d, "t"), Error);
    McOctree e = t;
    e.cuts.back() -= 1;  // the last level must expand every node
    EXPECT_THROW(validate_mc_octree(e, "t"), Error);
}

TEST(McOctreeIo, ALyingTriangleTableCannotOverflowTheExtraction) {
    McOctree t = small_tree();
    const std::size_t i = t.max_priority() / 2;
    const std::uint64_t truth = t.triangle_counts[i];
    for (auto& c : t.triangle_counts) c = 1;  // passes validation: the table's length is all it can check
    EXPECT_NO_THROW(validate_mc_octree(t, "t"));
    EXPECT_EQ(extract_mc_octree(t, i).mesh.triangle_count(), truth);
}

// Files written before the section container (version 2: one body, FNV-1a) are still read.
TEST(McOctreeIo, ReadsVersionTwoFiles) {
    lodforge::test::ScratchDir dir("mco-v2");
    // AnimatedMorphCube at resolution 4, written by version 2 (its `mcoctree build` said: 102 nodes, 5 levels,
    // 36 priorities, 0..124 triangles).
    const std::string v2 = lodforge::test::suite_file("data/cube-v2.mco");
    const McOctree old = read_mc_octree(v2);
    EXPECT_EQ(old.nodes.size(), 102u);
    EXPECT_EQ(old.levels, 4u);  // root level 4: five levels, 0 to 4
    EXPECT_EQ(old.max_priority(), 36u);
    EXPECT_EQ(extract_mc_octree(old, old.max_priority()).mesh.triangle_count(), 124u);
    write_mc_octree(old, dir.file("v3.mco"));
    const std::vector<char> now = bytes_of(dir.file("v3.mco"));
    ASSERT_GT(now.size(), 12u);
    EXPECT_EQ(now[8], 3);  // the current version
    lodforge::test::expect_same_tree(old, read_mc_octree(dir.file("v3.mco")), "v2 written as v3");
    std::vector<char> b = bytes_of(v2);
    b[b.size() / 2] = char(b[b.size() / 2] ^ 0x10);
    write_bytes(dir.file("bad.mco"), b, b.size());
    try {
        (void)read_mc_octree(dir.file("bad.mco"));
        ADD_FAILURE() << "a flipped byte was read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
    }
}
