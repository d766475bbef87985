// Morph LODStrips runtime: one LODStrips strip set for a morphing mesh with one change set per collapse
// order (one for a single order, one per sampled frame for per-frame orders), with per-frame vertex
// positions and normals blended on the GPU-facing vertex buffer.
// Single header, C++17, standard library only; needs lodstrips_runtime.h next to it (same rules).
// Design: docs/morph.md ("Morph LODStrips"), format: docs/formats/lfmstrips.md, in the LodForge
// repository. Follows J. F. Ramos Romero, "LODStrips: Continuous Level of Detail using Triangle Strips"
// (PhD dissertation, Universitat Jaume I, 2008), ch. 6: a supermesh whose frames share one
// connectivity, so one strip set serves every frame, with the change set of the frame in force.
//
//   lodstrips::MorphLodStrips m;
//   std::string error;
//   if (!m.load_file("horse.lfmstrips", &error)) { ... }
//   m.set_frame(0.37);                          // t in [0, 1] over the whole sequence
//   m.go_to_lod(0.25);                          // 0 = coarsest stored level, 1 = full detail
//   upload_vertices(m.positions(), m.normals(), m.vertex_count());   // only the prefix in use
//   upload(m.indices(), m.index_count());       // afterwards only m.changes() spans
//
// Vertices are in the active change set's canonical order, so a level uses the prefix [0, vertex_count()).
// Only that prefix is blended: set_frame(t) blends it, go_to_lod to a finer level blends the vertices it
// adds, so set_frame and go_to_lod commute (the drawn prefix and the element buffer are the same in
// either order) and a frame change at a coarse level costs only the coarse level's vertices.
// With several change sets, set_frame(t) makes the set of the keyframe nearest t active: its element
// buffer and vertex numbering replace the previous ones (indices() points elsewhere, changes() reports
// the whole buffer once, vertex_ids() maps the new numbering to the file's), at the same LOD request.
// Every set keeps its own runtime at its last level, so a switch in steady playback moves no collapse;
// set_live_set_limit(n) trades that memory for a rebuild on switching to a parked set.
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
inline constexpr std::uint32_t morph_format_version = 2;  // written; version 1 is read too
inline constexpr std::uint32_t morph_flag_quantized = 1u;  // FRMS: 16-bit positions, octahedral normals

// A further change set (per-frame orders): the records of one keyframe's collapse sequence over the
// shared strip set, in that sequence's own canonical numbering.
struct MorphChangeSet {
    std::uint32_t frame = 0;              // keyframe whose sequence it records
    std::vector<std::uint32_t> to_base;   // this set's vertex c → vertex of `strips` (a permutation)
    Data records;                         // only collapse_begin, targets, rewrite_begin, rewrite_positions,
                                          // removal_begin, removals, triangles are used
};

// Everything a .lfmstrips file holds, decoded.
struct MorphData {
    Data strips;                         // the strip set + change set 0; its vertex arrays hold frame 0
    std::uint32_t frame_count = 0;
    std::vector<float> frame_positions;  // frame_count × 3 × vertex_count, in the numbering of `strips`
    std::vector<float> frame_normals;    // the same layout, unit length
    bool quantized = false;              // how the file stored the frames (informational)
    std::uint32_t version = morph_format_version;  // of the file read (informational)
    std::uint32_t strips_frame = 0;      // keyframe of change set 0 (a single order's: serves every frame)
    std::vector<MorphChangeSet> frame_sets;  // change sets 1.. (per-frame orders), frames increasing
    std::size_t change_set_count() const { return 1 + frame_sets.size(); }
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

// Section SETS of a version 2 file (docs/formats/lfmstrips.md): the change sets' frames, then per further set its
// numbering and records. Counts are bounded by the bytes left (every varint takes at least one byte), so
// nothing is allocated beyond the file; the records themselves are checked by MorphLodStrips::assign.
inline bool decode_sets(const std::uint8_t* p, std::size_t size, MorphData& d, std::string* error) {
    Reader r(p, size);
    const std::uint32_t n = d.strips.vertex_count;
    const std::size_t strips = d.strips.strip_count();
    auto bad = [&](std::size_t set, const std::string& what) {
        return fail(error, "section SETS, change set " + std::to_string(set) + ", byte " +
                               std::to_string(size - r.left()) + ": " + what);
    };
    const std::uint32_t q = r.count(std::min<std::uint64_t>(d.frame_count, r.left()));
    if (!r.ok() || q == 0) return fail(error, "section SETS: bad change set count (1 to the frame count)");
    std::vector<std::uint32_t> frames(q);
    for (std::uint32_t i = 0; i < q; ++i) {
        frames[i] = r.count(d.frame_count - 1u);
        if (!r.ok() || (i > 0 && frames[i] <= frames[i - 1])) return bad(i, "frames must be increasing keyframes");
    }
    d.strips_frame = frames[0];
    for (std::uint32_t i = 1; i < q; ++i) {
        MorphChangeSet& cs = d.frame_sets.emplace_back();
        cs.frame = frames[i];
        if (r.left() < n) return bad(i, "truncated vertex numbering");
        cs.to_base.resize(n);
        for (std::uint32_t& v : cs.to_base) v = r.count(n - 1u);
        Data& rec = cs.records;
        const std::uint32_t collapses = r.count(std::min<std::uint64_t>(n, r.left()));
        if (!r.ok()) return bad(i, "bad vertex numbering or collapse count");
        rec.collapse_begin.assign(1, 0);
        rec.rewrite_begin.assign(1, 0);
        rec.removal_begin.assign(1, 0);
        rec.triangles.assign(1, d.strips.triangles.empty() ? 0u : d.strips.triangles.front());
        std::uint64_t removed = 0;
        for (std::uint32_t k = 0; k < collapses; ++k) {
            const std::uint32_t m = r.count(std::min<std::uint64_t>(n - removed, r.left()));
            const std::int64_t lost = unzigzag(r.varint());
            if (!r.ok() || m == 0) return bad(i, "collapse " + std::to_string(k) + ": bad vertex count");
            const std::int64_t tris = std::int64_t(rec.triangles.back()) - lost;
            if (tris < 0 || tris > 0xFFFFFFFFll) return bad(i, "collapse " + std::to_string(k) + ": bad triangle count");
            for (std::uint32_t j = 0; j < m; ++j, ++removed) {
                const auto v = static_cast<std::uint32_t>(n - 1 - removed);
                const std::uint64_t delta = r.varint();
                const std::uint32_t count = r.count(r.left());
                if (!r.ok() || delta == 0 || delta > v) return bad(i, "collapse " + std::to_string(k) + ": bad target");
                rec.targets.push_back(v - static_cast<std::uint32_t>(delta));
                std::uint64_t at = 0;
                for (std::uint32_t c = 0; c < count; ++c) {
                    const std::uint64_t g = r.varint();
                    if (g < 0xFFFFFFFFull) at = c == 0 ? g : at + 1 + g;
                    if (!r.ok() || g >= 0xFFFFFFFFull || at >= 0xFFFFFFFFull)
                        return bad(i, "collapse " + std::to_string(k) + ": bad position");
                    rec.rewrite_positions.push_back(static_cast<std::uint32_t>(at));
                }
                rec.rewrite_begin.push_back(static_cast<std::uint32_t>(rec.rewrite_positions.size()));
            }
            const std::uint32_t removals = r.count(r.left());
            std::int64_t strip = 0;
            for (std::uint32_t c = 0; c < removals; ++c) {
                strip += unzigzag(r.varint());
                const std::uint64_t pos = r.varint(), code = r.varint();
                if (!r.ok() || strip < 0 || std::uint64_t(strip) >= strips || pos > 0xFFFF || (code >> 1) >= 0x7FFF)
                    return bad(i, "collapse " + std::to_string(k) + ": bad removal");
                Removal x;
                x.strip = static_cast<std::uint32_t>(strip);
                x.pos = static_cast<std::uint16_t>(pos);
                x.count = static_cast<std::uint16_t>(2 * ((code >> 1) + 1));
                x.type = static_cast<std::uint8_t>((code & 1u) + 1);
                rec.removals.push_back(x);
            }
            rec.collapse_begin.push_back(static_cast<std::uint32_t>(rec.targets.size()));
            rec.removal_begin.push_back(static_cast<std::uint32_t>(rec.removals.size()));
            rec.triangles.push_back(static_cast<std::uint32_t>(tris));
        }
    }
    if (!r.ok()) return fail(error, "section SETS is truncated");
    if (!r.at_end()) return fail(error, "section SETS: bytes after the last change set");
    return true;
}

}  // namespace detail

// Decodes a .lfmstrips image. Returns false with a message naming the section and the problem; the
// strip records are checked by MorphLodStrips::assign (LodStrips::assign's replay).
inline bool decode_morph(const void* bytes, std::size_t size, MorphData& out, std::string* error) {
    using detail::fail;
    std::uint32_t version = 0;
    std::vector<detail::Section> sections;
    if (!detail::read_container(static_cast<const std::uint8_t*>(bytes), size, morph_file_magic, ".lfmstrips", version,
                                sections, error))
        return false;
    if (version != 1 && version != 2)
        return fail(error, "unsupported format version " + std::to_string(version) + " (this reader: 1 and 2)");
    static const char* const names[3] = {"LSTR", "FRMS", "SETS"};
    if (!detail::expect_sections(sections, names, version == 1 ? 2u : 3u, error)) return false;
    const std::uint8_t* sec[3] = {nullptr, nullptr, nullptr};
    std::size_t len[3] = {0, 0, 0};
    for (std::size_t i = 0; i < sections.size(); ++i) sec[i] = sections[i].data, len[i] = sections[i].size;

    MorphData d;
    d.version = version;
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
    if (version >= 2 && !detail::decode_sets(sec[2], len[2], d, error)) return false;
    out = std::move(d);
    return true;
}

// The runtime: the strips (element buffer, levels) of the active change set and a vertex buffer at time t.
class MorphLodStrips {
public:
    using Span = LodStrips::Span;

    // On failure (of the decoder or of assign) the object is left empty.
    bool load_memory(const void* bytes, std::size_t size, std::string* error = nullptr) {
        MorphData d;
        if (!decode_morph(bytes, size, d, error)) {
            *this = MorphLodStrips();
            return false;
        }
        return assign(std::move(d), error);
    }

    bool load_file(const std::string& path, std::string* error = nullptr) {
        std::ifstream in(path, std::ios::binary);
        const std::vector<char> bytes = in ? std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>())
                                           : std::vector<char>();
        if (!in.is_open() || in.bad()) {
            *this = MorphLodStrips();
            return detail::fail(error, in.is_open() ? "read error" : "cannot open for reading");
        }
        return load_memory(bytes.data(), bytes.size(), error);
    }

    // Checks the frames, each change set's numbering, then every change set's strips (LodStrips::assign
    // replays every record). Starts at full detail and t = 0. On failure the object is left empty.
    bool assign(MorphData d, std::string* error = nullptr) {
        const std::size_t limit = max_live_;
        *this = MorphLodStrips();
        max_live_ = limit;
        if (!take(std::move(d), error)) {
            *this = MorphLodStrips();
            max_live_ = limit;
            return false;
        }
        return true;
    }

    // Memory against switch time (docs/morph.md): at most n further change sets (besides set 0) keep a
    // live runtime, their element buffer at their level; the others keep only their records and are
    // rebuilt when set_frame needs them (one replay of the set's records, as at load), least recently
    // used first out. 0 = every set live (the default). Kept across assign/load. Buffers are the same
    // either way: a set's buffer depends only on its level.
    void set_live_set_limit(std::size_t n) {
        max_live_ = n;
        if (!sets_.empty()) make_live(active_);
    }
    std::size_t live_set_count() const {
        std::size_t n = 0;
        for (std::uint8_t l : live_) n += l;
        return n;
    }

    std::size_t frame_count() const { return frame_count_; }
    double time() const { return t_; }

    // The change sets: one per collapse order the file holds (per-frame orders: one per sampled frame).
    std::size_t change_set_count() const { return sets_.size(); }
    std::size_t change_set() const { return active_; }
    std::size_t change_set_frame(std::size_t set) const { return set_frames_[set]; }
    // The change set serving time t: the one whose keyframe is nearest t (ties: the earlier), as the
    // .lfmorph extraction (morph_sequence_at).
    std::size_t change_set_at(double t) const {
        if (sets_.size() <= 1) return 0;
        std::size_t k = 0;
        float s = 0.f;
        span(clamp_time(t), k, s);
        const std::size_t nearest = s < 0.5f ? k : k + 1;
        std::size_t best = 0;
        const auto dist = [&](std::size_t f) { return f > nearest ? f - nearest : nearest - f; };
        for (std::size_t i = 1; i < sets_.size(); ++i)
            if (dist(set_frames_[i]) < dist(set_frames_[best])) best = i;
        return best;
    }

    // t in [0, 1] over the whole sequence (clamped; NaN = 0). Keyframes are evenly spaced: between
    // keyframes k and k+1 with fraction s, p = (1 − s)·p_k + s·p_{k+1}, n = normalise((1 − s)·n_k + s·n_{k+1}).
    // When another change set serves t it becomes active at the same LOD request (factor, level or
    // triangle budget, as last asked).
    void set_frame(double t) {
        t_ = clamp_time(t);
        const std::size_t want = change_set_at(t_);
        if (want != active_) {
            active_ = want;
            make_live(active_);
            replay_request();
            sets_[active_].clear_changes();  // the whole buffer is reported instead
            switched_ = true;
        }
        blended_ = 0;
        blend_to(vertex_count());
    }

    void go_to_lod(double factor) {
        request_ = Request::lod, factor_ = factor;
        replay_request();
        blend_to(vertex_count());
    }
    void go_to_level(std::size_t level) {
        request_ = Request::level, count_ = level;
        replay_request();
        blend_to(vertex_count());
    }
    void go_to_triangles(std::size_t n) {
        request_ = Request::triangles, count_ = n;
        replay_request();
        blend_to(vertex_count());
    }

    // Vertex buffer: the active set's canonical order, 3 floats per vertex; [0, vertex_count()) holds the
    // pose at time().
    const float* positions() const { return positions_.data(); }
    const float* normals() const { return normals_.data(); }
    std::size_t vertex_count() const { return sets_.empty() ? 0 : sets_[active_].vertex_count(); }
    std::size_t total_vertex_count() const { return vertices_; }
    // Buffer vertex → vertex of the file's numbering (change set 0's: that of MorphData::strips and the
    // frames); the identity while change set 0 is active.
    const std::uint32_t* vertex_ids() const { return sets_.empty() ? nullptr : ids_[active_].data(); }
    // Vertices rewritten since clear_vertex_changes() (one range; empty when none).
    Span vertex_changes() const {
        if (dirty_hi_ <= dirty_lo_) return {};
        return {dirty_lo_, dirty_hi_ - dirty_lo_};
    }
    void clear_vertex_changes() {
        dirty_lo_ = 0xFFFFFFFFu;
        dirty_hi_ = 0;
    }

    // The element buffer and its changes: those of the active change set's LodStrips runtime. After a
    // change of set, indices() points at the new set's buffer and changes() is the whole buffer.
    const LodStrips& strips() const {
        static const LodStrips none;
        return sets_.empty() ? none : sets_[active_];
    }
    const std::uint32_t* indices() const { return strips().indices(); }
    std::size_t index_count() const { return strips().index_count(); }
    std::size_t strip_count() const { return strips().strip_count(); }
    const std::uint32_t* draw_offsets() const { return strips().draw_offsets(); }
    const std::int32_t* draw_counts() const { return strips().draw_counts(); }
    std::size_t level() const { return strips().level(); }
    std::size_t collapse_count() const { return strips().collapse_count(); }
    std::size_t triangle_count() const { return strips().triangle_count(); }
    std::vector<Span> changes() const {
        if (switched_) return {Span{0, static_cast<std::uint32_t>(index_count())}};
        return strips().changes();
    }
    void clear_changes() {
        switched_ = false;
        if (!sets_.empty()) sets_[active_].clear_changes();
    }
    void triangles(std::vector<std::uint32_t>& out) const { strips().triangles(out); }

private:
    enum class Request { level, lod, triangles };

    static double clamp_time(double t) { return !(t >= 0.0) ? 0.0 : t > 1.0 ? 1.0 : t; }

    void span(double t, std::size_t& k, float& s) const {
        k = 0, s = 0.f;
        if (frame_count_ > 1) {
            const double x = t * double(frame_count_ - 1);
            k = std::min(static_cast<std::size_t>(x), std::size_t(frame_count_) - 2);
            s = static_cast<float>(x - double(k));
        }
    }

    void replay_request() {
        if (sets_.empty()) return;
        LodStrips& l = sets_[active_];
        if (request_ == Request::lod) l.go_to_lod(factor_);
        else if (request_ == Request::triangles) l.go_to_triangles(count_);
        else l.go_to_level(std::min(count_, l.collapse_count()));
    }

    bool take(MorphData d, std::string* error) {
        const std::uint32_t n = d.strips.vertex_count;
        const std::size_t values = std::size_t(d.frame_count) * 3u * n;
        if (d.frame_count == 0 || d.frame_positions.size() != values || d.frame_normals.size() != values)
            return detail::fail(error, "frame arrays have inconsistent sizes");
        for (const auto* arr : {&d.frame_positions, &d.frame_normals})
            for (float x : *arr)
                if (!std::isfinite(x)) return detail::fail(error, "a frame value is not finite");
        if (d.strips_frame >= d.frame_count) return detail::fail(error, "change set 0 names a frame past the last");
        frame_count_ = d.frame_count;
        vertices_ = n;
        set_frames_.push_back(d.strips_frame);
        for (std::size_t i = 0; i < d.frame_sets.size(); ++i) {
            const std::string set = "change set " + std::to_string(i + 1) + ": ";
            if (d.frame_sets[i].frame >= d.frame_count || d.frame_sets[i].frame <= set_frames_.back())
                return detail::fail(error, set + "frames must be increasing keyframes");
            set_frames_.push_back(d.frame_sets[i].frame);
            std::vector<std::uint8_t> seen(n, 0);
            if (d.frame_sets[i].to_base.size() != n) return detail::fail(error, set + "numbering has the wrong size");
            for (std::uint32_t v : d.frame_sets[i].to_base) {
                if (v >= n || seen[v]) return detail::fail(error, set + "numbering is not a permutation");
                seen[v] = 1;
            }
        }
        // Further sets: the shared strips and vertex data in the set's numbering, with its own records.
        for (const std::uint32_t e : d.strips.initial_indices)
            if (e != restart_index && e >= n) return detail::fail(error, "an initial index is out of range");
        std::vector<Data> more;
        for (MorphChangeSet& cs : d.frame_sets) {
            more.push_back(set_data(d.strips, cs.to_base, std::move(cs.records)));
            ids_.push_back(std::move(cs.to_base));
        }
        frame_positions_ = std::move(d.frame_positions);
        frame_normals_ = std::move(d.frame_normals);
        std::vector<std::uint32_t> identity(n);
        for (std::uint32_t c = 0; c < n; ++c) identity[c] = c;
        ids_.insert(ids_.begin(), std::move(identity));
        sets_.resize(1 + more.size());
        std::string why;
        if (!sets_[0].assign(std::move(d.strips), &why)) return detail::fail(error, more.empty() ? why : "change set 0: " + why);
        for (std::size_t i = 0; i < more.size(); ++i)
            if (!sets_[i + 1].assign(std::move(more[i]), &why)) return detail::fail(error, "change set " + std::to_string(i + 1) + ": " + why);
        live_.assign(sets_.size(), 1);
        parked_.resize(sets_.size());
        last_use_.assign(sets_.size(), 0);
        positions_.assign(3u * std::size_t(vertices_), 0.f);
        normals_.assign(3u * std::size_t(vertices_), 0.f);
        set_frame(0.0);
        make_live(active_);  // applies the live-set limit
        return true;
    }

    // The strips of change set 0 (`base`: layout, vertex arrays, file numbering) renumbered into a further
    // set's numbering (`to`: set vertex → base vertex, a permutation), with that set's records.
    static Data set_data(const Data& base, const std::vector<std::uint32_t>& to, Data&& records) {
        const std::uint32_t n = base.vertex_count;
        Data x;
        std::vector<std::uint32_t> from_base(n);
        for (std::uint32_t c = 0; c < n; ++c) from_base[to[c]] = c;
        x.vertex_count = n;
        auto gather = [&](const std::vector<float>& src, std::size_t width) {
            std::vector<float> out(src.size() == width * n ? width * n : 0);
            for (std::uint32_t c = 0; c < n && !out.empty(); ++c)
                std::copy(src.begin() + std::ptrdiff_t(width * to[c]), src.begin() + std::ptrdiff_t(width * to[c] + width),
                          out.begin() + std::ptrdiff_t(width * c));
            return out;
        };
        x.positions = gather(base.positions, 3);
        // no normals: the runtime's own (blended) are what is drawn, and they cost 12 bytes a vertex per set
        x.colors = gather(base.colors, 4);
        x.colors_8bit = base.colors_8bit;
        for (const auto& set : base.texcoords) x.texcoords.push_back(gather(set, 2));
        x.materials = base.materials;
        x.restart = base.restart;
        x.strip_offsets = base.strip_offsets;
        x.strip_materials = base.strip_materials;
        x.initial_indices = base.initial_indices;
        for (std::uint32_t& e : x.initial_indices)
            if (e != restart_index) e = from_base[e];
        x.collapse_begin = std::move(records.collapse_begin);
        x.targets = std::move(records.targets);
        x.rewrite_begin = std::move(records.rewrite_begin);
        x.rewrite_positions = std::move(records.rewrite_positions);
        x.removal_begin = std::move(records.removal_begin);
        x.removals = std::move(records.removals);
        x.triangles = std::move(records.triangles);
        return x;
    }

    // Makes set q live (rebuilding its runtime from its parked records) and parks the least recently used
    // others beyond the limit. Set 0 (the base) and the active set stay live.
    void make_live(std::size_t q) {
        last_use_[q] = ++clock_;
        if (!live_[q]) {
            Data records = std::move(parked_[q]);
            parked_[q] = Data();
            // the same data passed LodStrips::assign at load, so this cannot fail
            sets_[q].assign(set_data(sets_[0].data(), ids_[q], std::move(records)));
            live_[q] = 1;
        }
        if (max_live_ == 0) return;
        for (;;) {
            std::size_t live = 0, oldest = 0;
            for (std::size_t i = 1; i < sets_.size(); ++i)
                if (live_[i]) {
                    ++live;
                    if (i != q && (oldest == 0 || last_use_[i] < last_use_[oldest])) oldest = i;
                }
            if (live <= max_live_ || oldest == 0) return;
            park(oldest);
        }
    }

    // Keeps only set q's records (what the file holds for it) and drops its runtime.
    void park(std::size_t q) {
        const Data& d = sets_[q].data();
        Data& r = parked_[q];
        r.collapse_begin = d.collapse_begin;
        r.targets = d.targets;
        r.rewrite_begin = d.rewrite_begin;
        r.rewrite_positions = d.rewrite_positions;
        r.removal_begin = d.removal_begin;
        r.removals = d.removals;
        r.triangles = d.triangles;
        sets_[q] = LodStrips();
        live_[q] = 0;
    }

    // Blends vertices [blended_, upto) of the active numbering at t_.
    void blend_to(std::size_t upto) {
        if (upto <= blended_) return;
        const std::size_t n = vertices_;
        std::size_t k = 0;
        float s = 0.f;
        span(t_, k, s);
        const float* pa = frame_positions_.data() + k * 3u * n;
        const float* na = frame_normals_.data() + k * 3u * n;
        const float* pb = s == 0.f ? pa : pa + 3u * n;
        const float* nb = s == 0.f ? na : na + 3u * n;
        const std::uint32_t* id = active_ == 0 ? nullptr : ids_[active_].data();
        const float r = 1.f - s;
        for (std::size_t v = blended_; v < upto; ++v) {
            const std::size_t b = 3u * (id ? id[v] : v);
            float* po = &positions_[3 * v];
            float* no = &normals_[3 * v];
            if (s == 0.f) {
                po[0] = pa[b], po[1] = pa[b + 1], po[2] = pa[b + 2];
                no[0] = na[b], no[1] = na[b + 1], no[2] = na[b + 2];
                continue;
            }
            po[0] = pa[b] * r + pb[b] * s, po[1] = pa[b + 1] * r + pb[b + 1] * s, po[2] = pa[b + 2] * r + pb[b + 2] * s;
            float x = na[b] * r + nb[b] * s, y = na[b + 1] * r + nb[b + 1] * s, z = na[b + 2] * r + nb[b + 2] * s;
            const float len = std::sqrt(x * x + y * y + z * z);
            if (len > 0) {
                x /= len, y /= len, z /= len;
            } else {
                x = 0, y = 0, z = 1;
            }
            no[0] = x, no[1] = y, no[2] = z;
        }
        dirty_lo_ = std::min<std::uint32_t>(dirty_lo_, static_cast<std::uint32_t>(blended_));
        dirty_hi_ = std::max<std::uint32_t>(dirty_hi_, static_cast<std::uint32_t>(upto));
        blended_ = upto;
    }

    std::vector<LodStrips> sets_;                  // one per change set, each at its last level (if live)
    std::vector<std::uint8_t> live_;               // per set: sets_[q] holds its runtime
    std::vector<Data> parked_;                     // per set not live: its records only
    std::vector<std::uint64_t> last_use_;
    std::uint64_t clock_ = 0;
    std::size_t max_live_ = 0;                     // 0 = every set live
    std::vector<std::uint32_t> set_frames_;
    std::vector<std::vector<std::uint32_t>> ids_;  // per set: buffer vertex → file vertex
    std::size_t active_ = 0;
    bool switched_ = false;
    Request request_ = Request::level;
    double factor_ = 1.0;
    std::size_t count_ = 0;
    std::uint32_t frame_count_ = 0, vertices_ = 0;
    std::vector<float> frame_positions_, frame_normals_;
    std::vector<float> positions_, normals_;
    double t_ = 0;
    std::size_t blended_ = 0;
    std::uint32_t dirty_lo_ = 0xFFFFFFFFu, dirty_hi_ = 0;
};

}  // namespace lodstrips
