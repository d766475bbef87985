// The .lodstrips format: round trip, storage, atomic writes, corrupt and lying files.
#include "strips/lodstrips_test_util.h"

#include "lodforge/error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <cstdio>
#include <random>

namespace lodforge {
namespace {

using test::built;

void expect_same_data(const lodstrips::Data& a, const lodstrips::Data& b) {
    EXPECT_EQ(a.vertex_count, b.vertex_count);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.normals, b.normals);
    EXPECT_EQ(a.colors, b.colors);
    EXPECT_EQ(a.texcoords, b.texcoords);
    EXPECT_EQ(a.materials.size(), b.materials.size());
    EXPECT_EQ(a.restart, b.restart);
    EXPECT_EQ(a.strip_offsets, b.strip_offsets);
    EXPECT_EQ(a.strip_materials, b.strip_materials);
    EXPECT_EQ(a.initial_indices, b.initial_indices);
    EXPECT_EQ(a.collapse_begin, b.collapse_begin);
    EXPECT_EQ(a.targets, b.targets);
    EXPECT_EQ(a.rewrite_begin, b.rewrite_begin);
    EXPECT_EQ(a.rewrite_positions, b.rewrite_positions);
    EXPECT_EQ(a.removal_begin, b.removal_begin);
    ASSERT_EQ(a.removals.size(), b.removals.size());
    for (std::size_t i = 0; i < a.removals.size(); ++i) {
        EXPECT_EQ(a.removals[i].strip, b.removals[i].strip);
        EXPECT_EQ(a.removals[i].pos, b.removals[i].pos);
        EXPECT_EQ(a.removals[i].count, b.removals[i].count);
        EXPECT_EQ(a.removals[i].type, b.removals[i].type);
    }
    EXPECT_EQ(a.triangles, b.triangles);
}

TEST(LodStripsFormat, RoundTripKeepsEveryRecord) {
    for (const char* name : {"spot", "dragon_res4"})
        for (StripJoin join : {StripJoin::restart, StripJoin::degenerate}) {
            SCOPED_TRACE(name);
            const lodstrips::Data& d = built(name, join).build.data;
            const std::vector<std::uint8_t> bytes = encode_lodstrips(d);
            lodstrips::Data back;
            std::string why;
            ASSERT_TRUE(lodstrips::decode(bytes.data(), bytes.size(), back, &why)) << why;
            expect_same_data(d, back);
            EXPECT_EQ(back.colors_8bit, d.colors_8bit);
            EXPECT_EQ(encode_lodstrips(back), bytes);
            EXPECT_EQ(lodstrips_storage(d).file_bytes, bytes.size());
        }
}

TEST(LodStripsFormat, MaterialsAndTexturePathsSurvive) {
    const lodstrips::Data& d = built("spot", StripJoin::restart).build.data;
    ASSERT_FALSE(d.materials.empty());
    const std::vector<std::uint8_t> bytes = encode_lodstrips(d);
    lodstrips::Data back;
    ASSERT_TRUE(lodstrips::decode(bytes.data(), bytes.size(), back, nullptr));
    ASSERT_EQ(back.materials.size(), d.materials.size());
    EXPECT_EQ(back.materials[0].name, d.materials[0].name);
    EXPECT_EQ(back.materials[0].base_color_texture, d.materials[0].base_color_texture);
    EXPECT_FALSE(back.materials[0].base_color_texture.empty()) << "Spot's texture is found beside the OBJ";
}

TEST(LodStripsFormat, StorageRatioToTheIndexedMeshIsBelowTwo) {
    for (const auto& [name, join] : {std::pair{"bunny", StripJoin::restart}, std::pair{"bunny", StripJoin::degenerate},
                                     std::pair{"frag_115", StripJoin::restart}}) {
        {
            const lodstrips::Data& d = built(name, join).build.data;
            const LodStripsStorage st = lodstrips_storage(d);
            EXPECT_EQ(st.indexed_mesh_bytes, st.vertex_bytes + 12u * d.triangles[0]);
            EXPECT_LT(st.ratio_to_indexed, 2.0) << name;
            EXPECT_GT(st.ratio_to_indexed, 1.0) << name << ": the strips and changes cost something";
            std::printf("%s %s: %.3f\n", name, join == StripJoin::restart ? "restart" : "degenerate", st.ratio_to_indexed);
        }
    }
}

TEST(LodStripsFormat, WriteReadThroughFilesAndErrorsNameTheFile) {
    test::ScratchDir dir("lodstrips-io");
    const lodstrips::Data& d = built("dragon_res4", StripJoin::restart).build.data;
    const std::string path = dir.file("res4.lodstrips");
    write_lodstrips(d, path);
    expect_same_data(read_lodstrips(path), d);
    try {
        read_lodstrips(dir.file("missing.lodstrips"));
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::io);
        EXPECT_NE(std::string(e.what()).find("missing.lodstrips"), std::string::npos);
    }
    EXPECT_THROW(write_lodstrips(d, dir.file("no/such/dir/x.lodstrips")), Error);
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path())) files += entry.is_regular_file();
    EXPECT_EQ(files, 1u) << "a failed write leaves no temporary";
    {
        std::ofstream bad(dir.file("bad.lodstrips"), std::ios::binary);
        bad << "LODSTRPS but not really";
    }
    try {
        read_lodstrips(dir.file("bad.lodstrips"));
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::format);
        EXPECT_NE(std::string(e.what()).find("bad.lodstrips"), std::string::npos);
    }
}

bool accepted(const std::vector<std::uint8_t>& bytes) {
    lodstrips::LodStrips rt;
    std::string why;
    const bool ok = rt.load_memory(bytes.data(), bytes.size(), &why);
    EXPECT_TRUE(ok || !why.empty());
    return ok;
}

// Recomputes the header and section checksums, so the checks behind them are reached.
void fix_checksums(std::vector<std::uint8_t>& b) {
    auto put = [&](std::size_t at, std::uint32_t v) {
        for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
    };
    auto get = [&](std::size_t at) {
        return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
               std::uint32_t(b[at + 3]) << 24;
    };
    put(20, lodstrips::detail::crc32(b.data(), 20));
    std::size_t at = 32;
    for (int i = 0; i < 5 && at + 12 <= b.size(); ++i) {
        const std::uint32_t len = get(at + 4);
        if (at + 12 + len > b.size()) return;
        put(at + 8, lodstrips::detail::crc32(b.data() + at + 12, len));
        at += 12 + len;
    }
}

TEST(LodStripsFormat, EveryTruncatedPrefixIsRejected) {
    const std::vector<std::uint8_t> bytes = encode_lodstrips(built("dragon_res4", StripJoin::degenerate).build.data);
    ASSERT_TRUE(accepted(bytes));
    for (std::size_t n = 0; n < bytes.size(); ++n) {
        lodstrips::LodStrips rt;
        std::string why;
        ASSERT_FALSE(rt.load_memory(bytes.data(), n, &why)) << "prefix of " << n << " bytes";
        ASSERT_FALSE(why.empty());
    }
    // A prefix whose header is patched to announce its own size still fails (sections cut short).
    for (std::size_t n : {std::size_t(40), bytes.size() / 2, bytes.size() - 1}) {
        std::vector<std::uint8_t> prefix(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
        for (int i = 0; i < 8; ++i) prefix[24 + i] = static_cast<std::uint8_t>(std::uint64_t(n) >> (8 * i));
        fix_checksums(prefix);
        EXPECT_FALSE(accepted(prefix)) << "patched prefix of " << n << " bytes";
    }
}

TEST(LodStripsFormat, RandomByteFlipsAreRejected) {
    const std::vector<std::uint8_t> bytes = encode_lodstrips(built("dragon_res4", StripJoin::restart).build.data);
    std::mt19937 rng(11);
    for (int i = 0; i < 400; ++i) {
        std::vector<std::uint8_t> b = bytes;
        const std::size_t at = std::uniform_int_distribution<std::size_t>(0, b.size() - 1)(rng);
        b[at] ^= static_cast<std::uint8_t>(std::uniform_int_distribution<int>(1, 255)(rng));
        ASSERT_FALSE(accepted(b)) << "flip at byte " << at;
    }
}

TEST(LodStripsFormat, FlipsBehindValidChecksumsNeverCrashTheRuntime) {
    // With checksums recomputed the record checks must catch what the CRC would have; whatever they
    // accept must be walkable over every level.
    const std::vector<std::uint8_t> bytes = encode_lodstrips(built("dragon_res4", StripJoin::restart).build.data);
    std::mt19937 rng(5);
    int rejected = 0;
    for (int i = 0; i < 300; ++i) {
        std::vector<std::uint8_t> b = bytes;
        for (int f = 0; f < 3; ++f) {
            const std::size_t at = std::uniform_int_distribution<std::size_t>(32, b.size() - 1)(rng);
            b[at] ^= static_cast<std::uint8_t>(std::uniform_int_distribution<int>(1, 255)(rng));
        }
        fix_checksums(b);
        lodstrips::LodStrips rt;
        if (!rt.load_memory(b.data(), b.size())) {
            ++rejected;
            continue;
        }
        rt.go_to_level(rt.collapse_count());
        rt.go_to_level(rt.collapse_count() / 2);
        rt.go_to_level(0);
        std::vector<std::uint32_t> tris;
        rt.triangles(tris);
        for (std::uint32_t v : tris) ASSERT_LT(v, rt.data().vertex_count);
    }
    EXPECT_GT(rejected, 200) << "most corruptions are caught by the record checks";
}

TEST(LodStripsFormat, LyingCountsAreRejectedBeforeAllocating) {
    std::vector<std::uint8_t> b = encode_lodstrips(built("dragon_res4", StripJoin::restart).build.data);
    // META starts at byte 44: flags varint, then the vertex count; announce 2^31 vertices.
    std::vector<std::uint8_t> lie(b.begin(), b.begin() + 45);
    const std::uint8_t big[5] = {0x80, 0x80, 0x80, 0x80, 0x08};
    std::size_t old_len = 1;
    while (b[45 + old_len - 1] & 0x80) ++old_len;
    lie.insert(lie.end(), big, big + 5);
    lie.insert(lie.end(), b.begin() + 45 + static_cast<std::ptrdiff_t>(old_len), b.end());
    const std::uint32_t meta_len = std::uint32_t(b[36]) | std::uint32_t(b[37]) << 8;
    const std::uint32_t new_len = meta_len + 5 - static_cast<std::uint32_t>(old_len);
    lie[36] = static_cast<std::uint8_t>(new_len), lie[37] = static_cast<std::uint8_t>(new_len >> 8);
    const std::uint64_t size = lie.size();
    for (int i = 0; i < 8; ++i) lie[24 + i] = static_cast<std::uint8_t>(size >> (8 * i));
    fix_checksums(lie);
    lodstrips::Data d;
    std::string why;
    EXPECT_FALSE(lodstrips::decode(lie.data(), lie.size(), d, &why));
    EXPECT_NE(why.find("VERT"), std::string::npos) << why;
}

}  // namespace
}  // namespace lodforge
