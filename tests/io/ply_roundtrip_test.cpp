// write_ply then read_ply gives back the same arrays, for every encoding and attribute combination,
// and files produced by an independent encoder with every scalar type read back right.

#include "ply_test_util.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <random>

using namespace lodforge;
using namespace lodforge::test;

namespace {

enum class Colors { none, uchar, floats };

Mesh make_mesh(bool normals, Colors colors, bool texcoords, std::size_t n = 300) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> u(-10.f, 10.f);
    std::uniform_int_distribution<int> byte(0, 255);
    Mesh m;
    for (std::size_t i = 0; i < n; ++i) {
        m.positions.push_back({u(rng), u(rng) * 1e-3f, u(rng) * 1e5f});
        if (normals) m.normals.push_back({u(rng) / 10.f, u(rng) / 10.f, u(rng) / 10.f});
        if (colors == Colors::uchar)
            m.colors.push_back({byte(rng) / 255.f, byte(rng) / 255.f, byte(rng) / 255.f, byte(rng) / 255.f});
        if (colors == Colors::floats) m.colors.push_back({u(rng) / 20 + .5f, 0.1f, 1.f / 3.f, u(rng) / 20 + .5f});
    }
    if (texcoords) {
        m.texcoords.emplace_back();
        for (std::size_t i = 0; i < n; ++i) m.texcoords[0].push_back({u(rng) / 10.f, u(rng) / 7.f});
    }
    std::uniform_int_distribution<std::uint32_t> vi(0, static_cast<std::uint32_t>(n - 1));
    for (std::size_t t = 0; t < 2 * n; ++t) m.indices.insert(m.indices.end(), {vi(rng), vi(rng), vi(rng)});
    return m;
}

void expect_same_arrays(const Mesh& a, const Mesh& b) {
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.normals, b.normals);
    EXPECT_EQ(a.colors, b.colors);
    EXPECT_EQ(a.texcoords, b.texcoords);
    EXPECT_EQ(a.indices, b.indices);
}

}  // namespace

TEST(PlyRoundTrip, EveryEncodingAndAttributeCombination) {
    ScratchDir dir("ply-roundtrip");
    for (PlyEncoding enc : kEncodings)
        for (Colors colors : {Colors::none, Colors::uchar, Colors::floats})
            for (bool normals : {false, true})
                for (bool texcoords : {false, true}) {
                    SCOPED_TRACE(std::string(encoding_name(enc)) + " colors " + std::to_string(int(colors)) +
                                 " normals " + std::to_string(normals) + " texcoords " + std::to_string(texcoords));
                    const Mesh m = make_mesh(normals, colors, texcoords);
                    WriteOptions options;
                    options.ply_encoding = enc;
                    options.ply_colors_as_uchar = colors != Colors::floats;
                    const std::string path = dir.file("m.ply");
                    write_ply(m, path, options);
                    const Mesh r = read_ply(path);
                    expect_same_arrays(m, r);
                    PlyReader reader(path);
                    EXPECT_EQ(reader.header().format, enc);
                    if (colors != Colors::none) {
                        EXPECT_EQ(reader.header().elements[0].properties[normals ? 6 : 3].type,
                                  colors == Colors::uchar ? PlyType::uint8 : PlyType::float32);
                    }
                }
}

TEST(PlyRoundTrip, WriteOptionsDropAttributes) {
    ScratchDir dir("ply-options");
    const Mesh m = make_mesh(true, Colors::uchar, true, 20);
    WriteOptions options;
    options.write_normals = options.write_colors = options.write_texcoords = false;
    write_ply(m, dir.file("a.ply"), options);
    const Mesh r = read_ply(dir.file("a.ply"));
    EXPECT_EQ(r.positions, m.positions);
    EXPECT_EQ(r.indices, m.indices);
    EXPECT_FALSE(r.has_normals() || r.has_colors() || r.has_texcoords());
}

TEST(PlyRoundTrip, EmptyMeshAndUnusedVerticesSurvive) {
    ScratchDir dir("ply-empty");
    Mesh empty;
    write_ply(empty, dir.file("e.ply"));
    const Mesh r = read_ply(dir.file("e.ply"));
    EXPECT_EQ(r.vertex_count(), 0u);
    EXPECT_EQ(r.triangle_count(), 0u);

    Mesh lonely;
    lonely.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}};  // vertex 3 used by no face
    lonely.indices = {0, 1, 2};
    for (PlyEncoding enc : kEncodings) {
        WriteOptions o;
        o.ply_encoding = enc;
        write_ply(lonely, dir.file("l.ply"), o);
        EXPECT_EQ(read_ply(dir.file("l.ply")).positions, lonely.positions);
    }
}

TEST(PlyRoundTrip, WedgeTexcoordMeshKeepsEveryCornerUv) {
    ScratchDir dir("ply-wedge");
    const Mesh m = read_ply(shared_data("tex-ply-wedge-uv/laurana500.ply"));
    for (PlyEncoding enc : kEncodings) {
        SCOPED_TRACE(encoding_name(enc));
        WriteOptions o;
        o.ply_encoding = enc;
        write_ply(m, dir.file("w.ply"), o);
        const Mesh r = read_ply(dir.file("w.ply"));
        expect_same_arrays(m, r);
        ASSERT_EQ(r.materials.size(), 1u);
        EXPECT_EQ(r.materials[0].base_color_texture.path, "laurana500.png");
        EXPECT_EQ(r.face_materials, m.face_materials);
        // Wedges are written as plain vertices: the seam identity is not stored in PLY (docs/ply.md).
        EXPECT_EQ(r.point_count(), r.vertex_count());
    }
}

TEST(PlyRoundTrip, PolygonsAreFanTriangulatedInEveryEncoding) {
    ScratchDir dir("ply-poly");
    const std::vector<Vec3f> pos = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}, {3, 0.5f, 0}};
    const TestElement faces = face_element({{0, 1, 2, 3}, {1, 4, 6, 5, 2}, {0, 1}, {4, 6, 5}});
    for (PlyEncoding enc : kEncodings) {
        SCOPED_TRACE(encoding_name(enc));
        const std::string bytes = encode_ply(enc, {vertex_element(PlyType::float32, pos), faces});
        PlyReader reader(bytes_of(bytes), "poly.ply");
        PlyFaceChunk chunk;
        std::vector<Vec3f> p(pos.size());
        reader.read_vertices(p);
        EXPECT_EQ(reader.read_faces(100, chunk), 4u);
        EXPECT_EQ(chunk.skipped_faces, 1u);  // the two-corner face
        EXPECT_EQ(chunk.faces_read, 4u);
        const std::vector<std::uint32_t> expected = {0, 1, 2, 0, 2, 3, 1, 4, 6, 1, 6, 5, 1, 5, 2, 4, 6, 5};
        EXPECT_EQ(chunk.indices, expected);
        EXPECT_EQ(reader.current_element(), nullptr);

        const Mesh m = read_ply_memory(bytes);
        EXPECT_EQ(m.indices, expected);
        write_ply(m, dir.file("p.ply"));
        expect_same_arrays(read_ply(dir.file("p.ply")), m);
    }
}

TEST(PlyRoundTrip, TriangleStripsAlternateWindingRestartAndDropDegenerates) {
    // A 2 x 3 grid of quads as in Stanford's igea.ply: strips with -1 restarts and a degenerate join.
    std::vector<Vec3f> pos;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) pos.push_back({float(x), float(y), 0});
    // Row 0: 4 0 5 1 6 2 7 3 (restart) row 1: 8 4 9 5 10 6 11 7, then a degenerate pair 7 7.
    const TestElement strips = face_element({{4, 0, 5, 1, 6, 2, 7, 3, -1, 8, 4, 9, 5, 10, 6, 11, 7, 7, 7}},
                                            PlyType::int32, PlyType::int32, "tristrips");
    for (PlyEncoding enc : kEncodings) {
        SCOPED_TRACE(encoding_name(enc));
        const std::string bytes = encode_ply(enc, {vertex_element(PlyType::float32, pos), strips});
        const Mesh m = read_ply_memory(bytes);
        ASSERT_EQ(m.triangle_count(), 12u);
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {  // every triangle faces +z
            const Vec3f a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                        c = m.positions[m.indices[3 * t + 2]];
            EXPECT_GT(cross(b - a, c - a).z, 0.f) << "triangle " << t;
        }
        EXPECT_EQ((std::vector<std::uint32_t>(m.indices.begin(), m.indices.begin() + 6)),
                  (std::vector<std::uint32_t>{4, 0, 5, 5, 0, 1}));
        PlyReader reader(bytes_of(bytes), "strips.ply");
        PlyFaceChunk chunk;
        while (reader.current_element()) {
            if (reader.at_faces()) reader.read_faces(1, chunk);
            else reader.skip_element();
        }
        EXPECT_EQ(chunk.dropped_strip_triangles, 2u);  // 11 7 7 and 7 7 7

        ScratchDir dir("ply-strips");
        write_ply(m, dir.file("s.ply"));
        expect_same_arrays(read_ply(dir.file("s.ply")), m);
    }
}

TEST(PlyRoundTrip, EveryScalarTypeForPositionsCountsAndIndices) {
    const PlyType all[] = {PlyType::int8,  PlyType::uint8,  PlyType::int16,   PlyType::uint16,
                           PlyType::int32, PlyType::uint32, PlyType::float32, PlyType::float64};
    const PlyType integers[] = {PlyType::int8, PlyType::uint8, PlyType::int16, PlyType::uint16, PlyType::int32, PlyType::uint32};
    std::vector<Vec3f> pos;
    for (int i = 0; i < 40; ++i) pos.push_back({float(i), float((i * 7) % 13), float(100 - i)});
    std::vector<std::vector<double>> tris;
    for (int i = 0; i + 2 < 40; ++i) tris.push_back({double(i), double(i + 1), double(i + 2)});
    std::vector<std::uint32_t> expected;
    for (const auto& t : tris)
        for (double v : t) expected.push_back(static_cast<std::uint32_t>(v));
    for (PlyEncoding enc : kEncodings)
        for (PlyType pt : all)
            for (PlyType ct : integers)
                for (PlyType it : integers) {
                    SCOPED_TRACE(std::string(encoding_name(enc)) + " pos " + ply_type_name(pt) + " count " +
                                 ply_type_name(ct) + " index " + ply_type_name(it));
                    const std::string bytes = encode_ply(enc, {vertex_element(pt, pos), face_element(tris, ct, it)});
                    const Mesh m = read_ply_memory(bytes);
                    ASSERT_EQ(m.positions, pos);
                    ASSERT_EQ(m.indices, expected);
                }
}

TEST(PlyRoundTrip, AttributeNamesAndTypesFromOtherWriters) {
    struct Case {
        std::vector<TestProperty> props;
        std::vector<double> values;
        Vec3f normal;
        Vec4f color;
        Vec2f uv;
        bool has_normal, has_color, has_uv;
    };
    const std::vector<Case> cases = {
        {{{"x"}, {"y"}, {"z"}, {"red", PlyType::uint8}, {"green", PlyType::uint8}, {"blue", PlyType::uint8}},
         {1, 2, 3, 255, 0, 51}, {}, {1, 0, 51 / 255.f, 1}, {}, false, true, false},
        {{{"x"}, {"y"}, {"z"}, {"diffuse_red", PlyType::uint8}, {"diffuse_green", PlyType::uint8},
          {"diffuse_blue", PlyType::uint8}, {"diffuse_alpha", PlyType::uint8}},
         {1, 2, 3, 255, 0, 51, 102}, {}, {1, 0, 51 / 255.f, 102 / 255.f}, {}, false, true, false},
        {{{"x", PlyType::float64}, {"y", PlyType::float64}, {"z", PlyType::float64}, {"red"}, {"green"}, {"blue"}, {"alpha"}},
         {1, 2, 3, 0.25, 0.5, 0.75, 0.125}, {}, {0.25f, 0.5f, 0.75f, 0.125f}, {}, false, true, false},
        {{{"x"}, {"y"}, {"z"}, {"red", PlyType::uint16}, {"green", PlyType::uint16}, {"blue", PlyType::uint16}},
         {1, 2, 3, 65535, 0, 0}, {}, {1, 0, 0, 1}, {}, false, true, false},
        {{{"x"}, {"y"}, {"z"}, {"s"}, {"t"}}, {1, 2, 3, 0.5, 0.25}, {}, {}, {0.5f, 0.25f}, false, false, true},
        {{{"x"}, {"y"}, {"z"}, {"texture_u"}, {"texture_v"}}, {1, 2, 3, 0.5, 0.25}, {}, {}, {0.5f, 0.25f}, false, false, true},
        {{{"x"}, {"y"}, {"z"}, {"texture_s", PlyType::float64}, {"texture_t", PlyType::float64}}, {1, 2, 3, 0.5, 0.25}, {}, {},
         {0.5f, 0.25f}, false, false, true},
        {{{"nx"}, {"confidence"}, {"x"}, {"ny"}, {"y"}, {"intensity", PlyType::uint8}, {"z"}, {"nz"}, {"u"}, {"v"}},
         {0, 0.5, 1, 1, 2, 7, 3, 0, 0.5, 0.25}, {0, 1, 0}, {}, {0.5f, 0.25f}, true, false, true},
        // a vertex list property (skipped) in the middle
        {{{"x"}, {"flags", PlyType::int32, PlyType::uint8}, {"y"}, {"z"}}, {1, 2, 3}, {}, {}, {}, false, false, false},
    };
    for (PlyEncoding enc : kEncodings)
        for (std::size_t c = 0; c < cases.size(); ++c) {
            SCOPED_TRACE(std::string(encoding_name(enc)) + " case " + std::to_string(c));
            const Case& k = cases[c];
            TestElement v{"vertex", k.props, {}};
            std::vector<std::vector<double>> record;
            std::size_t next = 0;
            for (const TestProperty& p : k.props) {
                if (p.count_type != PlyType::none) record.push_back({9, 8, 7});
                else record.push_back({k.values[next++]});
            }
            v.records = {record, record, record};
            const Mesh m = read_ply_memory(encode_ply(enc, {v, face_element({{0, 1, 2}})}));
            ASSERT_EQ(m.vertex_count(), 3u);
            EXPECT_EQ(m.positions[2], (Vec3f{1, 2, 3}));
            EXPECT_EQ(m.has_normals(), k.has_normal);
            EXPECT_EQ(m.has_colors(), k.has_color);
            EXPECT_EQ(m.has_texcoords(), k.has_uv);
            if (k.has_normal) {
                EXPECT_EQ(m.normals[1], k.normal);
            }
            if (k.has_color) {
                EXPECT_EQ(m.colors[1], k.color);
            }
            if (k.has_uv) {
                EXPECT_EQ(m.texcoords[0][1], k.uv);
            }
        }
}

TEST(PlyRoundTrip, UnknownElementsAndFacePropertiesAreSkipped) {
    const std::vector<Vec3f> pos = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    TestElement material{"material", {{"name", PlyType::uint8, PlyType::int32}, {"shininess", PlyType::float64}}, {}};
    material.records = {{{104, 105}, {0.5}}, {{}, {2}}};
    TestElement faces{"face",
                      {{"flags", PlyType::uint16}, {"vertex_index", PlyType::uint32, PlyType::uint16},
                       {"normals", PlyType::float32, PlyType::uint8}, {"quality", PlyType::float64}},
                      {{{1}, {0, 1, 2}, {0, 0, 1}, {0.5}}, {{2}, {2, 1, 3}, {}, {0.25}}}};
    TestElement edges{"edge", {{"vertex1", PlyType::int32}, {"vertex2", PlyType::int32}}, {{{0}, {1}}, {{1}, {2}}}};
    TestElement nothing{"empty_element", {}, {}};
    for (PlyEncoding enc : kEncodings) {
        SCOPED_TRACE(encoding_name(enc));
        const std::string bytes =
            encode_ply(enc, {material, vertex_element(PlyType::float32, pos), edges, faces, nothing},
                       {"generated by a test", "TextureFile"});
        const Mesh m = read_ply_memory(bytes);
        EXPECT_EQ(m.positions, pos);
        EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3}));
        EXPECT_TRUE(m.materials.empty());  // "TextureFile" without a name is only a comment
    }
}

TEST(PlyRoundTrip, CrLfLineEndingsInHeaderAndAsciiData) {
    std::string text = "ply\r\nformat ascii 1.0\r\ncomment TextureFile tex.png\r\nelement vertex 3\r\n"
                       "property float x\r\nproperty float y\r\nproperty float z\r\n"
                       "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                       "0 0 0\r\n1 0 0 \r\n\r\n0 1 0\r\n3 0 1 2\r\n";
    const Mesh m = read_ply_memory(text);
    EXPECT_EQ(m.positions.size(), 3u);
    // No newline after the last value, through memory and through a file.
    const std::string unterminated = text.substr(0, text.size() - 2);
    EXPECT_EQ(read_ply_memory(unterminated).indices, (std::vector<std::uint32_t>{0, 1, 2}));
    ScratchDir dir("ply-crlf");
    write_file(dir.file("u.ply"), unterminated);
    EXPECT_EQ(read_ply(dir.file("u.ply")).indices, (std::vector<std::uint32_t>{0, 1, 2}));
    EXPECT_EQ(m.positions[1], (Vec3f{1, 0, 0}));
    EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2}));
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_EQ(m.materials[0].base_color_texture.path, "tex.png");

    // Binary data after a CRLF header: the data starts right after "end_header\r\n".
    std::string bin = "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 1\r\nproperty float x\r\n"
                      "property float y\r\nproperty float z\r\nend_header\r\n";
    const float xyz[3] = {13.f, 10.f, 1.f};
    bin.append(reinterpret_cast<const char*>(xyz), 12);
    EXPECT_EQ(read_ply_memory(bin).positions[0], (Vec3f{13, 10, 1}));
}

TEST(PlyRoundTrip, TexnumberSelectsAmongSeveralTextureFiles) {
    const std::vector<Vec3f> pos = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    TestElement faces{"face",
                      {{"vertex_indices", PlyType::int32, PlyType::uint8}, {"texcoord", PlyType::float32, PlyType::uint8},
                       {"texnumber", PlyType::int32}},
                      {{{0, 1, 2}, {0, 0, 1, 0, 0, 1}, {1}},
                       {{2, 1, 3}, {0.5, 0.5, 0.25, 0.25, 1, 1}, {0}},
                       {{0, 2, 3}, {}, {1}}}};
    for (PlyEncoding enc : kEncodings) {
        SCOPED_TRACE(encoding_name(enc));
        const Mesh m = read_ply_memory(
            encode_ply(enc, {vertex_element(PlyType::float32, pos), faces}, {"TextureFile a.png", "TextureFile b b.png"}));
        ASSERT_EQ(m.materials.size(), 2u);
        EXPECT_EQ(m.materials[1].base_color_texture.path, "b b.png");
        EXPECT_EQ(m.face_materials, (std::vector<std::uint32_t>{1, 0, 1}));
        // vertex 2 is used with uv (0,1) first, then (0.5,0.5): one split. Vertex 1 (1,0) then (0.25,0.25).
        // The third face has no wedge uvs and keeps the stored vertices.
        EXPECT_EQ(m.vertex_count(), 6u);
        EXPECT_EQ(m.point_count(), 4u);
        EXPECT_EQ(m.indices[6], 0u);
        EXPECT_EQ(m.indices[7], 2u);
        EXPECT_EQ(m.texcoords[0][m.indices[3]], (Vec2f{0.5f, 0.5f}));
        EXPECT_EQ(m.texcoords[0][m.indices[4]], (Vec2f{0.25f, 0.25f}));
        EXPECT_EQ(m.texcoords[0][3], (Vec2f{1, 1}));
        EXPECT_EQ(m.position_ids[m.indices[3]], 2u);
    }
}

TEST(PlyRoundTrip, AsciiNumbersParseExactlyLikeFromChars) {
    // The reader's fast decimal path must give the very float/double std::from_chars gives.
    std::vector<std::string> floats = {"0", "-0", "+1", "1.", ".5", "-.5", "1e3", "1E-3", "16777216", "16777217",
                                       "0.1", "3.4028235e38", "1e-30", "123456789012345678901234567890",
                                       "0.000000000001", "9999999999", "-0.0597022", "0.30000001192092896"};
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> mag(-12, 12);
    std::uniform_int_distribution<int> precision(1, 17);
    char buf[64];
    for (int i = 0; i < 20000; ++i) {
        const double v = std::pow(10.0, mag(rng)) * (i % 2 ? -1 : 1);
        std::snprintf(buf, sizeof buf, i % 3 ? "%.*g" : "%.*f", precision(rng), v);
        floats.push_back(buf);
    }
    std::string text = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(floats.size()) +
                       "\nproperty float x\nproperty double y\nproperty float z\nproperty int i\nend_header\n";
    for (std::size_t k = 0; k < floats.size(); ++k)
        text += floats[k] + " " + floats[k] + " 1 " + std::to_string(static_cast<int>(k) - 5000) + "\n";
    PlyReader reader(bytes_of(text), "numbers.ply");
    std::vector<Vec3f> p(floats.size());
    ASSERT_EQ(reader.read_vertices(p), floats.size());
    for (std::size_t k = 0; k < floats.size(); ++k) {
        const std::string& t = floats[k];
        const char* b = t.data() + (t[0] == '+' ? 1 : 0);
        float f = 0;
        double d = 0;
        std::from_chars(b, t.data() + t.size(), f);
        std::from_chars(b, t.data() + t.size(), d);
        ASSERT_EQ(std::bit_cast<std::uint32_t>(p[k].x), std::bit_cast<std::uint32_t>(f)) << t;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(p[k].y), std::bit_cast<std::uint32_t>(static_cast<float>(d))) << t;
    }
}
