// PLY writer: ASCII or binary (either byte order), through AtomicFile so a failed or cancelled write
// never leaves a partial file. Records are formatted into a 1 MiB buffer and written in blocks; ASCII
// floats use std::to_chars (shortest text that reads back to the same float), so ASCII round trips
// are exact too.

#include "io/ply_internal.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

namespace lodforge {

namespace {

constexpr std::size_t kFlushBytes = std::size_t(1) << 20;
constexpr const char* kStage = "Writing PLY";

class Writer {
public:
    Writer(AtomicFile& file, PlyEncoding encoding, Progress* progress, std::uint64_t total_records)
        : file_(file),
          ascii_(encoding == PlyEncoding::ascii),
          swap_(!ascii_ && ((encoding == PlyEncoding::binary_big_endian) != (std::endian::native == std::endian::big))),
          progress_(progress),
          total_(std::max<std::uint64_t>(1, total_records)) {
        buffer_.reserve(kFlushBytes + 4096);
    }

    void text(std::string_view s) { buffer_.append(s); }

    void f32(float v) {
        if (ascii_) {
            char tmp[32];
            const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
            separator();
            buffer_.append(tmp, r.ptr);
        } else {
            raw(std::bit_cast<std::uint32_t>(v));
        }
    }

    void u8(std::uint8_t v) {
        if (ascii_) integer(v);
        else buffer_.push_back(static_cast<char>(v));
    }

    void u32(std::uint32_t v) {
        if (ascii_) integer(v);
        else raw(v);
    }

    void end_record() {
        if (ascii_) buffer_.push_back('\n');
        first_ = true;
        ++records_;
        if (buffer_.size() >= kFlushBytes) {
            flush();
            check_progress(progress_, static_cast<double>(records_) / static_cast<double>(total_), kStage);
        }
    }

    void flush() {
        if (buffer_.empty()) return;
        file_.stream().write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
        if (!file_.stream())
            throw_error(Error::Kind::io, file_.target_path(),
                        "write failed after " + std::to_string(written_) + " bytes (disk full or I/O error)");
        written_ += buffer_.size();
        buffer_.clear();
    }

private:
    void separator() {
        if (!first_) buffer_.push_back(' ');
        first_ = false;
    }

    void integer(std::uint32_t v) {
        char tmp[16];
        const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
        separator();
        buffer_.append(tmp, r.ptr);
    }

    void raw(std::uint32_t v) {
        if (swap_) v = __builtin_bswap32(v);
        char bytes[4];
        std::memcpy(bytes, &v, 4);
        buffer_.append(bytes, 4);
    }

    AtomicFile& file_;
    bool ascii_;
    bool swap_;
    Progress* progress_;
    std::uint64_t total_;
    std::uint64_t records_ = 0;
    std::uint64_t written_ = 0;
    bool first_ = true;
    std::string buffer_;
};

const char* encoding_name(PlyEncoding e) {
    switch (e) {
        case PlyEncoding::ascii: return "ascii";
        case PlyEncoding::binary_little_endian: return "binary_little_endian";
        case PlyEncoding::binary_big_endian: return "binary_big_endian";
    }
    return "binary_little_endian";
}

std::uint8_t to_u8(float c) {
    if (!(c > 0.f)) return 0;  // also NaN
    if (c >= 1.f) return 255;
    return static_cast<std::uint8_t>(std::lround(c * 255.f));
}

// A header line must stay one line whatever the texture path contains.
std::string one_line(std::string s) {
    std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    return s;
}

void check_sizes(const Mesh& mesh, const std::string& path) {
    const std::size_t n = mesh.positions.size();
    auto bad = [&](const char* what) {
        throw_error(Error::Kind::argument, path, std::string("cannot write PLY: ") + what);
    };
    if (!mesh.normals.empty() && mesh.normals.size() != n) bad("the normals array does not match the vertex count");
    if (!mesh.colors.empty() && mesh.colors.size() != n) bad("the colors array does not match the vertex count");
    if (!mesh.texcoords.empty() && mesh.texcoords[0].size() != n) bad("texcoord set 0 does not match the vertex count");
    if (mesh.indices.size() % 3 != 0) bad("the index count is not a multiple of 3");
    for (std::uint32_t i : mesh.indices)
        if (i >= n) bad(("vertex index " + std::to_string(i) + " is out of range").c_str());
}

}  // namespace

void write_ply(const Mesh& mesh, const std::string& path, const WriteOptions& options, Progress* progress) {
    check_sizes(mesh, path);
    const bool normals = options.write_normals && mesh.has_normals();
    const bool colors = options.write_colors && mesh.has_colors();
    const bool texcoords = options.write_texcoords && mesh.has_texcoords();
    const bool uchar_colors = options.ply_colors_as_uchar;
    const bool texnumbers = options.ply_face_materials && !mesh.face_materials.empty();
    if (texnumbers && mesh.face_materials.size() != mesh.triangle_count())
        throw_error(Error::Kind::argument, path, "cannot write PLY: face_materials does not match the triangle count");
    // int indices as most readers expect; uint only when the count needs the 32nd bit.
    const bool uint_indices = mesh.positions.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
    check_progress(progress, 0.0, kStage);

    std::string header = "ply\nformat ";
    header += encoding_name(options.ply_encoding);
    header += " 1.0\ncomment written by LodForge\n";
    if (!texnumbers && !mesh.materials.empty() && !mesh.materials[0].base_color_texture.path.empty())
        header += "comment TextureFile " + one_line(mesh.materials[0].base_color_texture.path) + "\n";
    header += "element vertex " + std::to_string(mesh.positions.size()) + "\n";
    header += "property float x\nproperty float y\nproperty float z\n";
    if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
    if (colors) {
        const char* t = uchar_colors ? "uchar" : "float";
        for (const char* c : {"red", "green", "blue", "alpha"}) header += std::string("property ") + t + " " + c + "\n";
    }
    if (texcoords) header += "property float u\nproperty float v\n";
    header += "element face " + std::to_string(mesh.triangle_count()) + "\n";
    header += uint_indices ? "property list uchar uint vertex_indices\n" : "property list uchar int vertex_indices\n";
    if (texnumbers) header += "property uint texnumber\n";
    header += "end_header\n";

    AtomicFile file(path, true);
    Writer w(file, options.ply_encoding, progress, mesh.positions.size() + mesh.triangle_count());
    w.text(header);

    const std::vector<Vec2f>* uv = texcoords ? &mesh.texcoords[0] : nullptr;
    auto vec3 = [&w](Vec3f v) {
        w.f32(v.x);
        w.f32(v.y);
        w.f32(v.z);
    };
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        vec3(mesh.positions[i]);
        if (normals) vec3(mesh.normals[i]);
        if (colors) {
            const Vec4f c = mesh.colors[i];
            for (float channel : {c.x, c.y, c.z, c.w}) {
                if (uchar_colors) w.u8(to_u8(channel));
                else w.f32(channel);
            }
        }
        if (uv) {
            w.f32((*uv)[i].x);
            w.f32((*uv)[i].y);
        }
        w.end_record();
    }
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        w.u8(3);
        for (std::size_t k = 0; k < 3; ++k) w.u32(mesh.indices[t + k]);
        if (texnumbers) w.u32(mesh.face_materials[t / 3]);
        w.end_record();
    }
    w.flush();
    file.commit();
    if (progress) progress->report(1.0, kStage);  // committed: too late to cancel
}

}  // namespace lodforge
