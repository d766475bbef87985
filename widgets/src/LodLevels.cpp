#include "lodforge/widgets/LodLevels.h"

#include "lodforge/metrics/heatmap.h"
#include "lodforge/render/image_compare.h"

#include "lodforge/error.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/pack/lod_pack.h"
#include "lodforge/pack/preset_levels.h"
#include "lodforge/progress_range.h"
#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/strips/lodstrips.h"
#include "lodforge/widgets/MeshScene.h"

#include <QStringList>

#include <algorithm>
#include <cmath>
#include <string>

namespace lodforge::widgets {

namespace {

QString stopText(LevelStop stop) {
    switch (stop) {
    case LevelStop::target_reached: return QStringLiteral("target reached");
    case LevelStop::error_limit: return QStringLiteral("error limit");
    case LevelStop::topology_limit: return QStringLiteral("topology limit");
    case LevelStop::closest: return QStringLiteral("closest level");
    }
    return {};
}

LevelData makeLevel(int index, Mesh&& mesh, const std::vector<std::shared_ptr<const Image>>& images) {
    LevelData level;
    level.index = index;
    level.triangles = mesh.triangle_count();
    level.vertices = mesh.vertex_count();
    auto shared = std::make_shared<Mesh>(std::move(mesh));
    level.scene = buildMeshScene(*shared, images);
    level.mesh = std::move(shared);
    return level;
}

// A part of `parent`'s range under a stage name of its own: the bar says which level is measured
// rather than compare()'s "compare".
class NamedRange final : public Progress {
public:
    NamedRange(Progress* parent, double begin, double end, std::string stage)
        : range_(parent, begin, end), stage_(std::move(stage)) {}
    void report(double fraction, std::string_view) override { range_.report(fraction, stage_); }
    bool cancelled() const override { return range_.cancelled(); }

private:
    ProgressRange range_;
    std::string stage_;
};

// Area-weighted samples per surface of the quick measure, for a level of the 871K-triangle dragon under
// 1 s on two cores: with 200,000 an octree level took 1.2 s of CPU over both threads (2.2 s for the
// 5K-triangle level, whose samples lie far from the original and prune the tree less), and 2.2-3.1 s
// with the original's tree built per level (docs/studio.md, "Measuring").
constexpr std::size_t quickMeasureSamples = 150000;

// Beyond this relative distance a triangle target counts as missed: clustering and structure cuts land
// near, not on, their targets, and "near" should not be reported as a miss.
constexpr double missTolerance = 0.1;

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

// The core builds the levels (as the pack does: build_preset_levels); the studio prepares the views.
std::vector<LevelData> buildLodLevels(const LevelData& original, const Preset& preset,
                                      const std::vector<std::shared_ptr<const Image>>& images, Progress* progress) {
    if (!original.mesh || original.mesh->triangle_count() == 0)
        throw Error(Error::Kind::invalid, "the mesh has no triangles to simplify");
    ProgressRange buildProgress(progress, 0.0, 0.9);
    PresetLevelsStats stats;
    // Measuring took most of a chain's time (80 of the dragon's 85 s): the levels show first and
    // measureLevels fills their errors in afterwards.
    PresetLevelsParams params;
    params.measure = false;
    PresetLevels built = build_preset_levels(*original.mesh, preset, params, &buildProgress, &stats);
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
    if (built.octree_stats.nodes > 0) {
        levels.front().structureSummary = octreeSummary(built.octree_stats);
    } else if (!built.cells.empty()) {
        levels.front().structureSummary =
            QStringLiteral("Marching-cube octree: %L1 cells in the finest level's cut").arg(built.cells.size());
    }
    const auto n = static_cast<double>(built.levels.size());
    for (std::size_t k = 0; k < built.levels.size(); ++k) {
        check_progress(progress, 0.9 + 0.1 * double(k) / n, "Preparing the views");
        LevelData level = makeLevel(int(k + 1), std::move(built.levels[k]), images);
        level.buildMs = stats.level_seconds[k] * 1e3;
        level.stopReason = stopText(built.stops[k]);
        level.targetTriangles = k < built.target_triangles.size() ? built.target_triangles[k] : 0;
        level.missedTarget = level.targetTriangles > 0 &&
                             std::abs(double(level.triangles) - double(level.targetTriangles)) >
                                 missTolerance * double(level.targetTriangles);
        // The octree reports a cut at or under its budget as "target reached", however far under:
        // far from the target it is the structure's closest level, and the label must not say otherwise.
        if (level.missedTarget && built.stops[k] == LevelStop::target_reached) level.stopReason = stopText(LevelStop::closest);
        for (std::size_t j = 1; j < levels.size() && level.sameAs < 0; ++j) {
            if (same_surface(*levels[j].mesh, *level.mesh)) level.sameAs = int(j);
        }
        level.verticesOnOriginal = built.vertices_on_input;
        level.cells = levels.front().cells;
        level.structureSummary = levels.front().structureSummary;
        level.continuous = levels.front().continuous;
        levels.push_back(std::move(level));
    }
    return levels;
}

void measureLevels(const std::vector<LevelData>& levels, bool full, const std::function<void(const LevelMeasure&)>& measured,
                   Progress* progress) {
    if (levels.size() < 2) return;
    const Mesh& original = *levels.front().mesh;
    DistanceParams params;
    params.vertex_errors = false;
    params.threads = 2;
    if (!full) {
        params.samples = quickMeasureSamples;
        params.include_vertices = false;
    }
    // The original's tree once for all levels (about a second of the dragon's measure each time).
    check_progress(progress, 0.0, "Measuring");
    const DistanceReference reference(original);
    std::vector<LevelMeasure> done(levels.size());
    const auto n = static_cast<double>(levels.size() - 1);
    for (std::size_t k = 1; k < levels.size(); ++k) {
        const std::string stage = "Measuring LOD " + std::to_string(k) + " of " + std::to_string(levels.size() - 1);
        check_progress(progress, double(k - 1) / n, stage);
        LevelMeasure m;
        const int same = levels[k].sameAs;
        if (same > 0 && std::size_t(same) < k) {
            m = done[std::size_t(same)];
        } else {
            NamedRange sub(progress, double(k - 1) / n, double(k) / n, stage);
            const DistanceResult d = compare(reference, *levels[k].mesh, params, &sub);
            m.error = d.hausdorff;
            m.errorRelative = d.hausdorff_relative;
            m.measured = full ? Measured::full : Measured::sampled;
        }
        m.level = int(k);
        done[k] = m;
        measured(m);
    }
    check_progress(progress, 1.0, "Measuring");
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
        ProgressRange sub(progress, double(k) / n, double(k + 1) / n);
        std::vector<float> values;
        const Mesh* surface = level.mesh.get();
        if (k == 0) {
            values.assign(original.vertex_count(), 0.f);
        } else {
            // On the level's own surface, so its outline is what is seen: the region field collects the
            // samples of both directions around each vertex, so a half-edge level (whose vertices lie on
            // the original, all at distance zero) still shows where its surface departs.
            DistanceParams params;
            params.vertex_errors = false;
            params.region_errors = true;
            params.threads = 2;
            values = compare(original, *level.mesh, params, &sub).region_errors;
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
