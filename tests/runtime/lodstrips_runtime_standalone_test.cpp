// The runtime header alone: this executable includes lodstrips_runtime.h, the standard library and
// GoogleTest, and links nothing of LodForge. It reads files the core wrote (lodstrips_fixture).
#include "lodforge/runtime/lodstrips_runtime.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using Tri = std::array<std::uint32_t, 3>;

std::string fixture(const std::string& name) { return std::string(LODSTRIPS_FIXTURE_DIR) + "/" + name; }

std::map<std::size_t, std::vector<Tri>> read_reference(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    auto u32 = [&] {
        std::uint32_t v = 0;
        in.read(reinterpret_cast<char*>(&v), 4);
        return v;
    };
    std::map<std::size_t, std::vector<Tri>> out;
    const std::uint32_t levels = u32();
    for (std::uint32_t i = 0; i < levels && in; ++i) {
        const std::uint32_t k = u32(), n = u32();
        std::vector<Tri>& tris = out[k];
        tris.resize(n);
        for (Tri& t : tris) t = {u32(), u32(), u32()};
    }
    return out;
}

std::vector<Tri> drawn(const lodstrips::LodStrips& rt) {
    std::vector<std::uint32_t> list;
    rt.triangles(list);
    std::vector<Tri> t;
    for (std::size_t i = 0; i < list.size(); i += 3) {
        std::uint32_t a = list[i], b = list[i + 1], c = list[i + 2];
        if (b < a && b < c) t.push_back({b, c, a});
        else if (c < a && c < b) t.push_back({c, a, b});
        else t.push_back({a, b, c});
    }
    std::sort(t.begin(), t.end());
    return t;
}

std::vector<std::uint32_t> buffer(const lodstrips::LodStrips& rt) {
    return std::vector<std::uint32_t>(rt.indices(), rt.indices() + rt.index_count());
}

class Standalone : public ::testing::TestWithParam<std::string> {};

TEST_P(Standalone, LevelsMatchTheIndexedMeshAndWalksAgree) {
    lodstrips::LodStrips rt;
    std::string why;
    ASSERT_TRUE(rt.load_file(fixture(GetParam() + ".lodstrips"), &why)) << why;
    const auto reference = read_reference(fixture(GetParam() + ".ref"));
    ASSERT_GT(reference.size(), 10u);
    for (const auto& [k, tris] : reference) {
        rt.go_to_level(k);
        ASSERT_TRUE(drawn(rt) == tris) << "level " << k << ": triangles or winding differ";
        EXPECT_EQ(rt.triangle_count(), tris.size());
    }
    // Coarsen then refine: byte-identical.
    rt.go_to_level(0);
    const std::vector<std::uint32_t> full = buffer(rt);
    rt.go_to_lod(0.0);
    EXPECT_EQ(rt.level(), rt.collapse_count());
    rt.go_to_lod(1.0);
    EXPECT_EQ(buffer(rt), full);
    // Random jumps agree with a linear walk; changed spans update a stale copy.
    lodstrips::LodStrips walk;
    ASSERT_TRUE(walk.load_file(fixture(GetParam() + ".lodstrips")));
    std::mt19937 rng(1);
    std::vector<std::uint32_t> engine = buffer(rt);
    for (int i = 0; i < 10; ++i) {
        const std::size_t k = std::uniform_int_distribution<std::size_t>(0, rt.collapse_count())(rng);
        rt.clear_changes();
        rt.go_to_level(k);
        for (const auto& s : rt.changes())
            std::copy(rt.indices() + s.offset, rt.indices() + s.offset + s.count, engine.begin() + s.offset);
        EXPECT_EQ(engine, buffer(rt));
        while (walk.level() < k) walk.go_to_level(walk.level() + 1);
        while (walk.level() > k) walk.go_to_level(walk.level() - 1);
        ASSERT_EQ(buffer(walk), buffer(rt)) << "level " << k;
    }
}

TEST_P(Standalone, CorruptFilesAreRejected) {
    std::ifstream in(fixture(GetParam() + ".lodstrips"), std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 100u);
    lodstrips::LodStrips rt;
    for (std::size_t n = 0; n < bytes.size(); n += 1 + n / 64) {
        std::string why;
        ASSERT_FALSE(rt.load_memory(bytes.data(), n, &why)) << n;
        EXPECT_FALSE(why.empty());
    }
    std::mt19937 rng(2);
    for (int i = 0; i < 100; ++i) {
        std::vector<std::uint8_t> b = bytes;
        b[std::uniform_int_distribution<std::size_t>(0, b.size() - 1)(rng)] ^= 0x5A;
        ASSERT_FALSE(rt.load_memory(b.data(), b.size()));
    }
    EXPECT_FALSE(rt.load_file(fixture("does-not-exist.lodstrips")));
}

INSTANTIATE_TEST_SUITE_P(CoreWritten, Standalone, ::testing::Values("dragon_res4", "spot"));

}  // namespace
