// The levels of detail the studio shows: built from a Preset on a worker thread (with the engines of
// lodforge_core), each with its measured error, build time and drawable scene; and their error heat maps.
#pragma once

#include "lodforge/io/image_decode.h"
#include "lodforge/pack/preset_levels.h"
#include "lodforge/mesh.h"
#include "lodforge/metrics/image_error.h"
#include "lodforge/pack/preset.h"
#include "lodforge/progress.h"

#include <QString>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace lodforge::widgets {

class MeshScene;

// LODStrips levels: what the continuous LOD slider needs to run the runtime itself (docs/studio.md).
struct ContinuousLodData {
    std::vector<std::uint8_t> lodstripsFile;                     // PresetLevels::lodstrips_file
    std::vector<std::shared_ptr<const lodforge::Image>> images;  // per material, as for the levels
    // The full-detail strips (level 0, every vertex of the runtime), made on the chain's worker: on the
    // dragon it took 0.36 s on the GUI thread at the slider's first move. The continuous view replaces
    // its triangles in place (LevelViews::showContinuous), so one LevelViews uses it at a time.
    std::shared_ptr<const MeshScene> fullScene;
};

// How a level's error was measured: not yet (the levels show before their measures), with the quick
// sample budget (measureLevels), or at full precision (compare()'s defaults, as `lodforge compare`).
enum class Measured { no, sampled, full };

struct LevelData {
    int index = 0;  // 0 = the original
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    double error = 0;           // measured symmetric Hausdorff distance to the original, model units
    double errorRelative = 0;   // the same relative to the original's bounding-box diagonal
    Measured measured = Measured::no;  // error and errorRelative are 0 until measured
    double buildMs = 0;         // time to build this level (0 for the original)
    QString stopReason;         // why the engine stopped ("target reached", ...), empty for the original
    std::size_t targetTriangles = 0;  // the preset's triangle target (ratios resolved); 0 for error targets
    // The target was a triangle count and the level is more than 10 % away from it (a structure's
    // nearest level, a topology limit): labels and the report then say so with the stop reason.
    bool missedTarget = false;
    // An earlier level (1..index-1) with the very same mesh, or -1: labels and the report flag it, as
    // the level adds nothing to the chain.
    int sameAs = -1;
    // Every vertex is a vertex of the original at its place (half-edge collapse): the distance to the
    // original is zero at the level's own vertices, so its heat map needs the region field.
    bool verticesOnOriginal = true;
    std::shared_ptr<const lodforge::Mesh> mesh;
    std::shared_ptr<const MeshScene> scene;
    // Levels cut from a structure (octree, MC octree; also their level 0): the structure's cells as an
    // overlay scene (buildCellsScene), and a summary of it for the report; null / empty otherwise.
    std::shared_ptr<const MeshScene> cells;
    QString structureSummary;
    // LODStrips levels (every level shares it): the runtime's file for the continuous slider; null otherwise.
    std::shared_ptr<const ContinuousLodData> continuous;
};

// "Octree: 85 nodes, 64 leaves, depth 3 reached; triangles per level 5,856 · 2,900 · 1,210"; empty when
// `stats` describes no tree.
QString octreeSummary(const lodforge::OctreeStats& stats);

QString methodDisplayName(lodforge::LodMethod method);

// Levels 0..N: `original` first (as given), then one per preset level, built with the preset's method,
// weights and border locking, not measured yet (measureLevels). `images`: the decoded base
// colour textures of the materials (LoadedModel::images), so the levels show their texture.
// The levels come from build_preset_levels (the pack's function). Throws lodforge::Error: argument for
// targets the method cannot take, invalid for a mesh without triangles, cancelled when `progress` asks
// to stop.
std::vector<LevelData> buildLodLevels(const LevelData& original, const lodforge::Preset& preset,
                                      const std::vector<std::shared_ptr<const lodforge::Image>>& images,
                                      lodforge::Progress* progress = nullptr);

struct LevelMeasure {
    int level = 0;
    double error = 0, errorRelative = 0;
    Measured measured = Measured::no;
};

// Measures levels 1..N against levels[0], one after the other, each direction on its own thread:
// `full` at full precision (compare()'s defaults), else quickly (a sample budget per surface, no vertex
// pass, the original's tree built once: docs/studio.md, "Measuring"). A level identical to an earlier one (sameAs) takes that one's measure. `measured` runs
// on this thread after each level. Throws Error(cancelled) when `progress` asks to stop.
void measureLevels(const std::vector<LevelData>& levels, bool full,
                   const std::function<void(const LevelMeasure&)>& measured, lodforge::Progress* progress = nullptr);

struct HeatmapData {
    // Per level: the level's surface with, at each vertex, the largest distance to the original
    // measured around it (DistanceResult::region_errors, model units). Level 0's field is zero.
    std::vector<std::shared_ptr<const MeshScene>> scenes;
    // Values at vertices no triangle uses are left out of both (they colour nothing).
    std::vector<float> levelMax;  // largest value per level
    double maxError = 0;          // largest value over all levels
    // The automatic colour range: the largest over the levels of each level's heatmap_range (a high
    // percentile), so one stray vertex does not turn every level one flat colour.
    double autoRange = 0;
};

// The image-space error of every level after the first against the original (levels[0]), rendered
// offscreen with the default ImageErrorParams (docs/image-compare.md); `images` as for buildLodLevels.
// Safe on a worker: each call renders in its own offscreen window. Throws lodforge::Error(cancelled)
// between levels when `progress` asks to stop, Error(io) when no X display can be had.
std::vector<lodforge::ImageError> computeImageErrors(const std::vector<LevelData>& levels,
                                                     const std::vector<std::shared_ptr<const lodforge::Image>>& images,
                                                     lodforge::Progress* progress = nullptr);

// Throws lodforge::Error(cancelled) when `progress` asks to stop.
HeatmapData computeHeatmaps(const std::vector<LevelData>& levels, lodforge::Progress* progress = nullptr);

}  // namespace lodforge::widgets
