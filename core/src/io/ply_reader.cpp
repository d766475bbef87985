// PLY data reader: the streaming PlyReader and read_ply on top of it.
//
// Speed comes from three things: large sequential reads into one reusable buffer (no per-value I/O
// calls), layouts compiled once per element (offset, type, destination of each property), and fast
// paths for the layouts nearly every file uses (float x y z vertices, `list uchar int` triangles) in
// the file's native byte order. ASCII numbers are parsed with std::from_chars (correctly rounded,
// locale-free). Robustness comes from checking every announced count against the bytes that are left
// before trusting it, so a lying header yields an Error, never a huge allocation or a long loop.

#include "io/ply_internal.h"

#include "lodforge/error.h"

#include <algorithm>
#include <cctype>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <unordered_map>

namespace lodforge {

using namespace ply_detail;

namespace {

// Destinations of vertex properties.
enum VertexSlot : std::uint8_t { kX, kY, kZ, kNx, kNy, kNz, kRed, kGreen, kBlue, kAlpha, kU, kV, kSlotCount, kSkip = 255 };

// What a face (or tristrips) property is used for.
enum class FaceRole : std::uint8_t { skip, indices, texcoord, texnumber };

struct VertexField {
    PlyType type = PlyType::none;
    PlyType count_type = PlyType::none;  // lists in a vertex element are skipped
    std::uint8_t slot = kSkip;
    float divisor = 1.f;  // colours: 255 or 65535 (the Mesh contract converts with c / 255)
    std::uint32_t offset = 0;  // byte offset in a fixed-size binary record
};

struct FaceField {
    PlyType type = PlyType::none;
    PlyType count_type = PlyType::none;
    FaceRole role = FaceRole::skip;
};

struct FaceLayout {
    int element = -1;
    bool strips = false;
    bool fast_triangles = false;  // binary, native order, only `list uchar int|uint vertex_indices`
    std::vector<FaceField> fields;
};

template <typename T>
T load_raw(const char* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

template <typename T>
T load(const char* p, bool swap) {
    if constexpr (sizeof(T) == 1) {
        return load_raw<T>(p);
    } else {
        using U = std::conditional_t<sizeof(T) == 2, std::uint16_t,
                                     std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;
        U u = load_raw<U>(p);
        if (swap) {
            if constexpr (sizeof(T) == 2) u = __builtin_bswap16(u);
            else if constexpr (sizeof(T) == 4) u = __builtin_bswap32(u);
            else u = __builtin_bswap64(u);
        }
        return std::bit_cast<T>(u);
    }
}

double load_value(PlyType type, const char* p, bool swap) {
    switch (type) {
        case PlyType::int8: return load<std::int8_t>(p, swap);
        case PlyType::uint8: return load<std::uint8_t>(p, swap);
        case PlyType::int16: return load<std::int16_t>(p, swap);
        case PlyType::uint16: return load<std::uint16_t>(p, swap);
        case PlyType::int32: return load<std::int32_t>(p, swap);
        case PlyType::uint32: return load<std::uint32_t>(p, swap);
        case PlyType::float32: return load<float>(p, swap);
        case PlyType::float64: return load<double>(p, swap);
        case PlyType::none: break;
    }
    return 0;
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
bool is_space(char c) { return is_blank(c) || c == '\n'; }

void type_range(PlyType type, double& lo, double& hi) {
    switch (type) {
        case PlyType::int8: lo = -128; hi = 127; return;
        case PlyType::uint8: lo = 0; hi = 255; return;
        case PlyType::int16: lo = -32768; hi = 32767; return;
        case PlyType::uint16: lo = 0; hi = 65535; return;
        case PlyType::int32: lo = -2147483648.0; hi = 2147483647.0; return;
        case PlyType::uint32: lo = 0; hi = 4294967295.0; return;
        default: lo = -std::numeric_limits<double>::infinity(); hi = std::numeric_limits<double>::infinity(); return;
    }
}

// Colour channels are stored 0..255 in 8- and 32-bit integers, 0..65535 in 16-bit ones, [0, 1] in floats.
float color_divisor(PlyType type) {
    switch (type) {
        case PlyType::float32:
        case PlyType::float64: return 1.f;
        case PlyType::int16:
        case PlyType::uint16: return 65535.f;
        default: return 255.f;
    }
}

std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
    std::uint64_t r;
    return __builtin_mul_overflow(a, b, &r) ? std::numeric_limits<std::uint64_t>::max() : r;
}

std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
    const std::uint64_t r = a + b;
    return r < a ? std::numeric_limits<std::uint64_t>::max() : r;
}

constexpr std::size_t kTokenWindow = 128;  // an ASCII number longer than this is rejected

}  // namespace

// ---- PlyFaceChunk ---------------------------------------------------------------------------------

void PlyFaceChunk::clear() {
    indices.clear();
    corner_texcoords.clear();
    texnumbers.clear();
    faces_read = skipped_faces = dropped_strip_triangles = 0;
}

// ---- PlyReader::Impl --------------------------------------------------------------------------------

struct PlyReader::Impl {
    Input in;
    PlyHeader header;
    bool ascii = false;
    bool swap = false;

    std::size_t element = 0;     // index of the current element
    std::uint64_t remaining = 0; // records left in it
    std::uint64_t line = 0;      // ASCII: newlines consumed so far
    bool end_checked = false;    // check_trailing_bytes has run

    int vertex_element = -1;
    std::uint64_t vertex_count = 0;
    PlyVertexAttributes attributes;
    std::vector<VertexField> vertex_fields;
    std::uint32_t vertex_record_size = 0;  // binary fixed-size record, 0 when it has lists
    bool vertex_fast_xyz = false;          // binary, native order, exactly float x y z

    FaceLayout faces;   // "face"
    FaceLayout strips;  // "tristrips"

    // Scratch for one face record.
    std::vector<std::int64_t> corner_indices;
    std::vector<float> corner_uvs;

    // ---- set-up ----

    void init() {
        header = parse_header(in);
        ascii = header.format == PlyEncoding::ascii;
        const bool file_big = header.format == PlyEncoding::binary_big_endian;
        swap = !ascii && (file_big != (std::endian::native == std::endian::big));
        line = header.header_lines;
        check_sizes();
        compile_vertex_layout();
        compile_face_layout(faces, "face", false);
        compile_face_layout(strips, "tristrips", true);
        element = 0;
        remaining = header.elements.empty() ? 0 : header.elements[0].count;
        advance();
    }

    [[noreturn]] void fail(Error::Kind kind, const std::string& what) const {
        throw_error(kind, in.path(), what);
    }

    std::string where() const {
        return ascii ? "line " + std::to_string(line + 1) : "byte " + std::to_string(in.offset());
    }

    // The smallest number of bytes a record of `e` can take: lets a lying count fail before any
    // allocation or loop sized by it.
    std::uint64_t min_record_bytes(const PlyElement& e) const {
        if (ascii) return 2 * e.properties.size();  // one character and one separator per value
        std::uint64_t bytes = 0;
        for (const PlyProperty& p : e.properties) bytes += ply_type_size(p.is_list() ? p.count_type : p.type);
        return bytes;
    }

    void check_sizes() {
        const std::uint64_t data = in.size() > header.data_offset ? in.size() - header.data_offset : 0;
        std::uint64_t need = 0;
        for (const PlyElement& e : header.elements) {
            need = saturating_add(need, saturating_mul(e.count, min_record_bytes(e)));
            // ASCII: the very last value of the file may lack its separator.
            const std::uint64_t need_here = ascii && need > 0 ? need - 1 : need;
            if (need_here > data)
                fail(Error::Kind::format,
                     "element " + show(e.name) + " announces " + std::to_string(e.count) +
                         " records, but only " + std::to_string(data) + " bytes of data follow the header (byte " +
                         std::to_string(header.data_offset) + "); the file is truncated or the header lies");
        }
    }

    void compile_vertex_layout() {
        vertex_element = -1;
        for (std::size_t i = 0; i < header.elements.size(); ++i)
            if (header.elements[i].name == "vertex") vertex_element = static_cast<int>(i);
        if (vertex_element < 0) return;
        const PlyElement& e = header.elements[static_cast<std::size_t>(vertex_element)];
        vertex_count = e.count;
        if (vertex_count > std::numeric_limits<std::uint32_t>::max())
            fail(Error::Kind::unsupported, "more than 4294967295 vertices (" + std::to_string(vertex_count) + ")");

        vertex_fields.assign(e.properties.size(), VertexField{});
        bool fixed = true;
        std::uint32_t offset = 0;
        for (std::size_t i = 0; i < e.properties.size(); ++i) {
            const PlyProperty& p = e.properties[i];
            VertexField& f = vertex_fields[i];
            f.type = p.type;
            f.count_type = p.count_type;
            f.offset = offset;
            if (p.is_list()) fixed = false;
            else offset += static_cast<std::uint32_t>(ply_type_size(p.type));
        }
        vertex_record_size = fixed ? offset : 0;

        // Binds a group of properties to slots: all of the first alternative that is complete.
        auto bind = [&](std::initializer_list<std::initializer_list<const char*>> alternatives, std::uint8_t first_slot,
                        bool colour) {
            for (const auto& names : alternatives) {
                std::vector<int> found;
                for (const char* n : names) found.push_back(e.find_property(n));
                if (std::find(found.begin(), found.end(), -1) != found.end()) continue;
                std::uint8_t slot = first_slot;
                for (std::size_t k = 0; k < found.size(); ++k, ++slot) {
                    const PlyProperty& p = e.properties[static_cast<std::size_t>(found[k])];
                    if (p.is_list())
                        fail(Error::Kind::format, "property " + show(p.name) +
                                                      " of element 'vertex' is a list; it must be a scalar");
                    VertexField& f = vertex_fields[static_cast<std::size_t>(found[k])];
                    f.slot = slot;
                    f.divisor = colour ? color_divisor(p.type) : 1.f;
                }
                return true;
            }
            return false;
        };
        if (!bind({{"x", "y", "z"}}, kX, false))
            fail(Error::Kind::format, "element 'vertex' has no x, y, z properties");
        attributes.normals = bind({{"nx", "ny", "nz"}}, kNx, false);
        attributes.colors = bind({{"red", "green", "blue"}, {"diffuse_red", "diffuse_green", "diffuse_blue"}}, kRed, true);
        attributes.alpha = attributes.colors && bind({{"alpha"}, {"diffuse_alpha"}}, kAlpha, true);
        attributes.texcoords = bind({{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}}, kU, false);

        vertex_fast_xyz = !ascii && !swap && e.properties.size() == 3 && vertex_fields[0].slot == kX &&
                          vertex_fields[1].slot == kY && vertex_fields[2].slot == kZ &&
                          std::all_of(e.properties.begin(), e.properties.end(),
                                      [](const PlyProperty& p) { return p.type == PlyType::float32 && !p.is_list(); });
    }

    void compile_face_layout(FaceLayout& layout, const char* name, bool is_strips) {
        layout = FaceLayout{};
        for (std::size_t i = 0; i < header.elements.size(); ++i)
            if (header.elements[i].name == name) layout.element = static_cast<int>(i);
        if (layout.element < 0) return;
        const PlyElement& e = header.elements[static_cast<std::size_t>(layout.element)];
        layout.strips = is_strips;
        layout.fields.resize(e.properties.size());
        for (std::size_t i = 0; i < e.properties.size(); ++i) {
            layout.fields[i].type = e.properties[i].type;
            layout.fields[i].count_type = e.properties[i].count_type;
        }
        int idx = e.find_property("vertex_indices");
        if (idx < 0) idx = e.find_property("vertex_index");
        if (idx < 0)
            fail(Error::Kind::format, "element " + show(e.name) + " has no vertex_indices list");
        const PlyProperty& ip = e.properties[static_cast<std::size_t>(idx)];
        if (!ip.is_list() || !is_integer(ip.type))
            fail(Error::Kind::format, "property " + show(ip.name) + " of element " + show(e.name) +
                                          " must be a list of integers, not " +
                                          (ip.is_list() ? "a list of " : "a scalar ") + ply_type_name(ip.type));
        layout.fields[static_cast<std::size_t>(idx)].role = FaceRole::indices;
        if (!is_strips) {
            if (const int t = e.find_property("texcoord"); t >= 0) {
                if (!e.properties[static_cast<std::size_t>(t)].is_list())
                    fail(Error::Kind::format, "property 'texcoord' of element 'face' must be a list (2 values per corner)");
                layout.fields[static_cast<std::size_t>(t)].role = FaceRole::texcoord;
            }
            if (const int t = e.find_property("texnumber"); t >= 0) {
                if (e.properties[static_cast<std::size_t>(t)].is_list())
                    fail(Error::Kind::format, "property 'texnumber' of element 'face' must be a scalar");
                layout.fields[static_cast<std::size_t>(t)].role = FaceRole::texnumber;
            }
        }
        layout.fast_triangles = !ascii && !swap && !is_strips && e.properties.size() == 1 &&
                                ip.count_type == PlyType::uint8 &&
                                (ip.type == PlyType::int32 || ip.type == PlyType::uint32);
    }

    // ---- element bookkeeping ----

    const PlyElement* current() const {
        return element < header.elements.size() ? &header.elements[element] : nullptr;
    }

    std::uint64_t record_index() const { return header.elements[element].count - remaining; }

    // Moves past finished (and empty) elements.
    void advance() {
        while (element < header.elements.size() && remaining == 0) {
            ++element;
            if (element < header.elements.size()) remaining = header.elements[element].count;
        }
        if (element == header.elements.size()) check_trailing_bytes();
    }

    // A binary file whose header announces fewer records than it holds reads later elements from the
    // earlier ones' bytes (faces from vertex data: 0 triangles, "no problems found"); the data left
    // after the last element shows it. A few bytes of whitespace or zero padding are tolerated.
    void check_trailing_bytes() {
        if (ascii || end_checked) return;
        end_checked = true;
        const std::uint64_t here = in.offset();
        const std::uint64_t left = in.size() > here ? in.size() - here : 0;
        if (left == 0) return;
        constexpr std::uint64_t kPadding = 64;
        bool padding = left <= kPadding && in.ensure(static_cast<std::size_t>(left));
        for (std::size_t i = 0; padding && i < left; ++i)
            padding = in.cur[i] == 0 || std::isspace(static_cast<unsigned char>(in.cur[i]));
        if (!padding)
            fail(Error::Kind::format, std::to_string(left) + " bytes of data follow the last element (from byte " +
                                          std::to_string(here) + "): the header's element counts are smaller than the data");
    }

    void consumed(std::uint64_t n) {
        remaining -= n;
        advance();
    }

    std::string record_name() const {
        const PlyElement& e = header.elements[element];
        return "element " + show(e.name) + " record " + std::to_string(record_index()) + " (of " +
               std::to_string(e.count) + ")";
    }

    [[noreturn]] void truncated() const {
        fail(Error::Kind::format, record_name() + ": the data ends at " +
                                      (ascii ? "line " + std::to_string(line + 1) + ", " : std::string()) + "byte " +
                                      std::to_string(in.offset()) + " (truncated, or the header's count is too large)");
    }

    [[noreturn]] void bad_value(std::size_t property, std::string_view token, const char* why) const {
        const PlyElement& e = header.elements[element];
        fail(Error::Kind::format, "line " + std::to_string(line + 1) + ": " + why + " " + show(token) +
                                      " for property " + show(e.properties[property].name) + " of " + record_name());
    }

    // ---- ASCII values ----

    // Before a record: blank lines are allowed between records.
    void ascii_record_start() {
        for (;;) {
            in.prefetch(kTokenWindow);
            while (in.cur < in.lim && is_space(*in.cur)) {
                if (*in.cur == '\n') ++line;
                ++in.cur;
            }
            if (in.cur < in.lim) return;
            if (in.at_end()) truncated();
        }
    }

    // After a record: the rest of its line must be blank.
    void ascii_record_end() {
        for (;;) {
            in.prefetch(kTokenWindow);
            while (in.cur < in.lim && is_blank(*in.cur)) ++in.cur;
            if (in.cur < in.lim) break;
            if (in.at_end()) return;
        }
        if (*in.cur == '\n') {
            ++line;
            ++in.cur;
            return;
        }
        const char* end = in.cur;
        while (end < in.lim && !is_space(*end)) ++end;
        fail(Error::Kind::format, "line " + std::to_string(line + 1) + ": unexpected " +
                                      show(std::string_view(in.cur, static_cast<std::size_t>(end - in.cur))) +
                                      " after the last property of " + record_name() +
                                      " (more values than the header declares)");
    }

    // One number on the current line, parsed as `type`.
    double ascii_value(PlyType type, std::size_t property) {
        for (;;) {
            in.prefetch(kTokenWindow);
            while (in.cur < in.lim && is_blank(*in.cur)) ++in.cur;
            if (in.cur < in.lim) break;
            if (in.at_end()) truncated();
        }
        if (*in.cur == '\n') {
            const PlyElement& e = header.elements[element];
            fail(Error::Kind::format, "line " + std::to_string(line + 1) + ": the line ends before property " +
                                          show(e.properties[property].name) + " of " + record_name() +
                                          " (fewer values than the header declares)");
        }
        in.prefetch(kTokenWindow);
        double value = 0;
        if (fast_number(type, value)) return value;
        return slow_number(type, property);
    }

    // Plain decimals ("-12", "0.0597022"), which is what scanners and exporters write. Exact: the digits
    // fit the mantissa and the power of ten is exact, so one IEEE division rounds correctly (Clinger's
    // fast path) and gives what from_chars gives. Anything else (exponents, long mantissas, nan, inf,
    // errors) goes to slow_number.
    bool fast_number(PlyType type, double& value) {
        const char* p = in.cur;
        const char* const lim = in.lim;
        const bool negative = *p == '-';
        if (*p == '-' || *p == '+') ++p;
        std::uint64_t mantissa = 0;
        int digits = 0, fraction = 0;
        for (; p < lim && static_cast<unsigned>(*p - '0') < 10; ++p, ++digits)
            mantissa = mantissa * 10 + static_cast<unsigned>(*p - '0');
        if (p < lim && *p == '.') {
            if (is_integer(type)) return false;
            for (++p; p < lim && static_cast<unsigned>(*p - '0') < 10; ++p, ++digits, ++fraction)
                mantissa = mantissa * 10 + static_cast<unsigned>(*p - '0');
        }
        if (digits == 0 || digits > 19) return false;
        if (p < lim ? !is_space(*p) : !in.lim_is_end()) return false;
        static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                            1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
        if (type == PlyType::float32) {
            if (mantissa > (1u << 24) || fraction > 10) return false;
            const float f = static_cast<float>(mantissa) / static_cast<float>(kPow10[fraction]);
            value = negative ? -f : f;
        } else if (type == PlyType::float64) {
            if (mantissa > (std::uint64_t(1) << 53) || fraction > 22) return false;
            const double d = static_cast<double>(mantissa) / kPow10[fraction];
            value = negative ? -d : d;
        } else {
            if (digits > 18) return false;
            value = negative ? -static_cast<double>(mantissa) : static_cast<double>(mantissa);
            double lo, hi;
            type_range(type, lo, hi);
            if (value < lo || value > hi) return false;  // slow_number words the error
        }
        in.cur = p;
        return true;
    }

    double slow_number(PlyType type, std::size_t property) {
        const char* begin = in.cur;
        const char* p = *begin == '+' ? begin + 1 : begin;
        double value = 0;
        const char* end = nullptr;
        if (type == PlyType::float32) {
            float f = 0;
            const auto r = std::from_chars(p, in.lim, f);
            if (r.ec == std::errc()) {
                end = r.ptr;
                value = f;
            }
        } else {
            bool parsed = false;
            if (is_integer(type)) {
                std::int64_t i = 0;
                const auto r = std::from_chars(p, in.lim, i);
                if (r.ec == std::errc() && (r.ptr == in.lim || is_space(*r.ptr))) {
                    end = r.ptr;
                    value = static_cast<double>(i);
                    parsed = true;
                }
            }
            if (!parsed) {  // a double, or an integer written as "3.0" / "1e2"
                const auto r = std::from_chars(p, in.lim, value);
                end = r.ec == std::errc() ? r.ptr : nullptr;
            }
        }
        const char* token_end = begin;
        while (token_end < in.lim && !is_space(*token_end)) ++token_end;
        const std::string_view token(begin, static_cast<std::size_t>(token_end - begin));
        if (!end || end != token_end) bad_value(property, token, "bad value");
        if (token_end == in.lim && !in.lim_is_end()) bad_value(property, token, "overlong value");
        if (is_integer(type)) {
            double lo, hi;
            type_range(type, lo, hi);
            if (value != std::floor(value)) bad_value(property, token, "not an integer:");
            if (!(value >= lo && value <= hi))
                bad_value(property, token, (std::string("value out of range for ") + ply_type_name(type) + ":").c_str());
        }
        in.cur = end;
        return value;
    }

    // ---- generic values (either encoding) ----

    double value(PlyType type, std::size_t property) {
        if (ascii) return ascii_value(type, property);
        const std::size_t n = ply_type_size(type);
        if (!in.ensure(n)) truncated();
        const double v = load_value(type, in.cur, swap);
        in.cur += n;
        return v;
    }

    // Reads a list length and checks it against the data left, so it can size loops and buffers.
    std::uint64_t list_count(PlyType count_type, PlyType item_type, std::size_t property) {
        const std::uint64_t at = in.offset();
        const double v = value(count_type, property);
        const PlyElement& e = header.elements[element];
        if (v < 0)
            fail(Error::Kind::format, where() + ": negative list length " + std::to_string(static_cast<long long>(v)) +
                                          " for property " + show(e.properties[property].name) + " of " +
                                          record_name());
        const auto n = static_cast<std::uint64_t>(v);
        const std::uint64_t left = in.size() - std::min(in.size(), in.offset());
        const std::uint64_t min_bytes = ascii ? saturating_mul(n, 2) : saturating_mul(n, ply_type_size(item_type));
        if (min_bytes > left + (ascii ? 1 : 0))
            fail(Error::Kind::format, "byte " + std::to_string(at) + (ascii ? " (line " + std::to_string(line + 1) + ")" : "") +
                                          ": list length " + std::to_string(n) + " for property " +
                                          show(e.properties[property].name) + " of " + record_name() +
                                          " is larger than the rest of the file");
        return n;
    }

    void skip_values(PlyType type, std::uint64_t n, std::size_t property) {
        if (!ascii) {
            if (!in.skip(n * ply_type_size(type))) truncated();
            return;
        }
        for (std::uint64_t k = 0; k < n; ++k) ascii_value(type, property);
    }

    // ---- vertices ----

    std::size_t read_vertices(std::span<Vec3f> positions, std::span<Vec3f> normals, std::span<Vec4f> colors,
                              std::span<Vec2f> texcoords) {
        if (!current() || static_cast<int>(element) != vertex_element)
            fail(Error::Kind::argument, "read_vertices called while the reader is at element " +
                                            show(current() ? current()->name : std::string("<end>")));
        const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(positions.size(), remaining));
        auto too_short = [&](std::size_t size) { return size != 0 && size < n; };
        if (too_short(normals.size()) || too_short(colors.size()) || too_short(texcoords.size()))
            fail(Error::Kind::argument, "read_vertices: an attribute span is shorter than the positions span");
        const bool want_normals = attributes.normals && !normals.empty();
        const bool want_colors = attributes.colors && !colors.empty();
        const bool want_texcoords = attributes.texcoords && !texcoords.empty();
        const std::uint64_t first = record_index();

        // `remaining` drops record by record so that messages name the record that failed.
        std::size_t done = 0;
        if (vertex_fast_xyz) {
            while (done < n) {
                const std::size_t k = std::min<std::size_t>(n - done, static_cast<std::size_t>(in.lim - in.cur) / 12);
                if (k == 0) {
                    if (!in.ensure(12)) truncated();
                    continue;
                }
                std::memcpy(static_cast<void*>(positions.data() + done), in.cur, k * 12);
                in.cur += k * 12;
                done += k;
                remaining -= k;
            }
        } else {
            float slots[kSlotCount] = {};
            const std::size_t record_size = ascii ? 0 : vertex_record_size;
            for (; done < n; ++done, --remaining) {
                slots[kAlpha] = 1.f;
                if (record_size) {
                    if (!in.ensure(record_size)) truncated();
                    for (const VertexField& f : vertex_fields)
                        if (f.slot != kSkip)
                            slots[f.slot] = static_cast<float>(load_value(f.type, in.cur + f.offset, swap)) / f.divisor;
                    in.cur += record_size;
                } else {
                    read_vertex_record(slots);
                }
                positions[done] = {slots[kX], slots[kY], slots[kZ]};
                if (want_normals) normals[done] = {slots[kNx], slots[kNy], slots[kNz]};
                if (want_colors) colors[done] = {slots[kRed], slots[kGreen], slots[kBlue], slots[kAlpha]};
                if (want_texcoords) texcoords[done] = {slots[kU], slots[kV]};
            }
        }
        for (std::size_t i = 0; i < n; ++i)
            if (!is_finite(positions[i]))
                fail(Error::Kind::invalid, "vertex " + std::to_string(first + i) + " has a non-finite position (" +
                                               std::to_string(positions[i].x) + ", " + std::to_string(positions[i].y) +
                                               ", " + std::to_string(positions[i].z) + ")");
        advance();
        return n;
    }

    // One vertex record, property by property (ASCII, or binary with lists).
    void read_vertex_record(float* slots) {
        if (ascii) ascii_record_start();
        for (std::size_t i = 0; i < vertex_fields.size(); ++i) {
            const VertexField& f = vertex_fields[i];
            if (f.count_type != PlyType::none) {
                skip_values(f.type, list_count(f.count_type, f.type, i), i);
            } else {
                const double v = value(f.type, i);
                if (f.slot != kSkip) slots[f.slot] = static_cast<float>(v) / f.divisor;
            }
        }
        if (ascii) ascii_record_end();
    }

    // ---- faces and strips ----

    const FaceLayout* face_layout() const {
        if (faces.element >= 0 && static_cast<std::size_t>(faces.element) == element) return &faces;
        if (strips.element >= 0 && static_cast<std::size_t>(strips.element) == element) return &strips;
        return nullptr;
    }

    [[noreturn]] void bad_index(std::int64_t index, const FaceLayout& layout) const {
        fail(Error::Kind::invalid, std::string(layout.strips ? "triangle strip " : "face ") +
                                       std::to_string(record_index()) + ": vertex index " + std::to_string(index) +
                                       " is out of range (" + std::to_string(vertex_count) + " vertices; " + where() + ")");
    }

    std::size_t read_faces(std::size_t max_records, PlyFaceChunk& out) {
        const FaceLayout* layout = current() ? face_layout() : nullptr;
        if (!layout)
            fail(Error::Kind::argument, "read_faces called while the reader is at element " +
                                            show(current() ? current()->name : std::string("<end>")));
        const bool has_uv = !layout->strips && std::any_of(layout->fields.begin(), layout->fields.end(),
                                                           [](const FaceField& f) { return f.role == FaceRole::texcoord; });
        const bool has_texnumber = !layout->strips && std::any_of(layout->fields.begin(), layout->fields.end(),
                                                                  [](const FaceField& f) { return f.role == FaceRole::texnumber; });
        const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(max_records, remaining));
        const auto vcount = static_cast<std::uint32_t>(vertex_count);
        std::size_t done = 0;
        while (done < n) {
            if (layout->fast_triangles) {
                // Common case: `list uchar int` triangles in native order, straight from the buffer.
                while (done < n && in.lim - in.cur >= 13 && static_cast<unsigned char>(*in.cur) == 3) {
                    std::uint32_t tri[3];
                    std::memcpy(tri, in.cur + 1, 12);
                    if (tri[0] >= vcount || tri[1] >= vcount || tri[2] >= vcount) {
                        const std::uint32_t bad = tri[0] >= vcount ? tri[0] : (tri[1] >= vcount ? tri[1] : tri[2]);
                        bad_index(layout->fields[0].type == PlyType::int32 ? static_cast<std::int32_t>(bad)
                                                                           : static_cast<std::int64_t>(bad),
                                  *layout);
                    }
                    out.indices.insert(out.indices.end(), tri, tri + 3);
                    in.cur += 13;
                    ++done;
                    --remaining;
                }
                if (done == n) break;
            }
            std::int64_t texnumber = 0;
            read_face_record(*layout, texnumber);
            if (layout->strips) emit_strip(*layout, out);
            else emit_polygon(*layout, has_uv, has_texnumber, texnumber, out);
            ++done;
            --remaining;
        }
        out.faces_read += done;
        advance();
        return done;
    }

    void read_face_record(const FaceLayout& layout, std::int64_t& texnumber) {
        corner_indices.clear();
        corner_uvs.clear();
        if (ascii) ascii_record_start();
        for (std::size_t i = 0; i < layout.fields.size(); ++i) {
            const FaceField& f = layout.fields[i];
            if (f.count_type == PlyType::none) {
                const double v = value(f.type, i);
                if (f.role == FaceRole::texnumber) texnumber = std::isnan(v) ? -1 : static_cast<std::int64_t>(std::clamp(v, -1e18, 1e18));
                continue;
            }
            const std::uint64_t count = list_count(f.count_type, f.type, i);
            if (f.role == FaceRole::skip) {
                skip_values(f.type, count, i);
                continue;
            }
            const auto c = static_cast<std::size_t>(count);
            if (!ascii) {
                const std::size_t item = ply_type_size(f.type);
                if (!in.ensure(c * item)) truncated();
                if (f.role == FaceRole::indices) {
                    for (std::size_t k = 0; k < c; ++k)
                        corner_indices.push_back(static_cast<std::int64_t>(load_value(f.type, in.cur + k * item, swap)));
                } else {
                    for (std::size_t k = 0; k < c; ++k)
                        corner_uvs.push_back(static_cast<float>(load_value(f.type, in.cur + k * item, swap)));
                }
                in.cur += c * item;
            } else if (f.role == FaceRole::indices) {
                for (std::size_t k = 0; k < c; ++k) corner_indices.push_back(static_cast<std::int64_t>(ascii_value(f.type, i)));
            } else {
                for (std::size_t k = 0; k < c; ++k) corner_uvs.push_back(static_cast<float>(ascii_value(f.type, i)));
            }
        }
        if (ascii) ascii_record_end();
    }

    void emit_polygon(const FaceLayout& layout, bool has_uv, bool has_texnumber, std::int64_t texnumber,
                      PlyFaceChunk& out) {
        const std::size_t n = corner_indices.size();
        for (std::int64_t index : corner_indices)
            if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count) bad_index(index, layout);
        if (has_uv && !corner_uvs.empty() && corner_uvs.size() != 2 * n)
            fail(Error::Kind::format, "face " + std::to_string(record_index()) + ": the texcoord list has " +
                                          std::to_string(corner_uvs.size()) + " values for " + std::to_string(n) +
                                          " corners (" + where() + ")");
        if (has_texnumber && !header.texture_files.empty() &&
            (texnumber < 0 || static_cast<std::uint64_t>(texnumber) >= header.texture_files.size()))
            fail(Error::Kind::invalid, "face " + std::to_string(record_index()) + ": texnumber " +
                                           std::to_string(texnumber) + " is out of range (" +
                                           std::to_string(header.texture_files.size()) + " TextureFile comments)");
        if (n < 3) {
            ++out.skipped_faces;
            return;
        }
        auto corner_uv = [&](std::size_t k) {
            if (corner_uvs.empty()) return Vec2f{std::nanf(""), std::nanf("")};
            return Vec2f{corner_uvs[2 * k], corner_uvs[2 * k + 1]};
        };
        for (std::size_t k = 1; k + 1 < n; ++k) {  // fan from the first corner
            out.indices.push_back(static_cast<std::uint32_t>(corner_indices[0]));
            out.indices.push_back(static_cast<std::uint32_t>(corner_indices[k]));
            out.indices.push_back(static_cast<std::uint32_t>(corner_indices[k + 1]));
            if (has_uv) {
                out.corner_texcoords.push_back(corner_uv(0));
                out.corner_texcoords.push_back(corner_uv(k));
                out.corner_texcoords.push_back(corner_uv(k + 1));
            }
            if (has_texnumber) out.texnumbers.push_back(texnumber);
        }
    }

    // Stanford tristrips: -1 restarts a strip; every second triangle of a strip flips its winding.
    void emit_strip(const FaceLayout& layout, PlyFaceChunk& out) {
        std::size_t run = 0;  // corners in the current strip so far
        std::int64_t a = 0, b = 0;
        for (std::int64_t index : corner_indices) {
            if (index == -1 || index == 0xFFFFFFFFll) {  // restart (int -1, or uint 0xFFFFFFFF)
                run = 0;
                continue;
            }
            if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count) bad_index(index, layout);
            if (run >= 2) {
                if (a == b || b == index || a == index) {
                    ++out.dropped_strip_triangles;
                } else if (run % 2 == 0) {
                    out.indices.insert(out.indices.end(), {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                                                           static_cast<std::uint32_t>(index)});
                } else {
                    out.indices.insert(out.indices.end(), {static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(a),
                                                           static_cast<std::uint32_t>(index)});
                }
            }
            a = b;
            b = index;
            ++run;
        }
    }

    // ---- skipping ----

    void skip_element() {
        const PlyElement* e = current();
        if (!e) return;
        if (e->properties.empty()) {  // such records take no bytes
            consumed(remaining);
            return;
        }
        if (!ascii) {
            std::uint64_t fixed = 0;
            bool has_list = false;
            for (const PlyProperty& p : e->properties) {
                has_list |= p.is_list();
                fixed += ply_type_size(p.type);
            }
            if (!has_list) {
                if (!in.skip(remaining * fixed)) truncated();
                consumed(remaining);
                return;
            }
        }
        while (remaining > 0) {
            if (ascii) ascii_record_start();
            for (std::size_t i = 0; i < e->properties.size(); ++i) {
                const PlyProperty& p = e->properties[i];
                if (p.is_list()) skip_values(p.type, list_count(p.count_type, p.type, i), i);
                else skip_values(p.type, 1, i);
            }
            if (ascii) ascii_record_end();
            --remaining;
        }
        advance();
    }
};

// ---- PlyReader ------------------------------------------------------------------------------------

PlyReader::PlyReader(const std::string& path) : impl_(std::make_unique<Impl>()) {
    impl_->in.open_file(path);
    impl_->init();
}

PlyReader::PlyReader(std::span<const std::byte> data, std::string name) : impl_(std::make_unique<Impl>()) {
    impl_->in.set_name(std::move(name));
    impl_->in.open_memory(reinterpret_cast<const char*>(data.data()), data.size());
    impl_->init();
}

PlyReader::~PlyReader() = default;
PlyReader::PlyReader(PlyReader&&) noexcept = default;
PlyReader& PlyReader::operator=(PlyReader&&) noexcept = default;

const PlyHeader& PlyReader::header() const { return impl_->header; }
const std::string& PlyReader::path() const { return impl_->in.path(); }
std::uint64_t PlyReader::file_size() const { return impl_->in.size(); }
std::uint64_t PlyReader::position() const { return impl_->in.offset(); }
const PlyElement* PlyReader::current_element() const { return impl_->current(); }
std::uint64_t PlyReader::remaining() const { return impl_->current() ? impl_->remaining : 0; }
bool PlyReader::at_vertices() const {
    return impl_->current() && static_cast<int>(impl_->element) == impl_->vertex_element;
}
bool PlyReader::at_faces() const { return impl_->current() && impl_->face_layout(); }
std::uint64_t PlyReader::vertex_count() const { return impl_->vertex_count; }
PlyVertexAttributes PlyReader::vertex_attributes() const { return impl_->attributes; }

bool PlyReader::has_corner_texcoords() const {
    return std::any_of(impl_->faces.fields.begin(), impl_->faces.fields.end(),
                       [](const FaceField& f) { return f.role == FaceRole::texcoord; });
}

bool PlyReader::has_texnumbers() const {
    return std::any_of(impl_->faces.fields.begin(), impl_->faces.fields.end(),
                       [](const FaceField& f) { return f.role == FaceRole::texnumber; });
}

std::size_t PlyReader::read_vertices(std::span<Vec3f> positions, std::span<Vec3f> normals, std::span<Vec4f> colors,
                                     std::span<Vec2f> texcoords) {
    return impl_->read_vertices(positions, normals, colors, texcoords);
}

std::size_t PlyReader::read_faces(std::size_t max_records, PlyFaceChunk& out) {
    return impl_->read_faces(max_records, out);
}

void PlyReader::skip_element() { impl_->skip_element(); }

void PlyReader::seek_ascii_record(std::size_t element, std::uint64_t record, std::uint64_t byte_offset, std::uint64_t line) {
    Impl& m = *impl_;
    if (!m.ascii) m.fail(Error::Kind::argument, "seek_ascii_record on a binary file");
    if (element >= m.header.elements.size() || element < m.element || record > m.header.elements[element].count ||
        byte_offset < m.in.offset())
        m.fail(Error::Kind::argument, "seek_ascii_record: cannot move back or past the element");
    if (!m.in.skip(byte_offset - m.in.offset())) m.truncated();
    m.element = element;
    m.remaining = m.header.elements[element].count - record;
    m.line = line;
    m.advance();
}

std::uint64_t PlyReader::line() const { return impl_->line; }

// ---- read_ply -------------------------------------------------------------------------------------

namespace {

constexpr std::size_t kChunk = 1 << 16;
constexpr const char* kStage = "Reading PLY";

// Splits wedges: the first corner that uses stored vertex i gives it its texcoord; a corner with a
// different texcoord gets (or reuses) a copy of i with the same position id.
void split_wedges(Mesh& mesh, const std::vector<Vec2f>& corners, bool vertices_have_texcoords, const std::string& path) {
    struct Key {
        std::uint32_t vertex;
        std::uint32_t u, v;
        bool operator==(const Key&) const = default;
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = k.vertex * 0x9E3779B97F4A7C15ull;
            h ^= (static_cast<std::uint64_t>(k.u) << 32 | k.v) + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2);
            return static_cast<std::size_t>(h ^ (h >> 31));
        }
    };
    auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f == 0.f ? 0.f : f); };  // -0 == +0

    const std::size_t stored = mesh.positions.size();
    if (mesh.texcoords.empty()) mesh.texcoords.assign(1, std::vector<Vec2f>(stored));
    std::vector<bool> assigned(stored, vertices_have_texcoords);
    std::unordered_map<Key, std::uint32_t, KeyHash> copies;
    ensure_position_ids(mesh);
    for (std::size_t c = 0; c < corners.size(); ++c) {
        const Vec2f uv = corners[c];
        if (std::isnan(uv.x) || std::isnan(uv.y)) continue;  // this face has no wedge texcoords
        const std::uint32_t v = mesh.indices[c];
        if (!assigned[v]) {
            mesh.texcoords[0][v] = uv;
            assigned[v] = true;
            continue;
        }
        const Vec2f have = mesh.texcoords[0][v];
        if (bits(have.x) == bits(uv.x) && bits(have.y) == bits(uv.y)) continue;
        const Key key{v, bits(uv.x), bits(uv.y)};
        auto [it, inserted] = copies.try_emplace(key, 0u);
        if (inserted) {
            if (mesh.positions.size() >= std::numeric_limits<std::uint32_t>::max())
                throw_error(Error::Kind::unsupported, path, "splitting texture seams needs more than 2^32 vertices");
            it->second = duplicate_vertex(mesh, v);
            mesh.texcoords[0][it->second] = uv;
        }
        mesh.indices[c] = it->second;
    }
}

}  // namespace

Mesh read_ply(PlyReader& reader, Progress* progress) {
    const PlyHeader& header = reader.header();
    if (!header.find_element("vertex")) throw_error(Error::Kind::invalid, reader.path(), "the file has no vertex element");
    const double size = std::max<double>(1.0, static_cast<double>(reader.file_size()));
    check_progress(progress, 0.0, kStage);

    Mesh mesh;
    mesh.source_dir = std::filesystem::path(reader.path()).parent_path().string();
    const PlyVertexAttributes attributes = reader.vertex_attributes();
    const auto vertex_count = static_cast<std::size_t>(reader.vertex_count());
    // Sizes are safe to allocate: the reader has checked the counts against the file size.
    mesh.positions.resize(vertex_count);
    if (attributes.normals) mesh.normals.resize(vertex_count);
    if (attributes.colors) mesh.colors.assign(vertex_count, Vec4f{0, 0, 0, 1});
    if (attributes.texcoords) mesh.texcoords.assign(1, std::vector<Vec2f>(vertex_count));

    PlyFaceChunk faces;
    if (const PlyElement* f = header.find_element("face")) {
        // Reserve for triangles, capped by what the rest of the file can hold (at least 8 bytes each).
        const std::uint64_t cap = reader.file_size() / 8;
        faces.indices.reserve(3 * static_cast<std::size_t>(std::min(f->count, cap)));
    }

    std::size_t vertices_done = 0;
    while (reader.current_element()) {
        if (reader.at_vertices()) {
            const std::size_t k = std::min(kChunk, vertex_count - vertices_done);
            auto sub = [&](auto& v) { return v.empty() ? std::span<typename std::decay_t<decltype(v)>::value_type>{}
                                                       : std::span(v).subspan(vertices_done, k); };
            reader.read_vertices(std::span(mesh.positions).subspan(vertices_done, k), sub(mesh.normals),
                                 sub(mesh.colors), mesh.texcoords.empty() ? std::span<Vec2f>{} : sub(mesh.texcoords[0]));
            vertices_done += k;
        } else if (reader.at_faces()) {
            reader.read_faces(kChunk, faces);
        } else {
            reader.skip_element();
        }
        check_progress(progress, static_cast<double>(reader.position()) / size, kStage);
    }
    mesh.indices = std::move(faces.indices);

    for (const std::string& file : header.texture_files) {
        Material& m = mesh.materials.emplace_back();
        m.name = std::filesystem::path(file).stem().string();
        m.base_color_texture.path = file;
    }
    if (!mesh.materials.empty()) {
        if (!faces.texnumbers.empty()) mesh.face_materials.assign(faces.texnumbers.begin(), faces.texnumbers.end());
        else mesh.face_materials.assign(mesh.triangle_count(), 0u);
    }
    if (!faces.corner_texcoords.empty()) split_wedges(mesh, faces.corner_texcoords, attributes.texcoords, reader.path());
    check_progress(progress, 1.0, kStage);
    return mesh;
}

Mesh read_ply(const std::string& path, Progress* progress) {
    PlyReader reader(path);
    return read_ply(reader, progress);
}

}  // namespace lodforge
