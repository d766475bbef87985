// The levels of a preset, whatever its method (preset_levels.h). The collapse chain follows Garland &
// Heckbert, "Simplifying Surfaces with Color and Texture using Quadric Error Metrics" (1998) and Hoppe,
// "New Quadric Metric for Simplifying Meshes with Appearance Attributes" (1999); clustering follows
// Rossignac & Borrel, "Multi-resolution 3D approximations for rendering complex scenes" (1993) and
// Lindstrom, "Out-of-Core Simplification of Large Polygonal Models" (2000). LODStrips (docs/lodstrips.md),
// the marching-cube octree (docs/mcoctree.md) and the out-of-core octree (docs/octree.md) build their own
// multiresolution structure once and the preset's levels are cuts of it, chosen by triangle count: these
// structures store their levels by triangle count (LODStrips: one per collapse, MC octree: one per
// priority, octree: one per tree level), not by an error bound the preset could name. Every level is
// measured against the input with the Metro distance (Cignoni, Rocchini & Scopigno, "Metro: Measuring
// Error on Simplified Surfaces", 1998).
#include "lodforge/pack/preset_levels.h"

#include "lodforge/error.h"
#include "lodforge/io/vertex_paint.h"
#include "lodforge/simplify/seams.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/pack/auto_levels.h"
#include "lodforge/octree/octree_build.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/io/temp_directory.h"
#include "lodforge/octree/ooc_soup.h"
#include "lodforge/progress_range.h"
#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/simplify/skin_cost.h"
#include "lodforge/simplify/simplify_cluster.h"
#include "lodforge/strips/lodstrips.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>

namespace lodforge {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string level_text(std::size_t i) { return "levels[" + std::to_string(i) + "]: "; }

// Triangle target of a level for the methods that take no error targets.
std::size_t target_triangles(const LodTarget& target, std::size_t input_triangles, std::size_t i,
                             const Preset& preset, const std::string& source) {
    double n = 0;
    switch (target.kind) {
    case LodTarget::Kind::ratio: n = std::floor(target.value * double(input_triangles)); break;
    case LodTarget::Kind::triangles: n = std::floor(target.value); break;
    case LodTarget::Kind::error:
        throw_error(Error::Kind::argument, source,
                    level_text(i) + "the " + std::string(to_string(preset.method)) +
                        " method takes ratio or triangle targets, not error targets");
    }
    if (!(n >= 1)) throw_error(Error::Kind::argument, source, level_text(i) + "the target asks for no triangles");
    return static_cast<std::size_t>(n);
}

std::vector<std::size_t> triangle_targets(const Mesh& mesh, const Preset& preset, const std::string& source) {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < preset.levels.size(); ++i)
        out.push_back(target_triangles(preset.levels[i], mesh.triangle_count(), i, preset, source));
    return out;
}

// Levels whose structure cannot carry the input's materials per face (the MC surface is rebuilt from
// points) keep none; the others keep the input's materials and texture search directory.
void keep_materials(const Mesh& input, Mesh& level) {
    level.materials = input.materials;
    level.source_dir = input.source_dir;
}

bool is_ply(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".ply";
}

LevelStop stop_of(SimplifyResult::StopReason r) {
    switch (r) {
    case SimplifyResult::StopReason::target_reached: return LevelStop::target_reached;
    case SimplifyResult::StopReason::error_limit: return LevelStop::error_limit;
    case SimplifyResult::StopReason::topology_limit: return LevelStop::topology_limit;
    }
    return LevelStop::closest;
}

// build_lod_chain reports level k's work in [k/n, (k+1)/n): the first report in each slice marks when
// that level started, which gives the time of every level (its simplification and its measurement).
class LevelClock final : public Progress {
public:
    LevelClock(Progress* parent, std::size_t levels) : parent_(parent), starts_(levels + 1) {}
    void report(double fraction, std::string_view stage) override {
        const auto n = static_cast<double>(starts_.size() - 1);
        const auto slice = static_cast<std::size_t>(std::clamp(std::floor(fraction * n + 1e-9), 0.0, n));
        for (std::size_t k = 0; k <= slice; ++k)
            if (!starts_[k]) starts_[k] = Clock::now();
        if (parent_) parent_->report(fraction, stage);
    }
    bool cancelled() const override { return parent_ && parent_->cancelled(); }
    std::vector<double> level_seconds() const {
        std::vector<double> out;
        const Clock::time_point now = Clock::now();
        for (std::size_t k = 0; k + 1 < starts_.size(); ++k) {
            const Clock::time_point end = starts_[k + 1] ? *starts_[k + 1] : now;
            out.push_back(starts_[k] ? std::chrono::duration<double>(end - *starts_[k]).count() : 0.0);
        }
        return out;
    }

private:
    Progress* parent_;
    std::vector<std::optional<Clock::time_point>> starts_;
};

DistanceParams measurement(const PresetLevelsParams& params) {
    DistanceParams d = params.distance;
    d.vertex_errors = false;
    return d;
}

void collapse_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params,
                     PresetLevels& out, Progress* progress, PresetLevelsStats* stats) {
    LodChainParams p;
    for (const LodTarget& t : preset.levels) {
        LodLevelTarget level;
        switch (t.kind) {
        case LodTarget::Kind::ratio: level.ratio = static_cast<float>(t.value); break;
        case LodTarget::Kind::triangles: level.triangles = static_cast<std::size_t>(t.value); break;
        case LodTarget::Kind::error: level.max_error = static_cast<float>(t.value); break;
        }
        p.levels.push_back(level);
    }
    p.simplify.weights = preset.weights;
    p.simplify.lock_border = preset.lock_border;
    SkinCostParams skin;
    skin.pose_samples = preset.skin.pose_samples;
    skin.weight = static_cast<float>(preset.skin.weight);
    const SkinPoseFrames poses = skin_pose_frames(mesh, skin);
    poses.attach(p.simplify);
    read_paint_sources(preset.importance, preset.lock, mesh, params.source_path, p.simplify.importance, p.simplify.lock);
    if (!preset.seams.empty()) p.simplify.seam_weights = parse_seam_weights(preset.seams);
    // Pose sampling checks one collapse order against every pose's positions of the input vertices, so
    // its levels keep input vertices (half-edge), whatever the preset's placement says.
    const Placement placement = poses.frames.empty() ? preset.placement : Placement::half_edge;
    p.simplify.placement = placement;
    p.measure = params.measure;
    p.distance = measurement(params);
    LevelClock clock(progress, p.levels.size());
    out.chain = build_lod_chain(mesh, p, &clock);
    if (stats) stats->level_seconds = clock.level_seconds();
    for (std::size_t k = 1; k < out.chain->levels.size(); ++k) {
        LodLevel& level = out.chain->levels[k];
        out.levels.push_back(std::move(level.mesh));
        level.mesh = Mesh{};
        out.target_triangles.push_back(level.target_triangles);
        out.stops.push_back(stop_of(level.reason));
        if (params.measure) out.distance.push_back(level.distance);
    }
    out.vertices_on_input = placement == Placement::half_edge;
}

void cluster_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params, PresetLevels& out,
                    Progress* progress, PresetLevelsStats* stats) {
    const auto n = static_cast<double>(preset.levels.size());
    for (std::size_t k = 0; k < preset.levels.size(); ++k) {
        const LodTarget& t = preset.levels[k];
        const Clock::time_point start = Clock::now();
        ClusterParams p;
        p.weights = preset.weights;
        if (t.kind == LodTarget::Kind::ratio) p.target_ratio = static_cast<float>(t.value);
        else if (t.kind == LodTarget::Kind::triangles) p.target_triangles = static_cast<std::size_t>(t.value);
        else target_triangles(t, mesh.triangle_count(), k, preset, params.source_path);  // throws
        const double begin = double(k) / n;
        ProgressRange simplify_progress(progress, begin, begin + 0.6 / n);
        ClusterResult r = simplify_cluster(mesh, p, &simplify_progress);
        if (r.mesh.triangle_count() == 0)
            throw_error(Error::Kind::invalid, params.source_path,
                        "level " + std::to_string(k + 1) + ": vertex clustering left no triangles");
        out.target_triangles.push_back(r.target_triangles);
        out.stops.push_back(r.reason == ClusterResult::StopReason::target_reached ||
                                    r.reason == ClusterResult::StopReason::resolution_given
                                ? LevelStop::target_reached
                                : LevelStop::closest);
        if (params.measure) {
            ProgressRange measure_progress(progress, begin + 0.6 / n, begin + 1.0 / n);
            out.distance.push_back(compare(mesh, r.mesh, measurement(params), &measure_progress));
        }
        out.levels.push_back(std::move(r.mesh));
        if (stats) stats->level_seconds.push_back(seconds_since(start));
    }
}

void lodstrips_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params, PresetLevels& out,
                      Progress* progress) {
    out.target_triangles = triangle_targets(mesh, preset, params.source_path);
    LodStripsParams p;
    p.join = preset.strips.primitive_restart ? StripJoin::restart : StripJoin::degenerate;
    p.weights = preset.weights;
    p.lock_border = preset.lock_border;
    p.coarsest_ratio = 0.f;
    p.coarsest_triangles = *std::min_element(out.target_triangles.begin(), out.target_triangles.end());
    ProgressRange build_progress(progress, 0.0, 0.9);
    LodStripsBuild build = build_lodstrips(mesh, p, &build_progress);
    out.lodstrips_file = encode_lodstrips(build.data);

    lodstrips::LodStrips runtime;
    std::string why;
    if (!runtime.assign(std::move(build.data), &why))
        throw_error(Error::Kind::invalid, params.source_path, "the LODStrips data built is inconsistent: " + why);
    for (std::size_t i = 0; i < out.target_triangles.size(); ++i) {
        check_progress(progress, 0.9 + 0.1 * double(i) / double(out.target_triangles.size()), "LODStrips levels");
        runtime.go_to_triangles(out.target_triangles[i]);
        const bool met = runtime.triangle_count() <= out.target_triangles[i];
        if (!met)
            out.notes.push_back("level " + std::to_string(i + 1) + ": LODStrips stops at " +
                                std::to_string(runtime.triangle_count()) + " triangles (asked " +
                                std::to_string(out.target_triangles[i]) + ")");
        out.stops.push_back(met ? LevelStop::target_reached : LevelStop::closest);
        Mesh level = lodstrips_mesh(runtime);
        keep_materials(mesh, level);
        // The .lodstrips file has no skin; a level's vertices are a prefix of the canonical order (removed
        // vertices come last), which names their input vertices.
        if (level.vertex_count() <= build.input_vertex.size())
            carry_influences(mesh, {build.input_vertex.begin(), build.input_vertex.begin() +
                                                                    static_cast<std::ptrdiff_t>(level.vertex_count())},
                             level);
        out.levels.push_back(std::move(level));
    }
    out.vertices_on_input = true;
}

void mcoctree_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params, PresetLevels& out,
                     Progress* progress) {
    out.target_triangles = triangle_targets(mesh, preset, params.source_path);
    McOctreeParams p;
    p.resolution = preset.mcoctree.resolution;
    ProgressRange build_progress(progress, 0.0, 0.9);
    McOctreeBuildResult built = build_mc_octree(mesh, p, &build_progress);
    for (const std::string& w : built.warnings) out.notes.push_back(w);
    McOctreeExtractor extractor(built.tree);
    for (std::size_t i = 0; i < out.target_triangles.size(); ++i) {
        check_progress(progress, 0.9 + 0.1 * double(i) / double(out.target_triangles.size()), "MC octree levels");
        const McExtraction& e = extractor.extract_triangles(out.target_triangles[i]);
        if (e.mesh.triangle_count() == 0)
            throw_error(Error::Kind::invalid, params.source_path,
                        "level " + std::to_string(i + 1) + ": the marching-cube octree has no level with at most " +
                            std::to_string(out.target_triangles[i]) + " triangles (its root has " +
                            std::to_string(mc_triangles_at(built.tree, 0)) + ")");
        out.levels.push_back(e.mesh);
        out.stops.push_back(e.mesh.triangle_count() <= out.target_triangles[i] ? LevelStop::target_reached
                                                                                : LevelStop::closest);
        if (i == 0)
            for (const McCell& c : extractor.cells(e.priority)) {
                StructureCell cell;
                for (int k = 0; k < 3; ++k) cell.min[k] = c.min[k];
                cell.size = c.size;
                cell.depth = static_cast<int>(built.tree.levels) - c.level;  // McCell counts levels from the leaves
                cell.leaf = c.level == 0;
                out.cells.push_back(cell);
            }
    }
    if (mesh.has_texcoords())
        out.notes.push_back("the marching-cube surface is rebuilt from points: texture coordinates and materials "
                            "are not carried over");
}

// The octree's level ratio for the artist's targets: their mean step (the geometric mean of each
// target over the one before, the input first), within the 30-50 % the levels are built for; the pack
// then takes the finest tree level at or below each target.
double octree_level_ratio(std::size_t input, const std::vector<std::size_t>& targets) {
    const std::size_t last = targets.empty() ? input : std::max<std::size_t>(targets.back(), 1);
    const double step = std::pow(static_cast<double>(last) / static_cast<double>(std::max<std::size_t>(input, 1)),
                                 1.0 / static_cast<double>(std::max<std::size_t>(targets.size(), 1)));
    return std::clamp(step, 0.3, 0.5);
}

void octree_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params, PresetLevels& out,
                   Progress* progress) {
    out.target_triangles = triangle_targets(mesh, preset, params.source_path);
    std::error_code ec;
    const fs::path system_temp = fs::temp_directory_path(ec);
    if (ec) throw_error(Error::Kind::io, params.source_path, "no temporary directory (TMPDIR): " + ec.message());
    TempDirectory temp(system_temp.string());
    // The octree streams a PLY from disk; other formats (already in memory here) are written as one,
    // with each face's material as its `texnumber` (the soup carries it through every level).
    std::string ply = params.source_path;
    if (!is_ply(ply)) {
        ply = temp.file("input.ply");
        WriteOptions w;
        w.ply_face_materials = true;
        write_mesh(mesh, ply, w);
    }
    OctreeBuildParams p;
    p.max_triangles = preset.octree.max_triangles_per_node;
    p.max_depth = static_cast<int>(preset.octree.max_depth);
    p.memory_bytes = std::size_t{preset.octree.memory_mb} << 20;
    p.weights = preset.weights;
    p.level_ratio = octree_level_ratio(mesh.triangle_count(), out.target_triangles);
    // The coarsest level is the artist's smallest target: the root shares nothing, so it can meet it.
    if (!out.target_triangles.empty())
        p.coarsest_triangles = *std::min_element(out.target_triangles.begin(), out.target_triangles.end());
    const std::string asset = temp.file("asset.lfoct");
    ProgressRange build_progress(progress, 0.0, 0.8);
    OctreeBuildResult built;
    try {
        built = build_octree(ply, asset, p, &build_progress);
    } catch (const Error& e) {
        throw without_temporary_names(e, params.source_path);  // the asset is a temporary too
    }
    for (const std::string& w : built.warnings) out.notes.push_back(w);
    // The out-of-core soup carries one UV set (docs/pack.md): what the levels lose is said, not left
    // for the user to find in the pack.
    if (mesh.texcoords.size() > 1)
        out.notes.push_back("the octree carries texture coordinate set 0 only: its levels drop the other " +
                            std::to_string(mesh.texcoords.size() - 1) + " set(s)");

    OctreeStore store(asset);
    out.octree_stats = store.stats();
    for (const OctreeCell& c : store.cells())
        out.cells.push_back({{c.min[0], c.min[1], c.min[2]}, c.size, c.depth, c.leaf, c.triangles});
    const std::vector<std::uint64_t>& per_level = built.stats.triangles_per_level;
    // Per target, the finest tree level at or below it (the root level when none is); a target whose
    // level a smaller target also takes gets the level above instead (closest, reported), so the pack
    // keeps one level per target: below the cells' cut lines and seams only the root shrinks further.
    const int root_level = static_cast<int>(per_level.size()) - 1;
    std::vector<int> chosen(out.target_triangles.size(), root_level);
    for (std::size_t i = 0; i < chosen.size(); ++i)
        for (int l = 1; l < root_level; ++l)
            if (per_level[static_cast<std::size_t>(l)] <= out.target_triangles[i]) {
                chosen[i] = l;
                break;
            }
    // Levels stay in order (a larger target never gets a coarser level); where the tree has too few
    // levels the finest ones repeat, and the pack drops the repeats as identical.
    for (std::size_t i = chosen.size(); i-- > 1;)
        if (chosen[i - 1] >= chosen[i]) chosen[i - 1] = std::max(1, chosen[i] - 1);
    for (std::size_t i = 0; i < out.target_triangles.size(); ++i) {
        check_progress(progress, 0.8 + 0.2 * double(i) / double(out.target_triangles.size()), "Octree levels");
        const int level = chosen[i];
        const bool met = per_level[static_cast<std::size_t>(level)] <= out.target_triangles[i];
        if (!met)
            out.notes.push_back("level " + std::to_string(i + 1) + ": the nearest octree level has " +
                                std::to_string(per_level[static_cast<std::size_t>(level)]) + " triangles (asked " +
                                std::to_string(out.target_triangles[i]) +
                                "); the cells' cut lines and seams stay at full resolution below the root: raise max "
                                "triangles per node");
        out.stops.push_back(met ? LevelStop::target_reached : LevelStop::closest);
        Mesh m = extract_mesh(store, level_cut(store, level));
        keep_materials(mesh, m);
        out.levels.push_back(std::move(m));
    }
}


PresetLevels listed_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params,
                           Progress* progress, PresetLevelsStats* stats) {
    if (preset.levels.empty()) throw_error(Error::Kind::argument, params.source_path, "the preset has no LOD levels");
    if (stats) stats->level_seconds.clear();
    PresetLevels out;
    if (preset.method != LodMethod::collapse && (!preset.importance.empty() || !preset.lock.empty() || !preset.seams.empty()))
        throw_error(Error::Kind::argument, params.source_path,
                    "importance, lock and seams need the collapse method (the preset's is " +
                        std::string(to_string(preset.method)) + ")");
    out.targets = preset.levels;
    if (preset.method == LodMethod::collapse) {
        collapse_levels(mesh, preset, params, out, progress, stats);
        return out;
    }
    if (preset.method == LodMethod::cluster) {
        cluster_levels(mesh, preset, params, out, progress, stats);
        return out;
    }
    // One structure, cut at every level; the build and the measurements split the progress.
    const Clock::time_point start = Clock::now();
    ProgressRange build_progress(progress, 0.0, params.measure ? 0.6 : 1.0);
    switch (preset.method) {
    case LodMethod::lodstrips: lodstrips_levels(mesh, preset, params, out, &build_progress); break;
    case LodMethod::mcoctree: mcoctree_levels(mesh, preset, params, out, &build_progress); break;
    case LodMethod::octree: octree_levels(mesh, preset, params, out, &build_progress); break;
    case LodMethod::collapse:
    case LodMethod::cluster: break;
    }
    const auto n = static_cast<double>(out.levels.size());
    if (params.measure)
        for (std::size_t k = 0; k < out.levels.size(); ++k) {
            ProgressRange measure_progress(progress, 0.6 + 0.4 * double(k) / n, 0.6 + 0.4 * double(k + 1) / n);
            out.distance.push_back(compare(mesh, out.levels[k], measurement(params), &measure_progress));
        }
    if (stats) stats->level_seconds.assign(out.levels.size(), seconds_since(start) / n);
    return out;
}

// "levels": "auto": the targets from choose_auto_levels, then the chain they name. A chain without the
// candidates auto dropped may measure a little worse than the candidates did, so a last level that no
// longer switches in at min_screen_pixels is left out (the rule's promise holds for the levels built).
PresetLevels auto_preset_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params,
                                Progress* progress, PresetLevelsStats* stats) {
    if (preset.method != LodMethod::collapse)
        throw_error(Error::Kind::argument, params.source_path,
                    "\"levels\": \"auto\" needs the collapse method (the preset's method is '" +
                        std::string(to_string(preset.method)) + "'): its levels are chosen by their error");
    AutoLevelsParams a;
    a.switching = preset.switching;
    a.min_screen_pixels = preset.min_screen_pixels;
    a.weights = preset.weights;
    a.lock_border = preset.lock_border;
    a.distance = params.distance;
    a.source_path = params.source_path;
    ProgressRange choose_progress(progress, 0.0, 0.5);
    const AutoLevelsResult chosen = choose_auto_levels(mesh, a, &choose_progress);
    Preset listed = preset;
    listed.auto_levels = false;
    listed.levels = chosen.targets;
    for (;;) {
        ProgressRange build_progress(progress, 0.5, 1.0);
        PresetLevels out = listed_levels(mesh, listed, params, &build_progress, stats);
        // Measured here when the caller does not measure (the studio), so every front end keeps the
        // same levels.
        const double last = params.measure ? out.distance.back().hausdorff_relative
                                           : compare(mesh, out.levels.back(), measurement(params)).hausdorff_relative;
        if (listed.levels.size() == 1 || !(last > 0) || preset.switching.pixels / last >= preset.min_screen_pixels) {
            std::string sizes;
            for (const AutoLevelCandidate& c : chosen.candidates)
                sizes += (sizes.empty() ? "" : ", ") + std::to_string(c.triangles) + (c.kept ? "" : " (dropped)");
            out.notes.push_back("automatic levels: " + std::to_string(listed.levels.size()) + " of " +
                                std::to_string(chosen.candidates.size()) + " candidates kept (triangles " + sizes +
                                ")");
            return out;
        }
        listed.levels.pop_back();
    }
}

}  // namespace

PresetLevels build_preset_levels(const Mesh& mesh, const Preset& preset, const PresetLevelsParams& params,
                                 Progress* progress, PresetLevelsStats* stats) {
    if (mesh.triangle_count() == 0) throw_error(Error::Kind::invalid, params.source_path, "the mesh has no triangles");
    if (preset.auto_levels) return auto_preset_levels(mesh, preset, params, progress, stats);
    return listed_levels(mesh, preset, params, progress, stats);
}

}  // namespace lodforge
