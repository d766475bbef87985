// LOD chains by successive half-edge collapse, with one shared vertex buffer (the layout of
// meshoptimizer's LOD chains: Kapoulkine, "meshoptimizer", simplification and "LOD chains" in its README)
// and the collapse sequences of all steps concatenated into one progressive-mesh sequence on the input
// (Hoppe, "Progressive Meshes", SIGGRAPH 1996). With optimal placement (Hoppe, "New Quadric Metric for
// Simplifying Meshes with Appearance Attributes", 1999) each level has its own vertex data; the steps
// still run level by level, each on the previous level's output (docs/pack.md, "Placement").
#include "lodforge/simplify/lod_chain.h"

#include "lodforge/error.h"
#include "lodforge/progress_range.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace lodforge {
namespace {

constexpr std::uint32_t kNone = ~0u;

bool is_count(const LodLevelTarget& t) { return t.ratio > 0.f || t.triangles > 0; }

std::string level_name(std::size_t i) { return "LOD level " + std::to_string(i + 1); }

// Validates the targets; returns the triangle target of each count level (0 for error levels).
std::vector<std::size_t> triangle_targets(const std::vector<LodLevelTarget>& levels, std::size_t input_triangles) {
    if (levels.empty()) throw Error(Error::Kind::argument, "build_lod_chain: no levels given");
    std::vector<std::size_t> targets(levels.size(), 0);
    std::size_t last_count = input_triangles;
    bool have_count = false;
    float last_error = 0.f;
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const LodLevelTarget& t = levels[i];
        const bool has_error = !std::isinf(t.max_error);
        const int kinds = (t.ratio != 0.f) + (t.triangles != 0) + has_error;
        if (kinds != 1)
            throw Error(Error::Kind::argument,
                        level_name(i) + ": set exactly one of ratio, triangles and max_error");
        // A ratio of 1 would copy the input (level 0 already is it); a triangle count at or above the
        // input's stays allowed, so one preset serves meshes of any size.
        if (t.ratio != 0.f && !(t.ratio > 0.f && t.ratio < 1.f))
            throw Error(Error::Kind::argument, level_name(i) + ": ratio " + std::to_string(t.ratio) +
                                                   " is outside (0, 1)");
        if (has_error && !(t.max_error > 0.f && std::isfinite(t.max_error)))
            throw Error(Error::Kind::argument, level_name(i) + ": max error must be finite and > 0");
        if (is_count(t)) {
            const std::size_t n =
                t.triangles ? t.triangles
                            : std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(
                                                           static_cast<double>(t.ratio) * input_triangles)));
            if (have_count && n >= last_count)
                throw Error(Error::Kind::argument,
                            level_name(i) + ": " + std::to_string(n) +
                                " triangles is not fewer than the previous level's " + std::to_string(last_count));
            targets[i] = n;
            last_count = n;
            have_count = true;
        } else {
            if (t.max_error <= last_error)
                throw Error(Error::Kind::argument,
                            level_name(i) + ": max error must be larger than the previous level's");
            last_error = t.max_error;
        }
    }
    return targets;
}

void build_shared(const Mesh& input, LodChainResult& out) {
    const std::size_t n = input.vertex_count();
    const std::size_t levels = out.levels.size();
    // Coarsest level using each input vertex (-1: none).
    std::vector<int> coarsest(n, -1);
    for (std::size_t l = 0; l < levels; ++l) {
        const LodLevel& level = out.levels[l];
        for (std::uint32_t v : level.mesh.indices) {
            const std::uint32_t iv = level.input_vertex[v];
            coarsest[iv] = std::max(coarsest[iv], static_cast<int>(l));
        }
    }
    std::vector<std::uint32_t> order;
    order.reserve(n);
    for (std::uint32_t v = 0; v < n; ++v)
        if (coarsest[v] >= 0) order.push_back(v);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return coarsest[a] > coarsest[b]; });
    std::vector<std::uint32_t> shared_of(n, kNone);
    for (std::uint32_t i = 0; i < order.size(); ++i) shared_of[order[i]] = i;

    SharedLodBuffers& s = out.shared;
    s.input_vertex = order;
    Mesh& v = s.vertices;
    v.materials = input.materials;
    v.source_dir = input.source_dir;
    v.positions.resize(order.size());
    allocate_vertex_attributes(v, input, order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::uint32_t iv = order[i];
        v.positions[i] = input.positions[iv];
        copy_vertex_attributes(v, i, input, iv);
    }

    std::size_t total = 0;
    for (const LodLevel& level : out.levels) total += level.mesh.indices.size();
    s.indices.reserve(total);
    const bool materials = !input.face_materials.empty();
    if (materials) s.face_materials.reserve(total / 3);
    s.levels.resize(levels);
    for (std::size_t l = 0; l < levels; ++l) {
        const LodLevel& level = out.levels[l];
        LodIndexRange& range = s.levels[l];
        range.first_index = s.indices.size();
        range.index_count = level.mesh.indices.size();
        range.vertex_count = static_cast<std::uint32_t>(
            std::count_if(order.begin(), order.end(), [&](std::uint32_t iv) { return coarsest[iv] >= int(l); }));
        for (std::uint32_t idx : level.mesh.indices) s.indices.push_back(shared_of[level.input_vertex[idx]]);
        if (materials) {
            if (level.mesh.face_materials.size() == level.mesh.triangle_count())
                s.face_materials.insert(s.face_materials.end(), level.mesh.face_materials.begin(),
                                        level.mesh.face_materials.end());
            else
                s.face_materials.resize(s.face_materials.size() + level.mesh.triangle_count(), 0);
        }
    }
}

}  // namespace

std::vector<LodLevelTarget> lod_levels_from_ratios(const std::vector<float>& ratios) {
    std::vector<LodLevelTarget> out(ratios.size());
    for (std::size_t i = 0; i < ratios.size(); ++i) out[i].ratio = ratios[i];
    return out;
}

std::vector<LodLevelTarget> lod_levels_from_triangles(const std::vector<std::size_t>& triangles) {
    std::vector<LodLevelTarget> out(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) out[i].triangles = triangles[i];
    return out;
}

std::vector<LodLevelTarget> lod_levels_from_errors(const std::vector<float>& max_errors) {
    std::vector<LodLevelTarget> out(max_errors.size());
    for (std::size_t i = 0; i < max_errors.size(); ++i) out[i].max_error = max_errors[i];
    return out;
}

LodChainResult build_lod_chain(const Mesh& mesh, const LodChainParams& params, Progress* progress) {
    if (mesh.triangle_count() == 0) throw Error(Error::Kind::invalid, "build_lod_chain: the mesh has no triangles");
    const std::vector<std::size_t> targets = triangle_targets(params.levels, mesh.triangle_count());
    const double diagonal = mesh.bounds().diagonal();

    LodChainResult out;
    out.levels.reserve(params.levels.size() + 1);
    {
        LodLevel& l0 = out.levels.emplace_back();
        l0.mesh = mesh;
        l0.triangles = mesh.triangle_count();
        l0.input_vertex.resize(mesh.vertex_count());
        std::iota(l0.input_vertex.begin(), l0.input_vertex.end(), 0u);
    }
    SimplifyResult& seq = out.sequence;
    DistanceParams distance = params.distance;
    distance.vertex_errors = false;

    const double per_level = 1.0 / static_cast<double>(params.levels.size());
    const double simplify_share = params.measure ? 0.7 : 1.0;
    for (std::size_t i = 0; i < params.levels.size(); ++i) {
        const LodLevelTarget& t = params.levels[i];
        const LodLevel& prev = out.levels.back();
        const double begin = per_level * static_cast<double>(i);
        check_progress(progress, begin, "LOD chain");

        SimplifyParams sp = params.simplify;
        sp.target_ratio = 0.f;
        sp.target_triangles = targets[i];
        sp.max_error = std::numeric_limits<float>::infinity();
        if (i > 0) {
            // Artist masks are per input vertex: each step reads them through its level's vertices.
            const std::vector<std::uint32_t>& iv = prev.input_vertex;
            if (params.simplify.importance.size() == mesh.vertex_count())
                for (std::size_t v = 0; v < iv.size(); ++v) sp.importance[v] = params.simplify.importance[iv[v]];
            if (params.simplify.lock.size() == mesh.vertex_count())
                for (std::size_t v = 0; v < iv.size(); ++v) sp.lock[v] = params.simplify.lock[iv[v]];
            if (!sp.importance.empty()) sp.importance.resize(iv.size());
            if (!sp.lock.empty()) sp.lock.resize(iv.size());
        }
        if (!is_count(t)) {
            // The step's limit is relative to its own input's diagonal; the level's to the chain input's.
            const double step_diagonal = prev.mesh.bounds().diagonal();
            sp.max_error = step_diagonal > 0 ? static_cast<float>(t.max_error * diagonal / step_diagonal) : t.max_error;
        }
        // Extra frames (skinned poses, morph frames) follow the step's vertices.
        std::vector<std::vector<Vec3f>> step_frames(params.simplify.extra_frames.size());
        for (std::size_t f = 0; f < step_frames.size(); ++f) {
            step_frames[f].reserve(prev.input_vertex.size());
            for (std::uint32_t iv : prev.input_vertex) step_frames[f].push_back((*params.simplify.extra_frames[f])[iv]);
            sp.extra_frames[f] = &step_frames[f];
        }
        ProgressRange step_progress(progress, begin, begin + per_level * simplify_share);
        SimplifyResult r = simplify(prev.mesh, sp, &step_progress);

        LodLevel level;
        level.triangles = r.triangles;
        level.target_triangles = targets[i];
        level.reason = r.reason;
        level.step_error = r.error;
        level.step_error_relative = diagonal > 0 ? static_cast<float>(r.error / diagonal) : 0.f;
        level.accumulated_error = prev.accumulated_error + level.step_error;
        level.accumulated_error_relative = prev.accumulated_error_relative + level.step_error_relative;
        level.input_vertex.resize(r.vertex_map.size());
        for (std::size_t v = 0; v < r.vertex_map.size(); ++v) level.input_vertex[v] = prev.input_vertex[r.vertex_map[v]];

        // Append the step's collapses to the sequence, translated to input vertices and points.
        if (i == 0) seq.input_points = r.input_points;
        std::vector<std::uint32_t> point_vertex(r.input_points.empty() ? 0 : *std::max_element(r.input_points.begin(),
                                                                                                 r.input_points.end()) + 1,
                                                kNone);
        for (std::uint32_t v = static_cast<std::uint32_t>(r.input_points.size()); v-- > 0;)
            point_vertex[r.input_points[v]] = v;
        auto input_point = [&](std::uint32_t step_point) {
            return seq.input_points[prev.input_vertex[point_vertex[step_point]]];
        };
        level.collapses_begin = seq.collapses.size();
        for (const Collapse& c : r.collapses) {
            Collapse translated;
            translated.from_point = input_point(c.from_point);
            translated.to_point = input_point(c.to_point);
            translated.moves_begin = static_cast<std::uint32_t>(seq.moves.size());
            for (std::uint32_t m = c.moves_begin; m < c.moves_end; ++m)
                seq.moves.push_back({prev.input_vertex[r.moves[m].from], prev.input_vertex[r.moves[m].to]});
            translated.moves_end = static_cast<std::uint32_t>(seq.moves.size());
            seq.collapses.push_back(translated);
        }
        level.collapses_end = seq.collapses.size();
        level.mesh = std::move(r.mesh);

        if (params.measure) {
            ProgressRange measure_progress(progress, begin + per_level * simplify_share, begin + per_level);
            level.distance = compare(mesh, level.mesh, distance, &measure_progress);
            level.measured = true;
        }
        out.levels.push_back(std::move(level));
    }
    const LodLevel& last = out.levels.back();
    seq.triangles = last.triangles;
    seq.reason = last.reason;
    seq.error = last.accumulated_error;
    seq.error_relative = last.accumulated_error_relative;
    seq.vertex_map = last.input_vertex;
    // Optimal placement moves the kept vertices of every step: no two levels hold the same vertex data.
    if (params.simplify.placement == Placement::half_edge) build_shared(mesh, out);
    check_progress(progress, 1.0, "LOD chain");
    return out;
}

}  // namespace lodforge
