// LODStrips runtime: continuous level of detail on triangle strips, for game engines.
// Single header, C++17, standard library only (no LodForge header, nothing to link; <sys/mman.h> on Linux). Format and design:
// docs/lodstrips.md and docs/formats/lodstrips.md in the LodForge repository. Follows J. F. Ramos Romero,
// "LODStrips: Continuous Level of Detail using Triangle Strips" (PhD dissertation, Universitat Jaume I,
// 2008), ch. 4, 5, 7.
//
//   lodstrips::LodStrips lod;
//   std::string error;
//   if (!lod.load_file("bunny.lodstrips", &error)) { ... }
//   lod.go_to_lod(0.25);                       // 0 = coarsest stored level, 1 = full detail
//   upload(lod.indices(), lod.index_count());  // once; afterwards only lod.changes() spans
//   glMultiDrawElements(GL_TRIANGLE_STRIP, lod.draw_counts(), GL_UNSIGNED_INT, offsets, lod.strip_count());
//
// Layout: one element buffer of fixed size (the full-resolution size) in which every strip owns a fixed
// region [strip_offset(s), strip_offset(s+1)). A strip shrinks inside its region; the freed tail repeats
// the region's last index (degenerate joins) or holds restart indices (restart mode), so the whole buffer
// also stays drawable with one draw call. Every strip starts on an even position and every removal
// removes an even number of indices, so each triangle keeps its winding.
//
// Loading never trusts the file: sizes, checksums (CRC-32 per section) and every record are checked, and
// the whole collapse sequence is replayed once, so no later go_to_* call can index out of range.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace lodstrips {

namespace detail {
// The element buffer and the compiled records are walked in collapse order, which jumps across
// megabytes: with 4 KiB pages the full dragon's extraction is dominated by TLB misses and swings between
// 40 and 64 ns per collapse from run to run. Arrays of 2 MiB or more therefore ask Linux for transparent
// huge pages (honoured in its default "madvise" mode; elsewhere a plain allocation). docs/lodstrips.md.
template <class T>
struct large_page_allocator {
    using value_type = T;
    static constexpr std::size_t huge_page = std::size_t(2) << 20;
    large_page_allocator() = default;
    template <class U>
    large_page_allocator(const large_page_allocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
#if defined(__linux__)
        if (n * sizeof(T) >= huge_page) {
            const std::size_t bytes = (n * sizeof(T) + huge_page - 1) / huge_page * huge_page;
            void* p = std::aligned_alloc(huge_page, bytes);
            if (!p) throw std::bad_alloc();
            ::madvise(p, bytes, MADV_HUGEPAGE);  // advice only: a refusal changes nothing but speed
            return static_cast<T*>(p);
        }
#endif
        return std::allocator<T>().allocate(n);
    }
    void deallocate(T* p, std::size_t n) noexcept {
#if defined(__linux__)
        if (n * sizeof(T) >= huge_page) {
            std::free(p);
            return;
        }
#endif
        std::allocator<T>().deallocate(p, n);
    }
    friend bool operator==(const large_page_allocator&, const large_page_allocator&) { return true; }
    friend bool operator!=(const large_page_allocator&, const large_page_allocator&) { return false; }
};
template <class T>
using large_vector = std::vector<T, large_page_allocator<T>>;
}  // namespace detail

inline constexpr std::uint32_t restart_index = 0xFFFFFFFFu;
inline constexpr char file_magic[8] = {'L', 'O', 'D', 'S', 'T', 'R', 'P', 'S'};
inline constexpr std::uint32_t format_version = 1;
inline constexpr std::uint32_t endian_tag = 0x01020304u;
inline constexpr std::uint32_t max_region_length = 65535;  // positions inside a strip fit 16 bits

struct Material {
    std::string name;
    float base_color[4] = {1, 1, 1, 1};
    float metallic = 0, roughness = 1;
    float emissive[3] = {0, 0, 0};
    bool double_sided = false;
    // Texture paths as written in the source (relative to the source's folder, or absolute); empty = none.
    std::string base_color_texture, normal_texture, metallic_roughness_texture, occlusion_texture,
        emissive_texture;
    std::uint32_t base_color_texcoord_set = 0;
};

// A degenerate run removed from a strip (positions are those of the state the record was made in).
struct Removal {
    std::uint32_t strip = 0;
    std::uint16_t pos = 0;    // first removed index, >= 2 (the run's first indices stay)
    std::uint16_t count = 0;  // even, > 0
    std::uint8_t type = 1;    // 1: a(aa)+ run of one index; 2: ab(ab)+ alternation
};

// Everything a .lodstrips file holds, decoded. Vertex v (canonical order) is removed by the collapse that
// removes ordinal vertex_count - 1 - v: the coarsest level uses a prefix of the vertices.
struct Data {
    std::uint32_t vertex_count = 0;
    std::vector<float> positions;                 // 3 per vertex
    std::vector<float> normals;                   // 3 per vertex, or empty
    std::vector<float> colors;                    // RGBA in [0, 1], 4 per vertex, or empty
    bool colors_8bit = false;                     // colours are stored as 8-bit (exactly k/255)
    std::vector<std::vector<float>> texcoords;    // per set, 2 per vertex
    std::vector<Material> materials;

    bool restart = true;                          // strips end with restart_index (else degenerate joins)
    std::vector<std::uint32_t> strip_offsets;     // strip_count + 1 region starts in the element buffer
    std::vector<std::uint32_t> strip_materials;   // per strip
    std::vector<std::uint32_t> initial_indices;   // the full-resolution element buffer

    // Collapse k removes vertex ordinals [collapse_begin[k], collapse_begin[k+1]).
    std::vector<std::uint32_t> collapse_begin;    // collapse_count + 1
    std::vector<std::uint32_t> targets;           // per ordinal: the vertex its occurrences become (< itself)
    std::vector<std::uint32_t> rewrite_begin;     // per ordinal + 1: range in rewrite_positions
    std::vector<std::uint32_t> rewrite_positions; // element-buffer positions holding the ordinal's vertex
    std::vector<std::uint32_t> removal_begin;     // collapse_count + 1
    std::vector<Removal> removals;
    std::vector<std::uint32_t> triangles;         // non-degenerate triangles at level k, collapse_count + 1

    std::size_t collapse_count() const { return collapse_begin.empty() ? 0 : collapse_begin.size() - 1; }
    std::size_t strip_count() const { return strip_offsets.empty() ? 0 : strip_offsets.size() - 1; }
    std::uint32_t vertex_of_ordinal(std::uint32_t o) const { return vertex_count - 1 - o; }
};

namespace detail {

inline std::uint32_t crc32(const std::uint8_t* p, std::size_t n) {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    std::uint32_t c = 0xFFFFFFFFu;
    for (std::size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xFFu] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}

// Little-endian reader over a byte range; every read is bounds-checked and failure is sticky.
class Reader {
public:
    Reader(const std::uint8_t* p, std::size_t n) : p_(p), end_(p + n) {}
    bool ok() const { return ok_; }
    bool at_end() const { return p_ == end_; }
    std::size_t left() const { return static_cast<std::size_t>(end_ - p_); }
    void fail() { ok_ = false; p_ = end_; }
    std::uint8_t u8() {
        if (left() < 1) { fail(); return 0; }
        return *p_++;
    }
    std::uint32_t u32() {
        if (left() < 4) { fail(); return 0; }
        std::uint32_t v = std::uint32_t(p_[0]) | std::uint32_t(p_[1]) << 8 | std::uint32_t(p_[2]) << 16 |
                          std::uint32_t(p_[3]) << 24;
        p_ += 4;
        return v;
    }
    float f32() {
        const std::uint32_t b = u32();
        float f;
        std::memcpy(&f, &b, 4);
        return f;
    }
    std::uint64_t varint() {
        std::uint64_t v = 0;
        for (int shift = 0; shift < 64; shift += 7) {
            if (left() < 1) { fail(); return 0; }
            const std::uint8_t b = *p_++;
            v |= std::uint64_t(b & 0x7Fu) << shift;
            if (!(b & 0x80u)) return v;
        }
        fail();
        return 0;
    }
    // A varint that must fit 32 bits and be <= limit.
    std::uint32_t count(std::uint64_t limit) {
        const std::uint64_t v = varint();
        if (v > limit) { fail(); return 0; }
        return static_cast<std::uint32_t>(v);
    }
    std::string str() {
        const std::uint32_t n = count(left());
        std::string s(reinterpret_cast<const char*>(p_), n);
        p_ += n;
        return s;
    }
    const std::uint8_t* here() const { return p_; }
    void skip(std::size_t n) {
        if (left() < n) { fail(); return; }
        p_ += n;
    }

private:
    const std::uint8_t* p_;
    const std::uint8_t* end_;
    bool ok_ = true;
};

inline std::int64_t unzigzag(std::uint64_t v) { return static_cast<std::int64_t>(v >> 1) ^ -static_cast<std::int64_t>(v & 1); }

inline unsigned lowest_bit(std::uint64_t x) {  // x != 0
#if defined(__GNUC__) || defined(__clang__)
    return static_cast<unsigned>(__builtin_ctzll(x));
#else
    unsigned i = 0;
    while (!(x & 1u)) { x >>= 1; ++i; }
    return i;
#endif
}

inline bool fail(std::string* error, const std::string& what) {
    if (error) *error = what;
    return false;
}

// One section of a tagged section container: a view into the file image.
struct Section {
    std::uint32_t tag = 0;
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
};

// The container every LodForge binary format shares (docs/formats/README.md, "Container"): 8-byte magic,
// u32 version, u32 byte-order tag, u32 section count, u32 CRC-32 of the 20 bytes before it, u64 file size;
// then per section u32 tag, u32 length, u32 CRC-32 of the payload, the payload. Checks everything but
// the version and what the sections mean; `kind` names the format in messages (".lodstrips").
inline bool read_container(const std::uint8_t* base, std::size_t size, const char (&magic)[8], const char* kind,
                           std::uint32_t& version, std::vector<Section>& sections, std::string* error) {
    if (size < 32) return fail(error, "file too short for the header (" + std::to_string(size) + " bytes)");
    if (std::memcmp(base, magic, 8) != 0) return fail(error, std::string("not a ") + kind + " file (bad magic)");
    Reader h(base + 8, 24);
    version = h.u32();
    const std::uint32_t endian = h.u32(), count = h.u32(), header_crc = h.u32();
    const std::uint32_t size_lo = h.u32(), size_hi = h.u32();
    const std::uint64_t declared = std::uint64_t(size_lo) | std::uint64_t(size_hi) << 32;
    if (endian != endian_tag) return fail(error, "unsupported byte order tag");
    if (header_crc != crc32(base, 20)) return fail(error, "header checksum mismatch");
    if (declared != size)
        return fail(error, "file is " + std::to_string(size) + " bytes, header says " + std::to_string(declared) +
                               " (truncated or padded)");
    if (count > (size - 32) / 12) return fail(error, "header announces " + std::to_string(count) + " sections");
    sections.clear();
    Reader dir(base + 32, size - 32);
    for (std::uint32_t i = 0; i < count; ++i) {
        Section s;
        s.tag = dir.u32();
        const std::uint32_t len = dir.u32(), crc = dir.u32();
        if (!dir.ok()) return fail(error, "truncated before section " + std::to_string(i + 1));
        std::string name = "section ";
        for (int k = 0; k < 4; ++k) name += char(s.tag >> (8 * k));
        if (dir.left() < len) return fail(error, name + " is truncated");
        s.data = dir.here();
        s.size = len;
        if (crc32(s.data, len) != crc) return fail(error, name + " checksum mismatch (corrupt file)");
        dir.skip(len);
        sections.push_back(s);
    }
    if (!dir.at_end()) return fail(error, "bytes after the last section");
    return true;
}

// Checks that the sections carry exactly `tags`, in this order (four ASCII characters each).
inline bool expect_sections(const std::vector<Section>& sections, const char* const* tags, std::size_t count,
                            std::string* error) {
    if (sections.size() != count)
        return fail(error, "expected " + std::to_string(count) + " sections, header says " +
                               std::to_string(sections.size()));
    for (std::size_t i = 0; i < count; ++i) {
        std::uint32_t want = 0;
        for (int k = 0; k < 4; ++k) want |= std::uint32_t(std::uint8_t(tags[i][k])) << (8 * k);
        if (sections[i].tag != want) return fail(error, std::string("expected section ") + tags[i] + " here");
    }
    return true;
}

}  // namespace detail

// Section tags (four ASCII characters, little-endian u32).
inline constexpr std::uint32_t section_tag(const char (&s)[5]) {
    return std::uint32_t(std::uint8_t(s[0])) | std::uint32_t(std::uint8_t(s[1])) << 8 |
           std::uint32_t(std::uint8_t(s[2])) << 16 | std::uint32_t(std::uint8_t(s[3])) << 24;
}

// Decodes a .lodstrips file image into `out`. Returns false with a message naming the section and the
// problem; the record-level consistency check is LodStrips::assign's (replay of the whole sequence).
inline bool decode(const void* bytes, std::size_t size, Data& out, std::string* error) {
    using detail::fail;
    std::uint32_t version = 0;
    std::vector<detail::Section> sec;
    if (!detail::read_container(static_cast<const std::uint8_t*>(bytes), size, file_magic, ".lodstrips", version, sec,
                                error))
        return false;
    if (version != format_version)
        return fail(error, "unsupported format version " + std::to_string(version) + " (this reader: 1)");
    static const char* const names[5] = {"META", "VERT", "MATL", "STRP", "COLL"};
    if (!detail::expect_sections(sec, names, 5, error)) return false;
    const std::uint8_t* sec_data[5];
    std::size_t sec_size[5];
    for (int i = 0; i < 5; ++i) sec_data[i] = sec[std::size_t(i)].data, sec_size[i] = sec[std::size_t(i)].size;

    Data d;
    // META
    detail::Reader m(sec_data[0], sec_size[0]);
    const std::uint32_t flags = m.count(0xFFFF);
    d.vertex_count = m.count(restart_index - 1);
    const std::uint32_t texcoord_sets = m.count(16);
    const std::uint32_t material_count = m.count(1u << 20);
    const std::uint32_t strip_count = m.count(1u << 30);
    const std::uint32_t element_count = m.count(restart_index - 1);
    const std::uint32_t collapse_count = m.count(d.vertex_count);
    const std::uint32_t removed_vertices = m.count(d.vertex_count);
    const std::uint32_t rewrite_count = m.count(0xFFFFFFFFu);
    const std::uint32_t removal_count = m.count(0xFFFFFFFFu);
    if (!m.ok() || !m.at_end()) return fail(error, "section META is malformed");
    if (flags & ~0x1Fu) return fail(error, "section META has unknown flags");
    d.restart = (flags & 1u) != 0;
    const bool has_normals = (flags & 2u) != 0, has_colors = (flags & 4u) != 0;
    d.colors_8bit = (flags & 8u) != 0;
    if (d.colors_8bit && !has_colors) return fail(error, "section META: 8-bit colours without colours");
    if (collapse_count > removed_vertices) return fail(error, "section META: more collapses than removed vertices");
    // Upper bounds against the file size before any allocation (every element needs at least a byte or
    // four), so a lying count cannot make the reader allocate gigabytes.
    const std::uint64_t per_vertex = 12u + (has_normals ? 12u : 0u) + (has_colors ? (d.colors_8bit ? 4u : 16u) : 0u) +
                                     8u * texcoord_sets;
    if (std::uint64_t(d.vertex_count) * per_vertex != sec_size[1])
        return fail(error, "section VERT has " + std::to_string(sec_size[1]) + " bytes, META announces " +
                               std::to_string(std::uint64_t(d.vertex_count) * per_vertex));
    if (strip_count > sec_size[3] || element_count > 2 * std::uint64_t(sec_size[3]) + 2 * std::uint64_t(strip_count) ||
        collapse_count > sec_size[4] || rewrite_count > sec_size[4] || removal_count > sec_size[4] ||
        material_count > sec_size[2])
        return fail(error, "section META announces more records than the file holds");

    // VERT: planar arrays.
    detail::Reader v(sec_data[1], sec_size[1]);
    auto floats = [&](std::vector<float>& dst, std::size_t n) {
        dst.resize(n);
        for (std::size_t i = 0; i < n; ++i) dst[i] = v.f32();
    };
    floats(d.positions, 3u * std::size_t(d.vertex_count));
    if (has_normals) floats(d.normals, 3u * std::size_t(d.vertex_count));
    if (has_colors) {
        if (d.colors_8bit) {
            d.colors.resize(4u * std::size_t(d.vertex_count));
            for (float& c : d.colors) c = float(v.u8()) / 255.f;
        } else {
            floats(d.colors, 4u * std::size_t(d.vertex_count));
        }
    }
    d.texcoords.resize(texcoord_sets);
    for (auto& set : d.texcoords) floats(set, 2u * std::size_t(d.vertex_count));
    if (!v.ok() || !v.at_end()) return fail(error, "section VERT is malformed");
    for (float f : d.positions)
        if (!std::isfinite(f)) return fail(error, "section VERT: a position is not finite");
    for (const auto* arr : {&d.normals, &d.colors})
        for (float f : *arr)
            if (!std::isfinite(f)) return fail(error, "section VERT: an attribute is not finite");
    for (const auto& set : d.texcoords)
        for (float f : set)
            if (!std::isfinite(f)) return fail(error, "section VERT: a texture coordinate is not finite");

    // MATL
    detail::Reader t(sec_data[2], sec_size[2]);
    d.materials.resize(material_count);
    for (Material& mat : d.materials) {
        mat.name = t.str();
        for (float& c : mat.base_color) c = t.f32();
        mat.metallic = t.f32();
        mat.roughness = t.f32();
        for (float& c : mat.emissive) c = t.f32();
        mat.double_sided = t.u8() != 0;
        mat.base_color_texture = t.str();
        mat.normal_texture = t.str();
        mat.metallic_roughness_texture = t.str();
        mat.occlusion_texture = t.str();
        mat.emissive_texture = t.str();
        mat.base_color_texcoord_set = t.count(texcoord_sets == 0 ? 0 : texcoord_sets - 1);
    }
    if (!t.ok() || !t.at_end()) return fail(error, "section MATL is malformed");

    // STRP: per strip region length and material, then the indices (zigzag deltas); in restart mode the
    // last slot of each region (the restart index) is implicit.
    detail::Reader s(sec_data[3], sec_size[3]);
    d.strip_offsets.resize(std::size_t(strip_count) + 1);
    d.strip_materials.resize(strip_count);
    d.strip_offsets[0] = 0;
    for (std::uint32_t i = 0; i < strip_count; ++i) {
        const std::uint32_t len = s.count(max_region_length);
        if (len < (d.restart ? 4u : 3u)) return fail(error, "section STRP: strip " + std::to_string(i) + " too short");
        d.strip_offsets[i + 1] = d.strip_offsets[i] + len;
        if (d.strip_offsets[i + 1] > element_count) return fail(error, "section STRP: strips exceed the element count");
        d.strip_materials[i] = s.count(material_count == 0 ? 0 : material_count - 1);
    }
    if (!s.ok() || d.strip_offsets.back() != element_count)
        return fail(error, "section STRP: strip lengths do not add up to the element count");
    d.initial_indices.resize(element_count);
    std::int64_t prev = 0;
    for (std::uint32_t i = 0; i < strip_count && s.ok(); ++i) {
        const std::uint32_t end = d.strip_offsets[i + 1] - (d.restart ? 1u : 0u);
        for (std::uint32_t e = d.strip_offsets[i]; e < end; ++e) {
            prev += detail::unzigzag(s.varint());
            if (prev < 0 || prev >= std::int64_t(d.vertex_count)) {
                return fail(error, "section STRP: index out of range at element " + std::to_string(e));
            }
            d.initial_indices[e] = static_cast<std::uint32_t>(prev);
        }
        if (d.restart) d.initial_indices[end] = restart_index;
    }
    if (!s.ok() || !s.at_end()) return fail(error, "section STRP is malformed");

    // COLL: per collapse the vertices it removes (their targets), then groups per strip.
    detail::Reader c(sec_data[4], sec_size[4]);
    d.collapse_begin.assign(1, 0);
    d.removal_begin.assign(1, 0);
    d.rewrite_begin.assign(1, 0);
    d.triangles.resize(std::size_t(collapse_count) + 1);
    d.targets.reserve(removed_vertices);
    d.rewrite_positions.reserve(rewrite_count);
    d.removals.reserve(removal_count);
    d.triangles[0] = c.count(0xFFFFFFFFu);
    std::vector<std::vector<std::uint32_t>> per_vertex_positions;
    for (std::uint32_t k = 0; k < collapse_count && c.ok(); ++k) {
        const std::uint32_t removed_before = d.collapse_begin.back();
        const std::uint32_t mcount = c.count(std::uint64_t(removed_vertices) - removed_before);
        if (mcount == 0) return fail(error, "section COLL: collapse " + std::to_string(k) + " removes no vertex");
        const std::uint32_t tri_removed = c.count(d.triangles[k]);
        d.triangles[k + 1] = d.triangles[k] - tri_removed;
        for (std::uint32_t j = 0; j < mcount; ++j) {
            const std::uint32_t vtx = d.vertex_of_ordinal(removed_before + j);
            const std::uint32_t delta = c.count(vtx);
            if (delta == 0) return fail(error, "section COLL: collapse " + std::to_string(k) + " has a bad target");
            d.targets.push_back(vtx - delta);
        }
        d.collapse_begin.push_back(removed_before + mcount);
        per_vertex_positions.assign(mcount, {});
        const std::uint32_t groups = c.count(strip_count);
        std::int64_t strip = 0;
        for (std::uint32_t g = 0; g < groups && c.ok(); ++g) {
            strip += detail::unzigzag(c.varint());
            if (strip < 0 || strip >= std::int64_t(strip_count))
                return fail(error, "section COLL: collapse " + std::to_string(k) + " names a strip out of range");
            const std::uint32_t off = d.strip_offsets[std::size_t(strip)];
            const std::uint32_t len = d.strip_offsets[std::size_t(strip) + 1] - off;
            for (std::uint32_t j = 0; j < mcount && c.ok(); ++j) {
                const std::uint32_t n = c.count(len);
                std::uint64_t pos = 0;
                for (std::uint32_t i = 0; i < n; ++i) {
                    pos = i == 0 ? c.varint() : pos + 1 + c.varint();
                    if (pos >= len) return fail(error, "section COLL: position out of its strip in collapse " + std::to_string(k));
                    per_vertex_positions[j].push_back(off + static_cast<std::uint32_t>(pos));
                }
            }
            const std::uint32_t r = c.count(len);
            for (std::uint32_t i = 0; i < r && c.ok(); ++i) {
                Removal rm;
                rm.strip = static_cast<std::uint32_t>(strip);
                const std::uint32_t pos = c.count(len);
                const std::uint32_t code = c.count(2u * len);
                rm.pos = static_cast<std::uint16_t>(pos);
                rm.type = static_cast<std::uint8_t>((code & 1u) + 1u);
                const std::uint64_t cnt = 2u * (std::uint64_t(code >> 1) + 1u);
                if (pos < 2 || pos + cnt > len) return fail(error, "section COLL: removal out of its strip in collapse " + std::to_string(k));
                rm.count = static_cast<std::uint16_t>(cnt);
                d.removals.push_back(rm);
            }
        }
        for (const auto& pv : per_vertex_positions) {
            d.rewrite_positions.insert(d.rewrite_positions.end(), pv.begin(), pv.end());
            d.rewrite_begin.push_back(static_cast<std::uint32_t>(d.rewrite_positions.size()));
        }
        d.removal_begin.push_back(static_cast<std::uint32_t>(d.removals.size()));
    }
    if (!c.ok() || !c.at_end()) return fail(error, "section COLL is malformed or truncated");
    if (d.collapse_begin.back() != removed_vertices || d.rewrite_positions.size() != rewrite_count ||
        d.removals.size() != removal_count)
        return fail(error, "section COLL: record counts differ from META");
    out = std::move(d);
    return true;
}

// The runtime: the current element buffer and the moves between levels. Level k = the first k collapses
// applied (0 = full detail, collapse_count() = the coarsest stored level).
class LodStrips {
public:
    struct Span {
        std::uint32_t offset = 0;  // element offset in the buffer
        std::uint32_t count = 0;
    };

    LodStrips() = default;

    bool load_memory(const void* bytes, std::size_t size, std::string* error = nullptr) {
        Data d;
        if (!decode(bytes, size, d, error)) return false;
        return assign(std::move(d), error);
    }

    bool load_file(const std::string& path, std::string* error = nullptr) {
        std::FILE* f = std::fopen(path.c_str(), "rb");
        if (!f) return detail::fail(error, "cannot open for reading");
        std::vector<std::uint8_t> bytes;
        std::uint8_t chunk[1 << 16];
        std::size_t n;
        while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0) bytes.insert(bytes.end(), chunk, chunk + n);
        const bool read_error = std::ferror(f) != 0;
        std::fclose(f);
        if (read_error) return detail::fail(error, "read error");
        return load_memory(bytes.data(), bytes.size(), error);
    }

    // Takes decoded (or freshly built) data, checks every record by replaying the whole sequence once,
    // and starts at full detail. On failure the object is left empty.
    bool assign(Data d, std::string* error = nullptr) {
        data_ = std::move(d);
        std::string why;
        if (!check_structure(why) || !precompute(why)) {
            *this = LodStrips();
            return detail::fail(error, why);
        }
        reset();
        if (!replay_check(why)) {
            *this = LodStrips();
            return detail::fail(error, why);
        }
        if (!compile_program(why)) {
            *this = LodStrips();
            return detail::fail(error, why);
        }
        span_begin_ = {};
        spans_ = {};
        removal_fill_ = {};
        reset();
        return true;
    }

    const Data& data() const { return data_; }
    std::size_t collapse_count() const { return data_.collapse_count(); }
    std::size_t level() const { return level_; }
    std::size_t strip_count() const { return data_.strip_count(); }
    bool primitive_restart() const { return data_.restart; }

    // The element buffer (fixed size) and the multi-draw layout: strip s is drawn from draw_offsets()[s]
    // with draw_counts()[s] indices (restart index excluded).
    const std::uint32_t* indices() const { return buffer_.data(); }
    std::size_t index_count() const { return buffer_.size(); }
    const std::uint32_t* draw_offsets() const { return data_.strip_offsets.data(); }
    const std::int32_t* draw_counts() const { return counts_.data(); }
    std::uint32_t strip_offset(std::size_t s) const { return data_.strip_offsets[s]; }
    std::uint32_t strip_index_count(std::size_t s) const { return static_cast<std::uint32_t>(counts_[s]); }
    std::uint32_t strip_material(std::size_t s) const { return data_.strip_materials[s]; }

    std::size_t triangle_count() const { return data_.triangles[level_]; }
    std::size_t triangle_count_at(std::size_t level) const { return data_.triangles[std::min(level, collapse_count())]; }
    // Vertices [0, vertex_count_at(k)) are the ones level k can reference.
    std::size_t vertex_count_at(std::size_t level) const {
        return data_.vertex_count - data_.collapse_begin[std::min(level, collapse_count())];
    }
    std::size_t vertex_count() const { return vertex_count_at(level_); }

    // factor 1 = full detail, 0 = coarsest stored level; linear in the number of collapses.
    void go_to_lod(double factor) {
        if (!(factor >= 0.0)) factor = 0.0;  // NaN too
        if (factor > 1.0) factor = 1.0;
        go_to_level(static_cast<std::size_t>(std::llround((1.0 - factor) * double(collapse_count()))));
    }
    // The finest level with at most n triangles (the coarsest level when even it has more).
    void go_to_triangles(std::size_t n) {
        const auto& t = data_.triangles;  // non-increasing
        auto it = std::find_if(t.begin(), t.end(), [&](std::uint32_t x) { return x <= n; });
        if (it == t.end()) {
            go_to_level(collapse_count());
            return;
        }
        // first level whose count is <= n: binary search on the non-increasing sequence
        std::size_t lo = 0, hi = t.size() - 1;
        while (lo < hi) {
            const std::size_t mid = (lo + hi) / 2;
            if (t[mid] <= n) hi = mid; else lo = mid + 1;
        }
        go_to_level(lo);
    }
    void go_to_level(std::size_t target) {
        target = std::min(target, collapse_count());
        // Collapses are in error order, so each one lands somewhere else in the buffer: while one is
        // applied, fetch the records of the collapse 2d ahead and, through the records of the collapse d
        // ahead (fetched d collapses ago), the strips it will touch, so the cache misses overlap.
        constexpr std::size_t d = prefetch_distance;
        changed_lo_ = std::min(changed_lo_, target);
        changed_hi_ = std::max(changed_hi_, target);
        // Past the target too: the next move usually continues in the same direction.
        const std::size_t K = collapse_count();
        while (level_ < target) {
            if (level_ + 2 * d < K) prefetch_records(level_ + 2 * d);
            if (level_ + d < K) prefetch(level_ + d);
            collapse(level_++);
        }
        while (level_ > target) {
            if (level_ > 2 * d) prefetch_records(level_ - 1 - 2 * d);
            if (level_ > d) prefetch(level_ - 1 - d);
            split(--level_);
        }
    }

    // Element ranges changed since the last clear_changes() (sorted, one per touched strip), for updating
    // the engine's copy of the index buffer with glBufferSubData or a staging copy. Computed here, not
    // while moving: the level only moves step by step, so the collapses applied or undone since
    // clear_changes() are exactly those between the lowest and the highest level visited, and their
    // records say which strips they touch from where. Cost: the records of those collapses.
    // Uses scratch members: not to be called concurrently on one object.
    std::vector<Span> changes() const {
        std::vector<std::uint32_t>& lo = scratch_lo_;      // no_span outside this call
        std::vector<std::uint64_t>& seen = scratch_seen_;  // a bit per strip, zero outside this call
        std::size_t n = 0;
        for (std::size_t k = changed_lo_; k < changed_hi_; ++k) {
            const std::uint32_t* p = program_.data() + program_begin_[k];
            const std::uint32_t* span = p + 3;
            for (std::uint32_t i = 0; i < p[0]; ++i, span += 2) {
                const std::uint32_t s = span[1];
                n += lo[s] == no_span;
                seen[s >> 6] |= std::uint64_t(1) << (s & 63u);
                lo[s] = std::min(lo[s], span[0]);
            }
        }
        // Strips in order from the bit set (cheaper than sorting the touched strips).
        std::vector<Span> out;
        out.reserve(n);
        for (std::size_t w = 0; w < seen.size() && out.size() < n; ++w) {
            for (std::uint64_t bits = seen[w]; bits != 0; bits &= bits - 1) {
                const std::size_t s = w * 64 + detail::lowest_bit(bits);
                out.push_back({lo[s], data_.strip_offsets[s + 1] - lo[s]});
                lo[s] = no_span;
            }
            seen[w] = 0;
        }
        return out;
    }
    void clear_changes() { changed_lo_ = changed_hi_ = level_; }

    // The triangles the current buffer draws (degenerate ones dropped, odd positions swapped back), three
    // indices each, in strip order. For extraction and tests; engines draw the strips.
    void triangles(std::vector<std::uint32_t>& out) const {
        out.clear();
        for (std::size_t s = 0; s < strip_count(); ++s) append_strip_triangles(s, out);
    }
    void append_strip_triangles(std::size_t s, std::vector<std::uint32_t>& out) const {
        const std::uint32_t* p = buffer_.data() + data_.strip_offsets[s];
        const std::int32_t n = counts_[s];
        for (std::int32_t i = 0; i + 2 < n; ++i) {
            std::uint32_t a = p[i], b = p[i + 1], c = p[i + 2];
            if (a == b || b == c || a == c) continue;
            if (i & 1) std::swap(a, b);
            out.push_back(a);
            out.push_back(b);
            out.push_back(c);
        }
    }

private:
    static constexpr std::uint32_t no_span = 0xFFFFFFFFu;

    bool check_structure(std::string& why) {
        const Data& d = data_;
        const std::size_t K = d.collapse_count(), S = d.strip_count();
        if (d.collapse_begin.empty() || d.removal_begin.size() != K + 1 || d.triangles.size() != K + 1 ||
            d.collapse_begin[0] != 0 || d.removal_begin[0] != 0) {
            why = "collapse tables have inconsistent sizes";
            return false;
        }
        const std::size_t removed = d.collapse_begin.back();
        if (removed > d.vertex_count || d.targets.size() != removed || d.rewrite_begin.size() != removed + 1 ||
            d.rewrite_begin[0] != 0 || d.rewrite_begin.back() != d.rewrite_positions.size() ||
            d.removal_begin.back() != d.removals.size()) {
            why = "collapse tables have inconsistent sizes";
            return false;
        }
        if (d.positions.size() != 3u * std::size_t(d.vertex_count) ||
            (!d.normals.empty() && d.normals.size() != d.positions.size()) ||
            (!d.colors.empty() && d.colors.size() != 4u * std::size_t(d.vertex_count))) {
            why = "vertex arrays have inconsistent sizes";
            return false;
        }
        for (const auto& set : d.texcoords)
            if (set.size() != 2u * std::size_t(d.vertex_count)) {
                why = "vertex arrays have inconsistent sizes";
                return false;
            }
        if (d.strip_offsets.empty() || d.strip_offsets[0] != 0 || d.strip_materials.size() != S ||
            d.strip_offsets.back() != d.initial_indices.size()) {
            why = "strip tables have inconsistent sizes";
            return false;
        }
        for (std::size_t s = 0; s < S; ++s) {
            const std::uint32_t a = d.strip_offsets[s], b = d.strip_offsets[s + 1];
            if (b < a + (d.restart ? 4u : 3u) || b - a > max_region_length || (!d.restart && (a & 1u))) {
                why = "strip " + std::to_string(s) + " has a bad region";
                return false;
            }
            if (d.strip_materials[s] >= std::max<std::size_t>(1, d.materials.size())) {
                why = "strip " + std::to_string(s) + " names a material out of range";
                return false;
            }
            for (std::uint32_t e = a; e < b; ++e) {
                const std::uint32_t x = d.initial_indices[e];
                const bool sep = d.restart && e + 1 == b;
                if (sep ? x != restart_index : x >= d.vertex_count) {
                    why = "strip " + std::to_string(s) + ": index out of range at element " + std::to_string(e);
                    return false;
                }
            }
        }
        for (std::size_t k = 0; k < K; ++k)
            if (d.collapse_begin[k + 1] <= d.collapse_begin[k] || d.removal_begin[k + 1] < d.removal_begin[k] ||
                d.triangles[k + 1] > d.triangles[k]) {
                why = "collapse " + std::to_string(k) + " is malformed";
                return false;
            }
        for (std::uint32_t o = 0; o < removed; ++o)
            if (d.targets[o] >= d.vertex_of_ordinal(o) || d.rewrite_begin[o + 1] < d.rewrite_begin[o]) {
                why = "removed vertex " + std::to_string(d.vertex_of_ordinal(o)) + " has a bad target";
                return false;
            }
        for (std::uint32_t p : d.rewrite_positions)
            if (p >= d.initial_indices.size()) {
                why = "a rewrite position is out of the element buffer";
                return false;
            }
        for (const Removal& r : d.removals)
            if (r.strip >= S || r.pos < 2 || r.count == 0 || (r.count & 1u) || (r.type != 1 && r.type != 2) ||
                std::uint32_t(r.pos) + r.count > d.strip_offsets[r.strip + 1] - d.strip_offsets[r.strip]) {
                why = "a removal record is out of its strip";
                return false;
            }
        return true;
    }

    // Per collapse, the strips it touches and from where (for changes()).
    bool precompute(std::string&) {
        const Data& d = data_;
        const std::size_t K = d.collapse_count();
        span_begin_.assign(1, 0);
        spans_.clear();
        std::vector<std::pair<std::uint32_t, std::uint32_t>> touched;  // (strip, lowest local pos)
        for (std::size_t k = 0; k < K; ++k) {
            touched.clear();
            for (std::uint32_t o = d.collapse_begin[k]; o < d.collapse_begin[k + 1]; ++o)
                for (std::uint32_t i = d.rewrite_begin[o]; i < d.rewrite_begin[o + 1]; ++i) {
                    const std::uint32_t p = d.rewrite_positions[i];
                    const auto it = std::upper_bound(d.strip_offsets.begin(), d.strip_offsets.end(), p);
                    const std::uint32_t s = static_cast<std::uint32_t>(it - d.strip_offsets.begin() - 1);
                    touched.push_back({s, p - d.strip_offsets[s]});
                }
            for (std::uint32_t i = d.removal_begin[k]; i < d.removal_begin[k + 1]; ++i)
                touched.push_back({d.removals[i].strip, d.removals[i].pos});
            std::sort(touched.begin(), touched.end());
            for (std::size_t i = 0; i < touched.size(); ++i)
                if (i == 0 || touched[i].first != touched[i - 1].first) spans_.push_back(touched[i]);
            span_begin_.push_back(static_cast<std::uint32_t>(spans_.size()));
        }
        return true;
    }

    void reset() {
        buffer_.assign(data_.initial_indices.begin(), data_.initial_indices.end());
        const std::size_t S = strip_count();
        counts_.resize(S);
        for (std::size_t s = 0; s < S; ++s)
            counts_[s] = static_cast<std::int32_t>(data_.strip_offsets[s + 1] - data_.strip_offsets[s] - (data_.restart ? 1 : 0));
        level_ = 0;
        changed_lo_ = changed_hi_ = 0;
        scratch_lo_.assign(S, no_span);
        scratch_seen_.assign((S + 63) / 64, 0);
    }

    std::uint32_t live(std::uint32_t s) const { return static_cast<std::uint32_t>(counts_[s]) + (data_.restart ? 1u : 0u); }

    // The collapse records recompiled for speed: one contiguous run of words per collapse, so a collapse
    // reads one or two cache lines of records instead of five tables. Layout of collapse k, from
    // program_[program_begin_[k]]:
    //   span count S, group count G, removal count R;
    //   S x (first changed element, strip)                       -- for changes() and prefetching
    //   G x (target, vertex, n, n element positions)              -- n a multiple of 4: the last position
    //                                                                is repeated (rewriting it twice is
    //                                                                harmless), so the loop runs in fours
    //   R x (strip, pos | (count | (type - 1)) << 16, fill)       -- count is even: its low bit is the type;
    //                                                                fill = what the freed slots get
    // The fill is the region's last slot in the state the removal was recorded in (replay_check saw it):
    // the restart index, or with degenerate joins the join's last index, which a rewrite may have changed.
    // Storing it saves reading that slot, up to 1 KiB past the live part and often the one cache line of
    // the removal that no prefetch reached (about a tenth of a collapse on dragon res2, degenerate joins).
    bool compile_program(std::string& why) {
        const Data& d = data_;
        const std::size_t K = d.collapse_count();
        std::uint64_t words = 3u * std::uint64_t(K) + 2u * std::uint64_t(spans_.size()) + 3u * std::uint64_t(d.removals.size());
        for (std::uint32_t o = 0; o < d.collapse_begin.back(); ++o)
            words += 3u + (std::uint64_t(d.rewrite_begin[o + 1] - d.rewrite_begin[o]) + 3u) / 4u * 4u;
        if (words > 0xFFFFFFFFu) {
            why = "too many collapse records for one model";
            return false;
        }
        program_.clear();
        program_begin_.assign(1, 0);
        program_.reserve(static_cast<std::size_t>(words));
        for (std::size_t k = 0; k < K; ++k) {
            program_.push_back(span_begin_[k + 1] - span_begin_[k]);
            program_.push_back(d.collapse_begin[k + 1] - d.collapse_begin[k]);
            program_.push_back(d.removal_begin[k + 1] - d.removal_begin[k]);
            for (std::uint32_t i = span_begin_[k]; i < span_begin_[k + 1]; ++i) {
                program_.push_back(d.strip_offsets[spans_[i].first] + spans_[i].second);
                program_.push_back(spans_[i].first);
            }
            for (std::uint32_t o = d.collapse_begin[k]; o < d.collapse_begin[k + 1]; ++o) {
                const std::uint32_t b = d.rewrite_begin[o], e = d.rewrite_begin[o + 1];
                const std::uint32_t n = e == b ? 0 : (e - b + 3) / 4 * 4;
                program_.push_back(d.targets[o]);
                program_.push_back(d.vertex_of_ordinal(o));
                program_.push_back(n);
                for (std::uint32_t i = 0; i < n; ++i) program_.push_back(d.rewrite_positions[std::min(b + i, e - 1)]);
            }
            for (std::uint32_t i = d.removal_begin[k]; i < d.removal_begin[k + 1]; ++i) {
                const Removal& r = d.removals[i];
                program_.push_back(r.strip);
                program_.push_back(std::uint32_t(r.pos) | (std::uint32_t(r.count) | std::uint32_t(r.type - 1u)) << 16);
                program_.push_back(removal_fill_[i]);
            }
            program_begin_.push_back(static_cast<std::uint32_t>(program_.size()));
        }
        return true;
    }

    static constexpr std::size_t prefetch_distance = 4;

    void prefetch_records(std::size_t k) const {
#if (defined(__GNUC__) || defined(__clang__)) && !defined(LODSTRIPS_NO_PREFETCH)
        const std::uint32_t* p = program_.data() + program_begin_[k];
        __builtin_prefetch(p);
        __builtin_prefetch(p + 16);
        __builtin_prefetch(program_.data() + program_begin_[k + 1] - 1);
#else
        (void)k;
#endif
    }

    void prefetch(std::size_t k) const {
#if (defined(__GNUC__) || defined(__clang__)) && !defined(LODSTRIPS_NO_PREFETCH)
        const std::uint32_t* p = program_.data() + program_begin_[k];
        const std::uint32_t n = p[0];
        const std::uint32_t* span = p + 3;
        const std::uint32_t* buf = buffer_.data();
        for (std::uint32_t i = 0; i < n; ++i, span += 2) {
            // A removal moves the rest of the live part (a split moves it right by a few indices more).
            const std::uint32_t s = span[1];
            const std::uint32_t* q = buf + span[0];
            const std::uint32_t* end = buf + std::min(data_.strip_offsets[s] + live(s) + 16u, data_.strip_offsets[s + 1]);
            for (; q < end; q += 16) __builtin_prefetch(q, 1);
        }
#else
        (void)k;
#endif
    }

    // Applies the rewrite groups at p: value 0 writes each group's target (collapse), 1 its own vertex
    // (split). Returns the end of the groups.
    static const std::uint32_t* rewrite(std::uint32_t* buf, const std::uint32_t* p, std::uint32_t groups, int value) {
        for (std::uint32_t g = 0; g < groups; ++g) {
            const std::uint32_t x = p[value], n = p[2];
            p += 3;
            for (std::uint32_t i = 0; i < n; i += 4) {
                buf[p[i]] = x;
                buf[p[i + 1]] = x;
                buf[p[i + 2]] = x;
                buf[p[i + 3]] = x;
            }
            p += n;
        }
        return p;
    }

    void collapse(std::size_t k) {
        std::uint32_t* buf = buffer_.data();
        const std::uint32_t* p = program_.data() + program_begin_[k];
        const std::uint32_t spans = p[0], groups = p[1], removals = p[2];
        p = rewrite(buf, p + 3 + 2 * spans, groups, 0);
        for (std::uint32_t r = 0; r < removals; ++r, p += 3) {
            const std::uint32_t s = p[0], pos = p[1] & 0xFFFFu, count = (p[1] >> 16) & ~1u, fill = p[2];
            std::uint32_t* region = buf + data_.strip_offsets[s];
            const std::uint32_t n = live(s);
            std::memmove(region + pos, region + pos + count, (n - pos - count) * sizeof(std::uint32_t));
            std::fill(region + n - count, region + n, fill);
            counts_[s] -= static_cast<std::int32_t>(count);
        }
    }

    // Removes r.count indices at r.pos: the live tail moves left (the restart index with it) and the freed
    // slots repeat the region's last slot, which is the last live index or the restart index.
    std::uint32_t remove_run(const Removal& r) {
        const Data& d = data_;
        std::uint32_t* region = buffer_.data() + d.strip_offsets[r.strip];
        const std::uint32_t n = live(r.strip);
        const std::uint32_t fill = region[d.strip_offsets[r.strip + 1] - d.strip_offsets[r.strip] - 1];
        std::memmove(region + r.pos, region + r.pos + r.count, (n - r.pos - r.count) * sizeof(std::uint32_t));
        std::fill(region + n - r.count, region + n, fill);
        counts_[r.strip] -= r.count;
        return fill;
    }

    void split(std::size_t k) {
        std::uint32_t* buf = buffer_.data();
        const std::uint32_t* head = program_.data() + program_begin_[k];
        const std::uint32_t spans = head[0], groups = head[1], removals = head[2];
        // Removals in reverse order, from the end of the record.
        const std::uint32_t* p = program_.data() + program_begin_[k + 1];
        for (std::uint32_t r = 0; r < removals; ++r) {
            p -= 3;
            const std::uint32_t s = p[0], pos = p[1] & 0xFFFFu, code = p[1] >> 16, count = code & ~1u;
            std::uint32_t* region = buf + data_.strip_offsets[s];
            counts_[s] += static_cast<std::int32_t>(count);
            const std::uint32_t n = live(s);
            std::memmove(region + pos + count, region + pos, (n - pos - count) * sizeof(std::uint32_t));
            if (!(code & 1u)) {
                std::fill(region + pos, region + pos + count, region[pos - 1]);
            } else {
                const std::uint32_t a = region[pos - 2], b = region[pos - 1];
                for (std::uint32_t j = 0; j < count; j += 2) {
                    region[pos + j] = a;
                    region[pos + j + 1] = b;
                }
            }
        }
        rewrite(buf, head + 3 + 2 * spans, groups, 1);
    }

    // Replays every collapse forward and checks each record against the state it must meet: a rewrite
    // finds its own vertex inside its strip's live part, a removal removes a real degenerate run of the
    // drawn part, and the stored triangle counts are the strips' own. Afterwards no go_to_* sequence can
    // leave the buffer or the regions.
    bool replay_check(std::string& why) {
        const Data& d = data_;
        const std::size_t K = d.collapse_count();
        std::vector<std::uint32_t> strip_of(buffer_.size());
        for (std::size_t s = 0; s < strip_count(); ++s)
            std::fill(strip_of.begin() + d.strip_offsets[s], strip_of.begin() + d.strip_offsets[s + 1], std::uint32_t(s));
        std::size_t tris = 0;
        for (std::size_t s = 0; s < strip_count(); ++s) tris += strip_triangles(s);
        if (tris != d.triangles[0]) {
            why = "the triangle count of the full level does not match the strips";
            return false;
        }
        removal_fill_.assign(d.removals.size(), 0);
        for (std::size_t k = 0; k < K; ++k) {
            std::size_t before = 0;
            for (std::uint32_t i = span_begin_[k]; i < span_begin_[k + 1]; ++i) before += strip_triangles(spans_[i].first);
            std::uint32_t* buf = buffer_.data();
            for (std::uint32_t o = d.collapse_begin[k]; o < d.collapse_begin[k + 1]; ++o) {
                const std::uint32_t v = d.vertex_of_ordinal(o), t = d.targets[o];
                for (std::uint32_t i = d.rewrite_begin[o]; i < d.rewrite_begin[o + 1]; ++i) {
                    const std::uint32_t p = d.rewrite_positions[i], s = strip_of[p];
                    const std::uint32_t limit = d.restart ? static_cast<std::uint32_t>(counts_[s])
                                                          : d.strip_offsets[s + 1] - d.strip_offsets[s];
                    if (buf[p] != v || p - d.strip_offsets[s] >= limit) {
                        why = "collapse " + std::to_string(k) + ": a rewrite does not meet its vertex";
                        return false;
                    }
                    buf[p] = t;
                }
            }
            for (std::uint32_t i = d.removal_begin[k]; i < d.removal_begin[k + 1]; ++i) {
                const Removal& r = d.removals[i];
                const std::uint32_t* region = buf + d.strip_offsets[r.strip];
                bool ok = std::uint32_t(r.pos) + r.count <= static_cast<std::uint32_t>(counts_[r.strip]);
                for (std::uint32_t j = 0; ok && j < r.count; ++j)
                    ok = region[r.pos + j] == (r.type == 1 ? region[r.pos - 1] : region[r.pos - 2 + (j & 1u)]);
                if (!ok) {
                    why = "collapse " + std::to_string(k) + ": a removal does not meet a degenerate run";
                    return false;
                }
                removal_fill_[i] = remove_run(r);
            }
            std::size_t after = 0;
            for (std::uint32_t i = span_begin_[k]; i < span_begin_[k + 1]; ++i) after += strip_triangles(spans_[i].first);
            if (before < after || before - after != d.triangles[k] - d.triangles[k + 1]) {
                why = "collapse " + std::to_string(k) + ": the stored triangle count does not match the strips";
                return false;
            }
            ++level_;
        }
        return true;
    }

    std::size_t strip_triangles(std::size_t s) const {
        const std::uint32_t* p = buffer_.data() + data_.strip_offsets[s];
        std::size_t n = 0;
        for (std::int32_t i = 0; i + 2 < counts_[s]; ++i) n += p[i] != p[i + 1] && p[i + 1] != p[i + 2] && p[i] != p[i + 2];
        return n;
    }

    Data data_;
    detail::large_vector<std::uint32_t> buffer_;
    std::vector<std::int32_t> counts_;
    std::size_t level_ = 0;
    std::vector<std::uint32_t> span_begin_;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> spans_;
    std::vector<std::uint32_t> program_begin_;
    detail::large_vector<std::uint32_t> program_;
    std::vector<std::uint32_t> removal_fill_;  // per removal, its fill (replay_check, for compile_program)
    std::size_t changed_lo_ = 0, changed_hi_ = 0;  // levels visited since clear_changes()
    mutable std::vector<std::uint32_t> scratch_lo_;    // changes(): per strip the lowest changed element
    mutable std::vector<std::uint64_t> scratch_seen_;  // changes(): the strips touched
};

}  // namespace lodstrips
