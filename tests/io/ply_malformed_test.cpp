// Bad input: every problem is a lodforge::Error of the right kind whose message names the file and
// says where; truncated files at every prefix throw and never crash.

#include "ply_test_util.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>

using namespace lodforge;
using namespace lodforge::test;

namespace {

const std::string kAsciiHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

// Writes `bytes` to a file, reads it, and checks kind and message; returns the message.
std::string expect_error(const std::string& bytes, Error::Kind kind, std::initializer_list<const char*> mentions = {}) {
    ScratchDir dir("ply-bad");
    const std::string path = dir.file("bad.ply");
    write_file(path, bytes);
    const CaughtError e = catch_error([&] { read_ply(path); });
    EXPECT_TRUE(e.thrown) << "no Error for:\n" << bytes.substr(0, 400);
    EXPECT_EQ(kind_name(e.kind), std::string(kind_name(kind))) << e.message;
    EXPECT_NE(e.message.find(path), std::string::npos) << "message does not name the file: " << e.message;
    for (const char* m : mentions) EXPECT_NE(e.message.find(m), std::string::npos) << "'" << m << "' not in: " << e.message;
    return e.message;
}

// A valid binary file exercising every path of the reader: normals, colours, a vertex list property,
// an unknown element with a list, polygons and wedge texcoords.
std::string rich_file(PlyEncoding enc) {
    TestElement v{"vertex",
                  {{"x"}, {"y"}, {"z"}, {"nx"}, {"ny"}, {"nz"}, {"red", PlyType::uint8}, {"green", PlyType::uint8},
                   {"blue", PlyType::uint8}, {"alpha", PlyType::uint8}, {"tags", PlyType::int16, PlyType::uint8}},
                  {}};
    for (int i = 0; i < 6; ++i)
        v.records.push_back({{i * 1.5}, {i * 0.25}, {-i * 1.0}, {0}, {0}, {1}, {double(i * 40)}, {7}, {8}, {255}, {1, 2}});
    TestElement other{"material", {{"name", PlyType::uint8, PlyType::uint32}, {"k", PlyType::float64}},
                      {{{65, 66, 67}, {0.5}}, {{}, {1.5}}}};
    TestElement f{"face", {{"vertex_indices", PlyType::int32, PlyType::uint8}, {"texcoord", PlyType::float32, PlyType::uint8}}, {}};
    f.records = {{{0, 1, 2}, {0, 0, 1, 0, 0, 1}}, {{2, 1, 3, 4}, {0.5, 0.5, 0.25, 0.25, 1, 1, 0.75, 0.5}}, {{4, 5, 0}, {}}};
    return encode_ply(enc, {v, other, f}, {"TextureFile t.png"});
}

}  // namespace

TEST(PlyMalformed, EmptyFile) { expect_error("", Error::Kind::format, {"empty file"}); }

TEST(PlyMalformed, MissingMagic) {
    expect_error("plx\nformat ascii 1.0\nend_header\n", Error::Kind::format, {"not a PLY file"});
    expect_error("PLY\n", Error::Kind::format, {"not a PLY file"});
    expect_error("plyformat ascii 1.0\n", Error::Kind::format, {"not a PLY file"});
    expect_error(std::string("\0\0\0\0\xff\xfe", 6), Error::Kind::format, {"not a PLY file"});
}

TEST(PlyMalformed, BadFormatLine) {
    expect_error("ply\nformat binary 1.0\nend_header\n", Error::Kind::format, {"line 2", "unknown format"});
    expect_error("ply\nformat ascii 2.0\nend_header\n", Error::Kind::format, {"line 2", "version"});
    expect_error("ply\nformat ascii\nend_header\n", Error::Kind::format, {"line 2"});
    expect_error("ply\nelement vertex 0\nend_header\n", Error::Kind::format, {"line 2", "before the format"});
    expect_error("ply\nend_header\n", Error::Kind::format, {"no format line"});
    expect_error("ply\nformat ascii 1.0\nformat ascii 1.0\nend_header\n", Error::Kind::format, {"second format"});
    expect_error("ply\nformat ascii 1.0\nelment vertex 1\nend_header\n", Error::Kind::format, {"line 3", "elment"});
}

TEST(PlyMalformed, UnknownTypeAndBadDeclarations) {
    const std::string h = "ply\nformat ascii 1.0\nelement vertex 1\n";
    expect_error(h + "property flot x\nend_header\n", Error::Kind::format, {"line 4", "unknown type 'flot'"});
    expect_error(h + "property list uchar int64 x\nend_header\n", Error::Kind::format, {"unknown type 'int64'"});
    expect_error(h + "property list float int vertex_indices\nend_header\n", Error::Kind::format, {"count type"});
    expect_error(h + "property float\nend_header\n", Error::Kind::format, {"line 4"});
    expect_error(h + "property float x\nproperty float x\nend_header\n", Error::Kind::format, {"declared twice"});
    expect_error("ply\nformat ascii 1.0\nproperty float x\nend_header\n", Error::Kind::format, {"before any element"});
    expect_error("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", Error::Kind::format, {"bad count '-1'"});
    expect_error("ply\nformat ascii 1.0\nelement vertex 1x\nend_header\n", Error::Kind::format, {"bad count"});
    expect_error("ply\nformat ascii 1.0\nelement vertex 0\nelement vertex 0\nend_header\n", Error::Kind::format,
                 {"declared twice"});
}

TEST(PlyMalformed, WrongPropertyTypes) {
    const std::string v = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string data = "0 0 0\n1 0 0\n0 1 0\n";
    expect_error(v + "element face 1\nproperty list uchar float vertex_indices\nend_header\n" + data + "3 0 1 2\n",
                 Error::Kind::format, {"vertex_indices", "list of integers"});
    expect_error(v + "element face 1\nproperty int vertex_indices\nend_header\n" + data + "0\n", Error::Kind::format,
                 {"vertex_indices", "scalar"});
    expect_error(v + "element face 1\nproperty int flags\nend_header\n" + data + "0\n", Error::Kind::format,
                 {"no vertex_indices"});
    expect_error(v + "element face 1\nproperty list uchar int vertex_indices\nproperty float texcoord\nend_header\n" + data +
                     "3 0 1 2 0.5\n",
                 Error::Kind::format, {"texcoord"});
    expect_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\n"
                 "property float z\nend_header\n1 0 0 0\n",
                 Error::Kind::format, {"'x'", "list"});
    expect_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
                 Error::Kind::format, {"no x, y, z"});
    expect_error(v + "end_header\n" + data.substr(0, 6), Error::Kind::format, {"'vertex' announces 3 records"});
    expect_error(v + "end_header\n0.5 0 0\n1 0 0\n0 1", Error::Kind::format, {"'vertex' record 2", "line 10", "truncated"});
}

TEST(PlyMalformed, NoVertexElementIsInvalidForAMesh) {
    expect_error("ply\nformat ascii 1.0\nelement thing 0\nend_header\n", Error::Kind::invalid, {"no vertex element"});
}

TEST(PlyMalformed, NoEndHeader) {
    expect_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", Error::Kind::format, {"end_header"});
    expect_error("ply\nformat binary_little_endian 1.0\nelement vertex 1\n" + std::string(70000, '\x01'),
                 Error::Kind::format, {"line 4", "64 KiB"});
    expect_error("ply", Error::Kind::format, {"end_header"});
}

TEST(PlyMalformed, HeaderCountLiesAreCaughtBeforeAllocating) {
    // 4e9 vertices in a 100-byte file: must fail at once, without reserving anything of that size.
    const auto start = std::chrono::steady_clock::now();
    for (const char* fmt : {"ascii", "binary_little_endian"}) {
        std::string s = std::string("ply\nformat ") + fmt +
                        " 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
        s += std::string(100, '1');
        expect_error(s, Error::Kind::format, {"'vertex'", "4000000000", "bytes of data"});
    }
    // Counts whose byte size overflows 64 bits.
    expect_error("ply\nformat binary_big_endian 1.0\nelement vertex 18446744073709551615\nproperty double x\n"
                 "property double y\nproperty double z\nend_header\n0123456789",
                 Error::Kind::format, {"'vertex'"});
    // A face count that lies, after a correct vertex element.
    expect_error(kAsciiHeader.substr(0, kAsciiHeader.find("element face 1")) + "element face 900000000\n" +
                     "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                 Error::Kind::format, {"'face'", "900000000"});
    // Elements without properties take no bytes; a huge count of them must not loop.
    const Mesh m = read_ply_memory("ply\nformat binary_little_endian 1.0\nelement nothing 18446744073709551615\n"
                                   "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
    EXPECT_EQ(m.vertex_count(), 0u);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(PlyMalformed, ShortBinaryDataNamesElementAndRecord) {
    const std::vector<Vec3f> pos = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::string bytes = encode_ply(PlyEncoding::binary_little_endian,
                                   {vertex_element(PlyType::float32, pos), face_element({{0, 1, 2}, {2, 1, 0}})});
    // Drop the last face (13 bytes) and put 5 garbage bytes: the minimum-size check passes (5 >= 1),
    // then the data runs out inside record 1.
    bytes.resize(bytes.size() - 13);
    bytes += std::string("\x03\x00\x00\x00\x00", 5);
    expect_error(bytes, Error::Kind::format, {"'face' record 1", "byte"});
}

TEST(PlyMalformed, GarbageInAsciiData) {
    expect_error(kAsciiHeader + "0 0 0\n1 0 abc\n0 1 0\n3 0 1 2\n", Error::Kind::format, {"line 11", "'abc'", "'z'", "record 1"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 1.5.3\n0 1 0\n3 0 1 2\n", Error::Kind::format, {"line 11", "'1.5.3'"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0 7\n0 1 0\n3 0 1 2\n", Error::Kind::format, {"line 11", "'7'", "more values"});
    expect_error(kAsciiHeader + "0 0 0\n1 0\n0 1 0\n3 0 1 2\n", Error::Kind::format, {"line 11", "fewer values"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n", Error::Kind::format, {"line 13", "'2.5'", "not an integer"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n", Error::Kind::format, {"out of range for uchar"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999\n", Error::Kind::format, {"out of range for int"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", Error::Kind::format, {"line 13"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0\n0 1 " + std::string(300, '1') + "\n3 0 1 2\n", Error::Kind::format,
                 {"line 12"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0\n0 1 1e99\n3 0 1 2\n", Error::Kind::format, {"'1e99'"});
}

TEST(PlyMalformed, NegativeAndAbsurdListCounts) {
    const std::string h = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                          "element face 1\nproperty list char int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    expect_error(h + "-1 0 1 2\n", Error::Kind::format, {"negative list length -1", "face"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", Error::Kind::format, {"out of range for uchar"});
    expect_error(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n250 0 1 2\n", Error::Kind::format, {"list length 250", "rest of the file"});

    const std::vector<Vec3f> pos = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (PlyEncoding enc : {PlyEncoding::binary_little_endian, PlyEncoding::binary_big_endian}) {
        std::string bytes = encode_ply(enc, {vertex_element(PlyType::float32, pos), face_element({{0, 1, 2}}, PlyType::int8)});
        bytes[bytes.size() - 13] = static_cast<char>(-3);
        expect_error(bytes, Error::Kind::format, {"negative list length -3", "'face' record 0"});
        std::string big = encode_ply(enc, {vertex_element(PlyType::float32, pos), face_element({{0, 1, 2}}, PlyType::uint32)});
        std::memset(&big[big.size() - 16], 0x7f, 4);  // a count of ~2e9 in either byte order
        expect_error(big, Error::Kind::format, {"rest of the file"});
    }
}

TEST(PlyMalformed, VertexIndexOutOfRangeNamesTheFace) {
    const std::vector<Vec3f> pos = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (PlyEncoding enc : kEncodings) {
        SCOPED_TRACE(encoding_name(enc));
        expect_error(encode_ply(enc, {vertex_element(PlyType::float32, pos), face_element({{0, 1, 2}, {0, 3, 1}})}),
                     Error::Kind::invalid, {"face 1", "vertex index 3", "3 vertices"});
        expect_error(encode_ply(enc, {vertex_element(PlyType::float32, pos), face_element({{0, 1, 2}, {2, 1, 0}, {-1, 1, 2}})}),
                     Error::Kind::invalid, {"face 2", "vertex index -1"});
        expect_error(encode_ply(enc, {vertex_element(PlyType::float32, pos), face_element({{0, 1, 2, 7, 1}})}),
                     Error::Kind::invalid, {"face 0", "vertex index 7"});
        expect_error(encode_ply(enc, {vertex_element(PlyType::float32, pos),
                                      face_element({{0, 1, 2, -1, 5, 1, 2}}, PlyType::int32, PlyType::int32, "tristrips")}),
                     Error::Kind::invalid, {"triangle strip 0", "vertex index 5"});
    }
}

TEST(PlyMalformed, NonFinitePositionsNameTheVertex) {
    const float nan = std::nanf(""), inf = INFINITY;
    for (PlyEncoding enc : kEncodings)
        for (float bad : {nan, inf, -inf}) {
            SCOPED_TRACE(std::string(encoding_name(enc)) + " " + std::to_string(bad));
            const std::vector<Vec3f> pos = {{0, 0, 0}, {1, 0, 0}, {0, bad, 0}, {1, 1, 1}};
            expect_error(encode_ply(enc, {vertex_element(PlyType::float32, pos), face_element({{0, 1, 2}})}),
                         Error::Kind::invalid, {"vertex 2", "non-finite"});
        }
    expect_error(kAsciiHeader + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", Error::Kind::invalid, {"vertex 1"});
}

TEST(PlyMalformed, WedgeAndTexnumberProblems) {
    const std::string h = "ply\nformat ascii 1.0\ncomment TextureFile a.png\nelement vertex 3\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n";
    const std::string data = "end_header\n0 0 0\n1 0 0\n0 1 0\n";
    expect_error(h + "property list uchar float texcoord\n" + data + "3 0 1 2 4 0 0 1 0\n", Error::Kind::format,
                 {"face 0", "texcoord list has 4 values for 3 corners"});
    expect_error(h + "property int texnumber\n" + data + "3 0 1 2 1\n", Error::Kind::invalid, {"face 0", "texnumber 1"});
    expect_error(h + "property int texnumber\n" + data + "3 0 1 2 -1\n", Error::Kind::invalid, {"texnumber -1"});
}

TEST(PlyMalformed, FilesThatCannotBeOpened) {
    ScratchDir dir("ply-open");
    const std::string missing = dir.file("missing.ply");
    CaughtError e = catch_error([&] { read_ply(missing); });
    EXPECT_EQ(e.kind, Error::Kind::io);
    EXPECT_NE(e.message.find(missing), std::string::npos);
    e = catch_error([&] { read_ply(dir.path().string()); });
    EXPECT_EQ(e.kind, Error::Kind::io);
    EXPECT_NE(e.message.find("directory"), std::string::npos);
}

TEST(PlyMalformed, EveryTruncatedPrefixThrows) {
    for (PlyEncoding enc : kEncodings) {
        SCOPED_TRACE(encoding_name(enc));
        const std::string full = rich_file(enc);
        const Mesh whole = read_ply_memory(full);
        ASSERT_EQ(whole.point_count(), 6u);
        ASSERT_EQ(whole.triangle_count(), 4u);
        // ASCII: a prefix that ends inside the file's last number can still be a complete (different)
        // file; every shorter one must throw.
        std::size_t must_throw = full.size();
        if (enc == PlyEncoding::ascii) {
            must_throw = full.find_last_not_of(" \n");
            while (must_throw > 0 && full[must_throw - 1] != ' ') --must_throw;
        }
        for (std::size_t n = 0; n < full.size(); ++n) {
            const std::string prefix = full.substr(0, n);
            const CaughtError c = catch_error([&] { read_ply_memory(prefix, "prefix.ply"); });
            if (n < must_throw) {
                ASSERT_TRUE(c.thrown) << "prefix of " << n << " bytes did not throw";
                ASSERT_EQ(c.kind, Error::Kind::format) << c.message;
                ASSERT_EQ(c.message.rfind("prefix.ply: ", 0), 0u) << c.message;
            }
        }
    }
}

TEST(PlyMalformed, TruncatedRealFilesThrowThroughTheFileReader) {
    // The file path reads through the buffered reader (the memory test above does not refill).
    ScratchDir dir("ply-trunc");
    const std::string path = dir.file("t.ply");
    for (const char* src : {"color-open3d-small/color.ply", "scan-dragon/dragon_vrip_res4.ply"}) {
        const std::string full = read_file(shared_data(src));
        for (std::size_t n : {std::size_t(0), std::size_t(10), std::size_t(200), full.size() / 3, full.size() / 2,
                              full.size() - 40, full.size() - 20}) {
            write_file(path, full.substr(0, n));
            const CaughtError c = catch_error([&] { read_ply(path); });
            EXPECT_TRUE(c.thrown) << src << " cut at " << n;
            EXPECT_NE(c.message.find(path), std::string::npos) << c.message;
        }
    }
}

TEST(PlyMalformed, RandomCorruptionNeverCrashes) {
    std::mt19937 rng(7);
    for (PlyEncoding enc : kEncodings) {
        const std::string full = rich_file(enc);
        std::uniform_int_distribution<std::size_t> pos(0, full.size() - 1);
        std::uniform_int_distribution<int> byte(0, 255);
        for (int trial = 0; trial < 3000; ++trial) {
            std::string s = full;
            for (int k = 0; k < 1 + trial % 4; ++k) s[pos(rng)] = static_cast<char>(byte(rng));
            try {
                const Mesh m = read_ply_memory(s);
                for (std::uint32_t i : m.indices) ASSERT_LT(i, m.vertex_count());
            } catch (const Error&) {
            }
        }
    }
}

TEST(PlyMalformed, StreamingApiMisuseIsAnArgumentError) {
    const std::string bytes = rich_file(PlyEncoding::binary_little_endian);
    PlyReader reader(bytes_of(bytes), "misuse.ply");
    PlyFaceChunk chunk;
    EXPECT_EQ(catch_error([&] { reader.read_faces(10, chunk); }).kind, Error::Kind::argument);
    std::vector<Vec3f> p(6), n(2);
    EXPECT_EQ(catch_error([&] { reader.read_vertices(p, n); }).kind, Error::Kind::argument);
    EXPECT_EQ(reader.read_vertices(p), 6u);
    EXPECT_EQ(catch_error([&] { reader.read_vertices(p); }).kind, Error::Kind::argument);
}
