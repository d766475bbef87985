// Helpers shared by the PLY tests: an independent little PLY encoder (so reader tests do not depend on
// our writer), error capture, and file helpers.
#pragma once

#include "lodforge/error.h"
#include "lodforge/mesh.h"
#include "lodforge/io/ply.h"

#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace lodforge::test {

struct CaughtError {
    bool thrown = false;
    Error::Kind kind = Error::Kind::argument;
    std::string message;
};

inline CaughtError catch_error(const std::function<void()>& f) {
    CaughtError c;
    try {
        f();
    } catch (const Error& e) {
        c.thrown = true;
        c.kind = e.kind();
        c.message = e.what();
    }
    return c;
}

inline void write_file(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline std::span<const std::byte> bytes_of(const std::string& s) {
    return {reinterpret_cast<const std::byte*>(s.data()), s.size()};
}

inline Mesh read_ply_memory(const std::string& bytes, const std::string& name = "memory.ply") {
    PlyReader reader(bytes_of(bytes), name);
    return read_ply(reader);
}

// ---- An encoder independent of write_ply: any element, any property types, any encoding. ----

struct TestProperty {
    std::string name;
    PlyType type = PlyType::float32;
    PlyType count_type = PlyType::none;  // none: scalar
};

struct TestElement {
    std::string name;
    std::vector<TestProperty> properties;
    // records[r][p] holds the values of property p of record r (one value for a scalar).
    std::vector<std::vector<std::vector<double>>> records;
};

inline void encode_value(std::string& out, PlyType type, double v, PlyEncoding enc) {
    if (enc == PlyEncoding::ascii) {
        char tmp[64];
        std::to_chars_result r{};
        switch (type) {
            case PlyType::float32: r = std::to_chars(tmp, tmp + sizeof tmp, static_cast<float>(v)); break;
            case PlyType::float64: r = std::to_chars(tmp, tmp + sizeof tmp, v); break;
            default: r = std::to_chars(tmp, tmp + sizeof tmp, static_cast<long long>(v)); break;
        }
        if (!out.empty() && out.back() != '\n') out += ' ';
        out.append(tmp, r.ptr);
        return;
    }
    unsigned char b[8];
    std::size_t n = ply_type_size(type);
    switch (type) {
        case PlyType::int8: { auto x = static_cast<std::int8_t>(v); std::memcpy(b, &x, 1); break; }
        case PlyType::uint8: { auto x = static_cast<std::uint8_t>(v); std::memcpy(b, &x, 1); break; }
        case PlyType::int16: { auto x = static_cast<std::int16_t>(v); std::memcpy(b, &x, 2); break; }
        case PlyType::uint16: { auto x = static_cast<std::uint16_t>(v); std::memcpy(b, &x, 2); break; }
        case PlyType::int32: { auto x = static_cast<std::int32_t>(v); std::memcpy(b, &x, 4); break; }
        case PlyType::uint32: { auto x = static_cast<std::uint32_t>(v); std::memcpy(b, &x, 4); break; }
        case PlyType::float32: { auto x = static_cast<float>(v); std::memcpy(b, &x, 4); break; }
        case PlyType::float64: std::memcpy(b, &v, 8); break;
        case PlyType::none: n = 0; break;
    }
    const bool big = enc == PlyEncoding::binary_big_endian;
    if (big != (std::endian::native == std::endian::big))
        for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    out.append(reinterpret_cast<const char*>(b), n);
}

inline const char* encoding_name(PlyEncoding e) {
    return e == PlyEncoding::ascii ? "ascii"
           : e == PlyEncoding::binary_little_endian ? "binary_little_endian"
                                                    : "binary_big_endian";
}

inline std::string encode_ply(PlyEncoding enc, const std::vector<TestElement>& elements,
                              const std::vector<std::string>& comments = {}) {
    std::string out = "ply\nformat ";
    out += encoding_name(enc);
    out += " 1.0\n";
    for (const auto& c : comments) out += "comment " + c + "\n";
    for (const auto& e : elements) {
        out += "element " + e.name + " " + std::to_string(e.records.size()) + "\n";
        for (const auto& p : e.properties) {
            out += "property ";
            if (p.count_type != PlyType::none) out += std::string("list ") + ply_type_name(p.count_type) + " ";
            out += std::string(ply_type_name(p.type)) + " " + p.name + "\n";
        }
    }
    out += "end_header\n";
    for (const auto& e : elements) {
        for (const auto& record : e.records) {
            std::string line;
            for (std::size_t p = 0; p < e.properties.size(); ++p) {
                const TestProperty& prop = e.properties[p];
                if (prop.count_type != PlyType::none)
                    encode_value(line, prop.count_type, static_cast<double>(record[p].size()), enc);
                for (double v : record[p]) encode_value(line, prop.type, v, enc);
            }
            out += line;
            if (enc == PlyEncoding::ascii) out += "\n";
        }
    }
    return out;
}

// A small tetrahedron-ish vertex element (x y z of `type`) plus faces.
inline TestElement vertex_element(PlyType type, const std::vector<Vec3f>& positions) {
    TestElement e{"vertex", {{"x", type}, {"y", type}, {"z", type}}, {}};
    for (const Vec3f& p : positions) e.records.push_back({{p.x}, {p.y}, {p.z}});
    return e;
}

inline TestElement face_element(const std::vector<std::vector<double>>& polygons, PlyType count_type = PlyType::uint8,
                                PlyType index_type = PlyType::int32, const char* name = "face") {
    TestElement e{name, {{"vertex_indices", index_type, count_type}}, {}};
    for (const auto& poly : polygons) e.records.push_back({poly});
    return e;
}

inline constexpr PlyEncoding kEncodings[] = {PlyEncoding::ascii, PlyEncoding::binary_little_endian,
                                             PlyEncoding::binary_big_endian};

}  // namespace lodforge::test
