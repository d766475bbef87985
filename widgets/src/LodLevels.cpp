#include "lodforge/widgets/LodLevels.h"

#include "lodforge/metrics/heatmap.h"
#include "lodforge/render/image_compare.h"

#include "lodforge/error.h"
#include "lodforge/simplify/lod_chain.h"
#include "lodforge/pack/lod_methods.h"
#include "lodforge/strips/lodstrips.h"
#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/progress_range.h"
#include "lodforge/simplify/simplify_cluster.h"
#include "lodforge/widgets/MeshScene.h"

#include <QElapsedTimer>
#include <QStringList>

#include <algorithm>
#include <cmath>
#include <string>

namespace lodforge::widgets {

namespace {

// build_lod_chain reports level k's work in [k/n, (k+1)/n): the first report in each slice marks when
// that level started, which gives the time of every level (its simplification and its measurement).
class LevelClock final : public Progress {
public:
    LevelClock(Progress* parent, std::size_t levels) : parent_(parent), starts_(levels + 1, -1) { timer_.start(); }
    void report(double fraction, std::string_view stage) override {
        const auto n = static_cast<double>(starts_.size() - 1);
        const auto slice = static_cast<std::size_t>(std::clamp(std::floor(fraction * n + 1e-9), 0.0, n));
        for (std::size_t k = 0; k <= slice; ++k)
            if (starts_[k] < 0) starts_[k] = timer_.nsecsElapsed();
        if (parent_) parent_->report(fraction, stage);
    }
    bool cancelled() const override { return parent_ && parent_->cancelled(); }
    // Milliseconds of level k (0-based among the built levels).
    double levelMs(std::size_t k) {
        const qint64 end = k + 1 < starts_.size() && starts_[k + 1] >= 0 ? starts_[k + 1] : timer_.nsecsElapsed();
        return starts_[k] < 0 ? 0.0 : static_cast<double>(end - starts_[k]) / 1e6;
    }

private:
    Progress* parent_;
    QElapsedTimer timer_;
    std::vector<qint64> starts_;
};

QString reasonText(SimplifyResult::StopReason reason) {
    switch (reason) {
    case SimplifyResult::StopReason::target_reached: return QStringLiteral("target reached");
    case SimplifyResult::StopReason::error_limit: return QStringLiteral("error limit");
    case SimplifyResult::StopReason::topology_limit: return QStringLiteral("topology limit");
    }
    return {};
}

QString reasonText(ClusterResult::StopReason reason) {
    switch (reason) {
    case ClusterResult::StopReason::target_reached: return QStringLiteral("target reached");
    case ClusterResult::StopReason::closest: return QStringLiteral("closest count found");
    case ClusterResult::StopReason::grid_limit: return QStringLiteral("grid limit");
    case ClusterResult::StopReason::resolution_given: return QStringLiteral("resolution given");
    }
    return {};
}

LevelData makeLevel(int index, Mesh&& mesh, const DistanceResult* distance,
                    const std::vector<std::shared_ptr<const Image>>& images) {
    LevelData level;
    level.index = index;
    level.triangles = mesh.triangle_count();
    level.vertices = mesh.vertex_count();
    if (distance) {
        level.error = distance->hausdorff;
        level.errorRelative = distance->hausdorff_relative;
    }
    auto shared = std::make_shared<Mesh>(std::move(mesh));
    level.scene = buildMeshScene(*shared, images);
    level.mesh = std::move(shared);
    return level;
}

std::vector<LevelData> buildCollapseLevels(const LevelData& original, const Preset& preset,
                                           const std::vector<std::shared_ptr<const Image>>& images,
                                           Progress* progress) {
    LodChainParams params;
    for (const LodTarget& t : preset.levels) {
        LodLevelTarget target;
        switch (t.kind) {
        case LodTarget::Kind::ratio: target.ratio = static_cast<float>(t.value); break;
        case LodTarget::Kind::triangles: target.triangles = static_cast<std::size_t>(std::llround(t.value)); break;
        case LodTarget::Kind::error: target.max_error = static_cast<float>(t.value); break;
        }
        params.levels.push_back(target);
    }
    params.simplify.weights = preset.weights;
    params.simplify.lock_border = preset.lock_border;
    params.measure = true;

    ProgressRange chainProgress(progress, 0.0, 0.8);
    LevelClock clock(&chainProgress, params.levels.size());
    LodChainResult chain = build_lod_chain(*original.mesh, params, &clock);

    std::vector<LevelData> levels{original};
    for (std::size_t k = 1; k < chain.levels.size(); ++k) {
        check_progress(progress, 0.8 + 0.2 * double(k - 1) / double(chain.levels.size() - 1), "Preparing the views");
        LodLevel& l = chain.levels[k];
        LevelData level = makeLevel(int(k), std::move(l.mesh), l.measured ? &l.distance : nullptr, images);
        level.buildMs = clock.levelMs(k - 1);
        level.stopReason = reasonText(l.reason);
        level.verticesOnOriginal = true;
        levels.push_back(std::move(level));
    }
    return levels;
}

std::vector<LevelData> buildClusterLevels(const LevelData& original, const Preset& preset,
                                          const std::vector<std::shared_ptr<const Image>>& images,
                                          Progress* progress) {
    std::vector<LevelData> levels{original};
    const auto n = static_cast<double>(preset.levels.size());
    for (std::size_t k = 0; k < preset.levels.size(); ++k) {
        const LodTarget& t = preset.levels[k];
        ClusterParams params;
        switch (t.kind) {
        case LodTarget::Kind::ratio: params.target_ratio = static_cast<float>(t.value); break;
        case LodTarget::Kind::triangles:
            params.target_triangles = static_cast<std::size_t>(std::llround(t.value));
            break;
        case LodTarget::Kind::error:
            throw Error(Error::Kind::argument,
                        "level " + std::to_string(k + 1) +
                            ": vertex clustering takes ratio or triangle targets, not error targets");
        }
        params.weights = preset.weights;
        QElapsedTimer timer;
        timer.start();
        const double begin = double(k) / n;
        ProgressRange simplifyProgress(progress, begin, begin + 0.6 / n);
        ClusterResult r = simplify_cluster(*original.mesh, params, &simplifyProgress);
        if (r.mesh.triangle_count() == 0)
            throw Error(Error::Kind::invalid, "level " + std::to_string(k + 1) + ": vertex clustering left no triangles");
        ProgressRange measureProgress(progress, begin + 0.6 / n, begin + 0.9 / n);
        DistanceParams distance;
        distance.vertex_errors = false;
        const DistanceResult d = compare(*original.mesh, r.mesh, distance, &measureProgress);
        const double ms = static_cast<double>(timer.nsecsElapsed()) / 1e6;
        check_progress(progress, begin + 0.9 / n, "Preparing the views");
        LevelData level = makeLevel(int(k + 1), std::move(r.mesh), &d, images);
        level.buildMs = ms;
        level.stopReason = reasonText(r.reason);
        level.verticesOnOriginal = false;
        levels.push_back(std::move(level));
    }
    return levels;
}

// LODStrips, MC octree and out-of-core octree: the core builds the levels (as the pack does), the
// studio measures them and prepares the views.
std::vector<LevelData> buildStructureLevels(const LevelData& original, const Preset& preset,
                                            const std::vector<std::shared_ptr<const Image>>& images,
                                            Progress* progress) {
    QElapsedTimer timer;
    timer.start();
    ProgressRange buildProgress(progress, 0.0, 0.6);
    MethodLevels built = build_method_levels(*original.mesh, preset, std::string(), &buildProgress);
    const double buildMs = static_cast<double>(timer.nsecsElapsed()) / 1e6 / double(built.levels.size());
    std::vector<LevelData> levels{original};
    levels.front().cells = buildCellsScene(built.cells);
    if (!built.lodstrips_file.empty()) {
        auto continuous = std::make_shared<ContinuousLodData>();
        continuous->lodstripsFile = std::move(built.lodstrips_file);
        continuous->images = images;
        lodstrips::LodStrips runtime;
        if (runtime.load_memory(continuous->lodstripsFile.data(), continuous->lodstripsFile.size())) {
            runtime.go_to_level(0);
            continuous->fullScene = buildMeshScene(lodstrips_mesh(runtime), images);
        }
        levels.front().continuous = std::move(continuous);
    }
    if (preset.method == LodMethod::octree) {
        levels.front().structureSummary = octreeSummary(built.octree_stats);
    } else if (!built.cells.empty()) {
        levels.front().structureSummary =
            QStringLiteral("Marching-cube octree: %L1 cells in the finest level's cut").arg(built.cells.size());
    }
    const auto n = static_cast<double>(built.levels.size());
    for (std::size_t k = 0; k < built.levels.size(); ++k) {
        ProgressRange measureProgress(progress, 0.6 + 0.4 * double(k) / n, 0.6 + 0.4 * double(k + 1) / n);
        DistanceParams distance;
        distance.vertex_errors = false;
        const DistanceResult d = compare(*original.mesh, built.levels[k], distance, &measureProgress);
        LevelData level = makeLevel(int(k + 1), std::move(built.levels[k]), &d, images);
        level.buildMs = buildMs;
        level.stopReason = level.triangles <= built.target_triangles[k] ? QStringLiteral("target reached")
                                                                        : QStringLiteral("closest level");
        // LODStrips levels are vertex subsets of the original (half-edge collapses); the others are new
        // surfaces that carry their own error field.
        level.verticesOnOriginal = preset.method == LodMethod::lodstrips;
        level.cells = levels.front().cells;
        level.structureSummary = levels.front().structureSummary;
        level.continuous = levels.front().continuous;
        levels.push_back(std::move(level));
    }
    return levels;
}

}  // namespace

QString octreeSummary(const OctreeStats& stats) {
    if (stats.nodes == 0) return {};
    QStringList perLevel;
    for (std::uint64_t t : stats.triangles_per_level) perLevel << QStringLiteral("%L1").arg(t);
    return QStringLiteral("Octree: %L1 nodes, %L2 leaves, depth %3 reached; triangles per level %4")
        .arg(stats.nodes)
        .arg(stats.leaves)
        .arg(stats.depth_reached)
        .arg(perLevel.join(QStringLiteral(" · ")));
}

bool methodHasEngine(LodMethod) { return true; }

QString methodDisplayName(LodMethod method) {
    switch (method) {
    case LodMethod::collapse: return QStringLiteral("Edge collapse");
    case LodMethod::cluster: return QStringLiteral("Vertex clustering");
    case LodMethod::octree: return QStringLiteral("Out-of-core octree");
    case LodMethod::lodstrips: return QStringLiteral("LODStrips");
    case LodMethod::mcoctree: return QStringLiteral("Marching-cube octree");
    }
    return {};
}

std::vector<LevelData> buildLodLevels(const LevelData& original, const Preset& preset,
                                      const std::vector<std::shared_ptr<const Image>>& images, Progress* progress) {
    if (!original.mesh || original.mesh->triangle_count() == 0)
        throw Error(Error::Kind::invalid, "the mesh has no triangles to simplify");
    if (preset.levels.empty()) throw Error(Error::Kind::argument, "the preset has no LOD levels");
    switch (preset.method) {
    case LodMethod::collapse: return buildCollapseLevels(original, preset, images, progress);
    case LodMethod::cluster: return buildClusterLevels(original, preset, images, progress);
    case LodMethod::octree:
    case LodMethod::lodstrips:
    case LodMethod::mcoctree: break;
    }
    return buildStructureLevels(original, preset, images, progress);
}

std::vector<ImageError> computeImageErrors(const std::vector<LevelData>& levels,
                                           const std::vector<std::shared_ptr<const Image>>& images, Progress* progress) {
    std::vector<ImageError> out;
    if (levels.size() < 2) return out;
    const Mesh& original = *levels.front().mesh;
    for (std::size_t k = 1; k < levels.size(); ++k) {
        check_progress(progress, double(k - 1) / double(levels.size() - 1), "Image error");
        // The levels keep the original's materials: its decoded textures serve them all.
        out.push_back(render::compareImages(original, images, *levels[k].mesh, images, ImageErrorParams{}));
    }
    check_progress(progress, 1.0, "Image error");
    return out;
}

HeatmapData computeHeatmaps(const std::vector<LevelData>& levels, Progress* progress) {
    HeatmapData out;
    if (levels.empty()) return out;
    const Mesh& original = *levels.front().mesh;
    const auto n = static_cast<double>(levels.size());
    for (std::size_t k = 0; k < levels.size(); ++k) {
        check_progress(progress, double(k) / n, "Heat map");
        const LevelData& level = levels[k];
        DistanceParams params;
        params.vertex_errors = true;
        ProgressRange sub(progress, double(k) / n, double(k + 1) / n);
        std::vector<float> values;
        const Mesh* surface = nullptr;
        if (k == 0) {
            surface = &original;
            values.assign(original.vertex_count(), 0.f);
        } else if (level.verticesOnOriginal) {
            // The level's vertices lie on the original: measure the original's vertices against the level.
            surface = &original;
            values = compare(*level.mesh, original, params, &sub).vertex_errors;
        } else {
            surface = level.mesh.get();
            values = compare(original, *level.mesh, params, &sub).vertex_errors;
        }
        const float levelMax = heatmap_range(*surface, values, 1.f);
        out.levelMax.push_back(levelMax);
        out.maxError = std::max(out.maxError, double(levelMax));
        out.autoRange = std::max(out.autoRange, double(heatmap_range(*surface, values)));
        out.scenes.push_back(buildScalarScene(*surface, values));
    }
    check_progress(progress, 1.0, "Heat map");
    return out;
}

}  // namespace lodforge::widgets
