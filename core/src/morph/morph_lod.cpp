// Levels of detail of morphing meshes: half-edge collapse sequences shared by every frame.
//
// Based on:
//  - J. F. Ramos, "LODStrips: Continuous Level of Detail using Triangle Strips", PhD thesis, Universitat
//    Jaume I, 2008, chapter 6 (one collapse sequence per sampled frame of a supermesh);
//  - M. Garland, P. Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997
//    (the quadrics, here one set per frame for the single order);
//  - P. Cignoni, C. Rocchini, R. Scopigno, "Metro: Measuring Error on Simplified Surfaces", 1998
//    (the per-frame measurements).
//
// Half-edge collapses never move or create vertices, so a sequence built on one pose is a valid
// connectivity for every pose; the strategies differ only in which poses the collapse costs see.
#include "lodforge/morph/morph_lod.h"

#include "lodforge/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace lodforge {
namespace {

void check_levels(const std::vector<float>& levels) {
    if (levels.empty()) throw Error(Error::Kind::argument, "morph lod: at least one level is needed");
    for (std::size_t i = 0; i < levels.size(); ++i) {
        if (!(levels[i] > 0.f && levels[i] < 1.f))
            throw Error(Error::Kind::argument, "morph lod: level ratio " + std::to_string(levels[i]) + " is outside (0, 1)");
        if (i > 0 && !(levels[i] < levels[i - 1]))
            throw Error(Error::Kind::argument, "morph lod: level ratios must decrease");
    }
}

// The mesh one frame's simplification sees: base connectivity and attributes, that frame's positions
// (and normals when the input had them), points that hold in every frame.
Mesh frame_input(const MorphMesh& morph, std::size_t frame, const std::vector<std::uint32_t>& points) {
    Mesh m = morph.base;
    m.positions = morph.frame_positions[frame];
    if (morph.normals_from_input) m.normals = morph.frame_normals[frame];
    m.position_ids = points;
    return m;
}

MorphSequence build_sequence(const MorphMesh& morph, const MorphLodParams& params, std::size_t frame,
                             const std::vector<std::uint32_t>& points, const std::vector<std::size_t>& cost_frames,
                             std::size_t input_triangles, Progress* progress) {
    const Mesh input = frame_input(morph, frame, points);
    SimplifyParams sp = params.simplify;
    sp.placement = Placement::half_edge;
    sp.weld = false;
    sp.target_ratio = 0.f;
    sp.max_error = std::numeric_limits<float>::infinity();
    sp.target_triangles = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::llround(double(params.levels.back()) * double(input_triangles))));
    sp.frame_cost = params.frame_cost;
    sp.extra_frames.clear();
    for (std::size_t f : cost_frames)
        if (f != frame) sp.extra_frames.push_back(&morph.frame_positions[f]);
    MorphSequence seq;
    seq.frame = frame;
    seq.sequence = simplify(input, sp, progress);
    seq.sequence.mesh = Mesh{};
    seq.sequence.vertex_map.clear();
    // Each level ends at the first prefix with no more than its target triangles (the count only falls).
    const std::size_t total = seq.sequence.collapses.size();
    std::size_t lo = 0;
    for (float ratio : params.levels) {
        const auto target = static_cast<std::size_t>(std::llround(double(ratio) * double(input_triangles)));
        std::size_t a = lo, b = total;
        while (a < b) {
            const std::size_t mid = a + (b - a) / 2;
            if (replay_collapses(morph.base, seq.sequence, mid).size() / 3 <= target) b = mid;
            else a = mid + 1;
        }
        seq.level_collapses.push_back(a);
        seq.level_triangles.push_back(replay_collapses(morph.base, seq.sequence, a).size() / 3);
        lo = a;
    }
    return seq;
}

// Materials of the faces replay_collapses(base, seq, k) returns: the same replay, keeping each face's
// source. The faces replay starts from are those it returns for k = 0 (input corners, input order).
std::vector<std::uint32_t> face_materials_of(const MorphMesh& morph, const MorphSequence& seq, std::size_t k) {
    const Mesh& base = morph.base;
    const std::uint32_t first = base.face_materials.front();
    const bool uniform = std::all_of(base.face_materials.begin(), base.face_materials.end(),
                                     [&](std::uint32_t m) { return m == first; });
    const SimplifyResult& r = seq.sequence;
    if (uniform) return std::vector<std::uint32_t>(replay_collapses(base, r, k).size() / 3, first);
    const std::vector<std::uint32_t> start = replay_collapses(base, r, 0);
    std::vector<std::uint32_t> to(base.vertex_count());
    std::iota(to.begin(), to.end(), 0u);
    for (std::size_t i = 0; i < k; ++i)
        for (std::uint32_t m = r.collapses[i].moves_begin; m < r.collapses[i].moves_end; ++m) to[r.moves[m].from] = r.moves[m].to;
    auto resolve = [&](std::uint32_t w) {
        while (to[w] != w) w = to[w];
        return w;
    };
    std::vector<std::uint32_t> out;
    std::size_t j = 0;
    for (std::size_t f = 0; f < base.triangle_count() && j < start.size(); ++f) {
        const std::uint32_t* c = &base.indices[3 * f];
        if (c[0] != start[j] || c[1] != start[j + 1] || c[2] != start[j + 2]) continue;  // dropped up front
        j += 3;
        const std::uint32_t a = resolve(c[0]), b = resolve(c[1]), d = resolve(c[2]);
        const auto& p = r.input_points;
        if (p[a] == p[b] || p[b] == p[d] || p[a] == p[d]) continue;
        out.push_back(base.face_materials[f]);
    }
    return out;
}

// The compact mesh of `indices` with the given per-vertex positions and normals.
Mesh compact_mesh(const MorphMesh& morph, const std::vector<Vec3f>& positions, const std::vector<Vec3f>& normals,
                  const std::vector<std::uint32_t>& indices, const MorphSequence& seq, std::size_t k) {
    const Mesh& base = morph.base;
    const std::size_t n = base.vertex_count();
    std::vector<std::uint8_t> used(n, 0);
    for (std::uint32_t i : indices) used[i] = 1;
    std::vector<std::uint32_t> group(n);
    if (base.position_ids.size() == n) group = base.position_ids;
    else std::iota(group.begin(), group.end(), 0u);
    const PointsFirstLayout layout = points_first_layout(used, group, base.point_count());
    std::vector<std::uint32_t> new_index(n, 0);
    for (std::uint32_t i = 0; i < layout.order.size(); ++i) new_index[layout.order[i]] = i;
    Mesh out;
    const std::size_t m = layout.order.size();
    out.positions.resize(m);
    out.normals.resize(m);
    out.position_ids.resize(m);
    if (base.has_colors()) out.colors.resize(m);
    out.texcoords.assign(base.texcoords.size(), std::vector<Vec2f>(m));
    for (std::size_t i = 0; i < m; ++i) {
        const std::uint32_t v = layout.order[i];
        out.positions[i] = positions[v];
        out.normals[i] = normals[v];
        out.position_ids[i] = layout.point_of_group[group[v]];
        if (base.has_colors()) out.colors[i] = base.colors[v];
        for (std::size_t s = 0; s < base.texcoords.size(); ++s) out.texcoords[s][i] = base.texcoords[s][v];
    }
    out.indices.resize(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i) out.indices[i] = new_index[indices[i]];
    if (!base.face_materials.empty()) out.face_materials = face_materials_of(morph, seq, k);
    out.materials = base.materials;
    out.source_dir = base.source_dir;
    return out;
}

}  // namespace

const char* morph_order_name(MorphOrder order) {
    switch (order) {
    case MorphOrder::single: return "single";
    case MorphOrder::per_frame: return "per-frame";
    case MorphOrder::naive: return "naive";
    }
    return "unknown";
}

MorphLod build_morph_lod(const MorphMesh& morph, const MorphLodParams& params, Progress* progress) {
    check_levels(params.levels);
    if (morph.frame_count() == 0) throw Error(Error::Kind::argument, "morph lod: no frames");
    const std::vector<std::uint32_t> points = morph_points(morph);
    MorphLod lod;
    lod.order = params.order;
    lod.levels = params.levels;
    SimplifyResult none;
    none.input_points = points;
    lod.triangles = replay_collapses(morph.base, none, 0).size() / 3;
    std::vector<std::size_t> frames{0};
    std::vector<std::size_t> cost_frames{0};
    if (params.order == MorphOrder::per_frame) frames = spread_frames(morph.frame_count(), 0);
    if (params.order == MorphOrder::single) cost_frames = spread_frames(morph.frame_count(), params.cost_frames);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        check_progress(progress, double(i) / double(frames.size()), "morph lod");
        lod.sequences.push_back(build_sequence(morph, params, frames[i], points, cost_frames,
                                               morph.base.triangle_count(), progress));
    }
    check_progress(progress, 1.0, "morph lod");
    return lod;
}

std::size_t morph_sequence_at(const MorphLod& lod, std::size_t frame_count, double t) {
    if (lod.sequences.size() <= 1) return 0;
    const MorphSpan span = morph_span(frame_count, t);
    const std::size_t nearest = span.s < 0.5f ? span.frame : span.frame + 1;
    // Sequences are sorted by frame: the closest frame wins.
    std::size_t best = 0;
    for (std::size_t i = 1; i < lod.sequences.size(); ++i) {
        const auto d = [&](std::size_t f) { return f > nearest ? f - nearest : nearest - f; };
        if (d(lod.sequences[i].frame) < d(lod.sequences[best].frame)) best = i;
    }
    return best;
}

std::size_t morph_collapses_for(const MorphSequence& sequence, double lod_factor) {
    if (!(lod_factor >= 0.0 && lod_factor <= 1.0))
        throw Error(Error::Kind::argument, "morph: LOD factor must be in [0, 1], got " + std::to_string(lod_factor));
    const std::size_t coarsest = sequence.level_collapses.empty() ? 0 : sequence.level_collapses.back();
    return static_cast<std::size_t>(std::llround((1.0 - lod_factor) * double(coarsest)));
}

std::vector<std::uint32_t> morph_level_indices(const MorphMesh& morph, const MorphSequence& sequence, std::size_t k) {
    return replay_collapses(morph.base, sequence.sequence, k);
}

Mesh extract_morph(const MorphMesh& morph, const MorphLod& lod, double t, double lod_factor) {
    if (lod.sequences.empty()) throw Error(Error::Kind::argument, "morph: the LOD has no sequences");
    const MorphSequence& seq = lod.sequences[morph_sequence_at(lod, morph.frame_count(), t)];
    const std::size_t k = morph_collapses_for(seq, lod_factor);
    const std::vector<std::uint32_t> indices = morph_level_indices(morph, seq, k);
    std::vector<Vec3f> positions, normals;
    morph_positions_at(morph, t, positions);
    morph_normals_at(morph, t, normals);
    return compact_mesh(morph, positions, normals, indices, seq, k);
}

std::vector<MorphLevelError> measure_morph_lod(const MorphMesh& morph, const MorphLod& lod,
                                               const MorphMeasureParams& params, Progress* progress) {
    std::vector<std::size_t> frames = params.frames, levels = params.levels;
    if (frames.empty()) frames = spread_frames(morph.frame_count(), 0);
    if (levels.empty()) levels = spread_frames(lod.levels.size(), 0);
    DistanceParams dp = params.distance;
    dp.vertex_errors = false;
    std::vector<MorphLevelError> out;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const std::size_t f = frames[i];
        if (f >= morph.frame_count()) throw Error(Error::Kind::argument, "morph measure: frame " + std::to_string(f) + " out of range");
        check_progress(progress, double(i) / double(frames.size()), "morph measure");
        const double t = morph.frame_count() > 1 ? double(f) / double(morph.frame_count() - 1) : 0.0;
        const MorphSequence& seq = lod.sequences[morph_sequence_at(lod, morph.frame_count(), t)];
        const Mesh reference = morph_keyframe_mesh(morph, f);
        for (std::size_t level : levels) {
            if (level >= seq.level_collapses.size()) throw Error(Error::Kind::argument, "morph measure: level out of range");
            const std::size_t k = seq.level_collapses[level];
            const std::vector<std::uint32_t> indices = morph_level_indices(morph, seq, k);
            const Mesh test = compact_mesh(morph, morph.frame_positions[f], morph.frame_normals[f], indices, seq, k);
            MorphLevelError e;
            e.level = level;
            e.frame = f;
            e.triangles = test.triangle_count();
            e.distance = compare(reference, test, dp);
            out.push_back(std::move(e));
        }
    }
    check_progress(progress, 1.0, "morph measure");
    return out;
}

}  // namespace lodforge
