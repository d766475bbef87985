// Morph LODStrips runtime: one LODStrips strip set and change set for a morphing mesh, with per-frame
// vertex positions and normals blended on the GPU-facing vertex buffer.
// Single header, C++17, standard library only; needs lodstrips_runtime.h next to it (same rules).
// Format and design: docs/morph.md ("Morph LODStrips") in the LodForge repository. Follows Ramos,
// "LodStrips" (UJI thesis, 2008), ch. 6: a supermesh whose frames share one connectivity, so one strip
// set with one collapse order's change set serves every frame.
//
//   lodstrips::MorphLodStrips m;
//   std::string error;
//   if (!m.load_file("horse.lfmstrips", &error)) { ... }
//   m.set_frame(0.37);                          // t in [0, 1] over the whole sequence
//   m.go_to_lod(0.25);                          // 0 = coarsest stored level, 1 = full detail
//   upload_vertices(m.positions(), m.normals(), m.vertex_count());   // only the prefix in use
//   upload(m.indices(), m.index_count());       // afterwards only m.changes() spans
//
// Vertices are in the strips' canonical order, so a level uses the prefix [0, vertex_count()). Only that
// prefix is blended: set_frame(t) blends it, go_to_lod to a finer level blends the vertices it adds, so
// set_frame and go_to_lod commute (the drawn prefix and the element buffer are the same in either order)
// and a frame change at a coarse level costs only the coarse level's vertices.
#pragma once

#include "lodstrips_runtime.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

namespace lodstrips {

inline constexpr char morph_file_magic[8] = {'L', 'F', 'M', 'S', 'T', 'R', 'P', 'S'};
inline constexpr std::uint32_t morph_format_version = 1;
inline constexpr std::uint32_t morph_flag_quantized = 1u;  // FRMS: 16-bit positions, octahedral normals

// Everything a .lfmstrips file holds, decoded.
struct MorphData {
    Data strips;                         // one strip set + change set; its vertex arrays hold frame 0
    std::uint32_t frame_count = 0;
    std::vector<float> frame_positions;  // frame_count × 3 × vertex_count, canonical vertex order
    std::vector<float> frame_normals;    // the same layout, unit length
    bool quantized = false;              // how the file stored the frames (informational)
};

namespace detail {

// Octahedral unit vector from two signed 16-bit values (snorm, /32767).
inline void oct_decode(std::int16_t a, std::int16_t b, float* out) {
    const float u = std::max(float(a) / 32767.f, -1.f), v = std::max(float(b) / 32767.f, -1.f);
    float x = u, y = v;
    const float z = 1.f - std::fabs(u) - std::fabs(v);
    if (z < 0) {
        x = (1.f - std::fabs(v)) * (u >= 0 ? 1.f : -1.f);
        y = (1.f - std::fabs(u)) * (v >= 0 ? 1.f : -1.f);
    }
    const float len = std::sqrt(x * x + y * y + z * z);
    if (len > 0) {
        out[0] = x / len, out[1] = y / len, out[2] = z / len;
    } else {
        out[0] = 0, out[1] = 0, out[2] = 1;
    }
}

inline std::uint16_t u16_at(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | p[1] << 8); }

}  // namespace detail

// Decodes a .lfmstrips image. Returns false with a message naming the section and the problem; the
// strip records are checked by MorphLodStrips::assign (LodStrips::assign's replay).
inline bool decode_morph(const void* bytes, std::size_t size, MorphData& out, std::string* error) {
    using detail::fail;
    const auto* base = static_cast<const std::uint8_t*>(bytes);
    if (size < 32) return fail(error, "file too short for the header (" + std::to_string(size) + " bytes)");
    if (std::memcmp(base, morph_file_magic, 8) != 0) return fail(error, "not a .lfmstrips file (bad magic)");
    detail::Reader h(base + 8, 24);
    const std::uint32_t version = h.u32(), endian = h.u32(), sections = h.u32(), header_crc = h.u32();
    const std::uint32_t size_lo = h.u32(), size_hi = h.u32();
    const std::uint64_t declared = std::uint64_t(size_lo) | std::uint64_t(size_hi) << 32;
    if (endian != endian_tag) return fail(error, "unsupported byte order tag");
    if (version != morph_format_version)
        return fail(error, "unsupported format version " + std::to_string(version) + " (this reader: 1)");
    if (header_crc != detail::crc32(base, 20)) return fail(error, "header checksum mismatch");
    if (declared != size)
        return fail(error, "file is " + std::to_string(size) + " bytes, header says " + std::to_string(declared) +
                               " (truncated or padded)");
    if (sections != 2) return fail(error, "expected 2 sections, header says " + std::to_string(sections));
    static const std::uint32_t order[2] = {section_tag("LSTR"), section_tag("FRMS")};
    static const char* names[2] = {"LSTR", "FRMS"};
    const std::uint8_t* sec[2];
    std::size_t len[2];
    detail::Reader dir(base + 32, size - 32);
    for (int i = 0; i < 2; ++i) {
        const std::uint32_t tag = dir.u32(), n = dir.u32(), crc = dir.u32();
        if (!dir.ok()) return fail(error, std::string("truncated before section ") + names[i]);
        if (tag != order[i]) return fail(error, std::string("expected section ") + names[i] + " here");
        if (dir.left() < n) return fail(error, std::string("section ") + names[i] + " is truncated");
        sec[i] = dir.here();
        len[i] = n;
        if (detail::crc32(sec[i], n) != crc)
            return fail(error, std::string("section ") + names[i] + " checksum mismatch (corrupt file)");
        dir.skip(n);
    }
    if (!dir.at_end()) return fail(error, "bytes after the last section");

    MorphData d;
    std::string why;
    if (!decode(sec[0], len[0], d.strips, &why)) return fail(error, "section LSTR: " + why);

    detail::Reader f(sec[1], len[1]);
    d.frame_count = f.u32();
    const std::uint32_t n = f.u32(), flags = f.u32();
    if (!f.ok()) return fail(error, "section FRMS is truncated");
    if (flags & ~morph_flag_quantized) return fail(error, "section FRMS has unknown flags");
    if (n != d.strips.vertex_count)
        return fail(error, "section FRMS has " + std::to_string(n) + " vertices, the strips " +
                               std::to_string(d.strips.vertex_count));
    if (d.frame_count == 0) return fail(error, "section FRMS has no frames");
    d.quantized = (flags & morph_flag_quantized) != 0;
    float origin[3] = {0, 0, 0}, extent[3] = {0, 0, 0};
    if (d.quantized) {
        for (float& x : origin) x = f.f32();
        for (float& x : extent) x = f.f32();
        if (!f.ok()) return fail(error, "section FRMS is truncated");
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite(origin[i]) || !std::isfinite(extent[i]) || extent[i] < 0)
                return fail(error, "section FRMS: bad quantisation box");
    }
    const std::uint64_t per_frame = std::uint64_t(n) * (d.quantized ? 10u : 24u);
    if (std::uint64_t(f.left()) != per_frame * d.frame_count)
        return fail(error, "section FRMS has " + std::to_string(f.left()) + " bytes of frames, expected " +
                               std::to_string(per_frame * d.frame_count));
    const std::size_t values = std::size_t(d.frame_count) * 3u * n;
    d.frame_positions.resize(values);
    d.frame_normals.resize(values);
    const std::uint8_t* p = f.here();
    for (std::uint32_t k = 0; k < d.frame_count; ++k) {
        float* pos = d.frame_positions.data() + std::size_t(k) * 3u * n;
        float* nrm = d.frame_normals.data() + std::size_t(k) * 3u * n;
        if (d.quantized) {
            for (std::size_t i = 0; i < 3u * std::size_t(n); ++i, p += 2)
                pos[i] = origin[i % 3] + extent[i % 3] * (float(detail::u16_at(p)) / 65535.f);
            for (std::size_t v = 0; v < n; ++v, p += 4)
                detail::oct_decode(static_cast<std::int16_t>(detail::u16_at(p)),
                                   static_cast<std::int16_t>(detail::u16_at(p + 2)), nrm + 3 * v);
        } else {
            std::memcpy(pos, p, 12u * std::size_t(n));
            p += 12u * std::size_t(n);
            std::memcpy(nrm, p, 12u * std::size_t(n));
            p += 12u * std::size_t(n);
        }
    }
    out = std::move(d);
    return true;
}

// The runtime: the strips (element buffer, levels) and a vertex buffer at time t.
class MorphLodStrips {
public:
    using Span = LodStrips::Span;

    bool load_memory(const void* bytes, std::size_t size, std::string* error = nullptr) {
        MorphData d;
        if (!decode_morph(bytes, size, d, error)) return false;
        return assign(std::move(d), error);
    }

    bool load_file(const std::string& path, std::string* error = nullptr) {
        std::ifstream in(path, std::ios::binary);
        if (!in) return detail::fail(error, "cannot open for reading");
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) return detail::fail(error, "read error");
        return load_memory(bytes.data(), bytes.size(), error);
    }

    // Checks the frames, then the strips (LodStrips::assign replays every record). Starts at full detail
    // and t = 0. On failure the object is left empty.
    bool assign(MorphData d, std::string* error = nullptr) {
        *this = MorphLodStrips();
        const std::size_t values = std::size_t(d.frame_count) * 3u * d.strips.vertex_count;
        if (d.frame_count == 0 || d.frame_positions.size() != values || d.frame_normals.size() != values)
            return detail::fail(error, "frame arrays have inconsistent sizes");
        for (const auto* arr : {&d.frame_positions, &d.frame_normals})
            for (float x : *arr)
                if (!std::isfinite(x)) return detail::fail(error, "a frame value is not finite");
        frame_count_ = d.frame_count;
        vertices_ = d.strips.vertex_count;
        frame_positions_ = std::move(d.frame_positions);
        frame_normals_ = std::move(d.frame_normals);
        if (!strips_.assign(std::move(d.strips), error)) {
            *this = MorphLodStrips();
            return false;
        }
        positions_.assign(3u * std::size_t(vertices_), 0.f);
        normals_.assign(3u * std::size_t(vertices_), 0.f);
        set_frame(0.0);
        return true;
    }

    std::size_t frame_count() const { return frame_count_; }
    double time() const { return t_; }

    // t in [0, 1] over the whole sequence (clamped; NaN = 0). Keyframes are evenly spaced: between
    // keyframes k and k+1 with fraction s, p = (1 − s)·p_k + s·p_{k+1}, n = normalise((1 − s)·n_k + s·n_{k+1}).
    void set_frame(double t) {
        if (!(t >= 0.0)) t = 0.0;
        if (t > 1.0) t = 1.0;
        t_ = t;
        blended_ = 0;
        blend_to(strips_.vertex_count());
    }

    void go_to_lod(double factor) {
        strips_.go_to_lod(factor);
        blend_to(strips_.vertex_count());
    }
    void go_to_level(std::size_t level) {
        strips_.go_to_level(level);
        blend_to(strips_.vertex_count());
    }
    void go_to_triangles(std::size_t n) {
        strips_.go_to_triangles(n);
        blend_to(strips_.vertex_count());
    }

    // Vertex buffer: canonical order, 3 floats per vertex; [0, vertex_count()) holds the pose at time().
    const float* positions() const { return positions_.data(); }
    const float* normals() const { return normals_.data(); }
    std::size_t vertex_count() const { return strips_.vertex_count(); }
    std::size_t total_vertex_count() const { return vertices_; }
    // Vertices rewritten since clear_vertex_changes() (one range; empty when none).
    Span vertex_changes() const {
        if (dirty_hi_ <= dirty_lo_) return {};
        return {dirty_lo_, dirty_hi_ - dirty_lo_};
    }
    void clear_vertex_changes() {
        dirty_lo_ = 0xFFFFFFFFu;
        dirty_hi_ = 0;
    }

    // The element buffer and its changes: those of the LodStrips runtime.
    const LodStrips& strips() const { return strips_; }
    const std::uint32_t* indices() const { return strips_.indices(); }
    std::size_t index_count() const { return strips_.index_count(); }
    std::size_t strip_count() const { return strips_.strip_count(); }
    const std::uint32_t* draw_offsets() const { return strips_.draw_offsets(); }
    const std::int32_t* draw_counts() const { return strips_.draw_counts(); }
    std::size_t level() const { return strips_.level(); }
    std::size_t collapse_count() const { return strips_.collapse_count(); }
    std::size_t triangle_count() const { return strips_.triangle_count(); }
    std::vector<Span> changes() const { return strips_.changes(); }
    void clear_changes() { strips_.clear_changes(); }
    void triangles(std::vector<std::uint32_t>& out) const { strips_.triangles(out); }

private:
    // Blends vertices [blended_, upto) at t_.
    void blend_to(std::size_t upto) {
        if (upto <= blended_) return;
        const std::size_t n = vertices_;
        std::size_t k = 0;
        float s = 0.f;
        if (frame_count_ > 1) {
            const double x = t_ * double(frame_count_ - 1);
            k = std::min(static_cast<std::size_t>(x), std::size_t(frame_count_) - 2);
            s = static_cast<float>(x - double(k));
        }
        const float* pa = frame_positions_.data() + k * 3u * n;
        const float* na = frame_normals_.data() + k * 3u * n;
        if (s == 0.f) {
            std::copy(pa + 3 * blended_, pa + 3 * upto, positions_.begin() + std::ptrdiff_t(3 * blended_));
            std::copy(na + 3 * blended_, na + 3 * upto, normals_.begin() + std::ptrdiff_t(3 * blended_));
        } else {
            const float* pb = pa + 3u * n;
            const float* nb = na + 3u * n;
            const float r = 1.f - s;
            for (std::size_t i = 3 * blended_; i < 3 * upto; ++i) positions_[i] = pa[i] * r + pb[i] * s;
            for (std::size_t v = blended_; v < upto; ++v) {
                float x = na[3 * v] * r + nb[3 * v] * s, y = na[3 * v + 1] * r + nb[3 * v + 1] * s,
                      z = na[3 * v + 2] * r + nb[3 * v + 2] * s;
                const float len = std::sqrt(x * x + y * y + z * z);
                if (len > 0) {
                    x /= len, y /= len, z /= len;
                } else {
                    x = 0, y = 0, z = 1;
                }
                normals_[3 * v] = x, normals_[3 * v + 1] = y, normals_[3 * v + 2] = z;
            }
        }
        dirty_lo_ = std::min<std::uint32_t>(dirty_lo_, static_cast<std::uint32_t>(blended_));
        dirty_hi_ = std::max<std::uint32_t>(dirty_hi_, static_cast<std::uint32_t>(upto));
        blended_ = upto;
    }

    LodStrips strips_;
    std::uint32_t frame_count_ = 0, vertices_ = 0;
    std::vector<float> frame_positions_, frame_normals_;
    std::vector<float> positions_, normals_;
    double t_ = 0;
    std::size_t blended_ = 0;
    std::uint32_t dirty_lo_ = 0xFFFFFFFFu, dirty_hi_ = 0;
};

}  // namespace lodstrips
