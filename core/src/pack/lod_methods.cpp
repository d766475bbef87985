// Preset levels from LODStrips (docs/lodstrips.md), the marching-cube octree (docs/mcoctree.md) and the
// out-of-core octree (docs/octree.md). Each method builds its own multiresolution structure once and
// the preset's levels are cuts of it, chosen by triangle count: these structures store their levels by
// triangle count (LODStrips: one per collapse, MC octree: one per priority, octree: one per tree level),
// not by an error bound the preset could name.
#include "lodforge/pack/lod_methods.h"

#include "lodforge/error.h"
#include "lodforge/io/atomic_file.h"
#include "lodforge/strips/lodstrips.h"
#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/octree/octree_build.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/progress_range.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <system_error>
#include <unistd.h>

namespace lodforge {

namespace fs = std::filesystem;

namespace {

std::vector<std::size_t> targets_of(const Mesh& mesh, const Preset& preset, const char* method) {
    if (preset.levels.empty()) throw Error(Error::Kind::argument, "the preset has no LOD levels");
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < preset.levels.size(); ++i)
        out.push_back(method_target_triangles(preset.levels[i], mesh.triangle_count(), i, method));
    return out;
}

// Levels whose structure cannot carry the input's materials per face (the MC surface is rebuilt from
// points) keep none; the others keep the input's materials and texture search directory.
void keep_materials(const Mesh& input, Mesh& level) {
    level.materials = input.materials;
    level.source_dir = input.source_dir;
}

// A temporary directory beside nothing the user owns, removed with the object.
class TempDir {
public:
    TempDir() {
        static std::atomic<unsigned> counter{0};
        std::error_code ec;
        const fs::path base = fs::temp_directory_path(ec);
        if (ec) throw Error(Error::Kind::io, "no temporary directory: " + ec.message());
        remove_stale_temporaries(base.string());
        path_ = base / ("lodforge-method-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        if (!fs::create_directories(path_, ec) || ec)
            throw_error(Error::Kind::io, path_.string(), "cannot create a temporary directory");
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    fs::path file(const std::string& name) const { return path_ / name; }

private:
    fs::path path_;
};

bool is_ply(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".ply";
}

}  // namespace

std::size_t method_target_triangles(const LodTarget& target, std::size_t input_triangles, std::size_t level,
                                    const char* method) {
    const std::string where = "levels[" + std::to_string(level) + "]: ";
    double n = 0;
    switch (target.kind) {
    case LodTarget::Kind::ratio: n = std::floor(target.value * double(input_triangles)); break;
    case LodTarget::Kind::triangles: n = std::floor(target.value); break;
    case LodTarget::Kind::error:
        throw Error(Error::Kind::argument, where + "the " + std::string(method) +
                                               " method takes ratio or triangle targets, not error targets");
    }
    if (!(n >= 1)) throw Error(Error::Kind::argument, where + "the target asks for no triangles");
    return static_cast<std::size_t>(n);
}

MethodLevels build_lodstrips_levels(const Mesh& mesh, const Preset& preset, const std::string& source_path,
                                    Progress* progress) {
    MethodLevels out;
    out.target_triangles = targets_of(mesh, preset, "lodstrips");
    LodStripsParams params;
    params.join = preset.strips.primitive_restart ? StripJoin::restart : StripJoin::degenerate;
    params.weights = preset.weights;
    params.lock_border = preset.lock_border;
    params.coarsest_ratio = 0.f;
    params.coarsest_triangles = *std::min_element(out.target_triangles.begin(), out.target_triangles.end());
    ProgressRange build_progress(progress, 0.0, 0.9);
    LodStripsBuild build = build_lodstrips(mesh, params, &build_progress);
    out.lodstrips_file = encode_lodstrips(build.data);

    lodstrips::LodStrips runtime;
    std::string why;
    if (!runtime.assign(std::move(build.data), &why))
        throw_error(Error::Kind::invalid, source_path, "the LODStrips data built is inconsistent: " + why);
    for (std::size_t i = 0; i < out.target_triangles.size(); ++i) {
        check_progress(progress, 0.9 + 0.1 * double(i) / double(out.target_triangles.size()), "LODStrips levels");
        runtime.go_to_triangles(out.target_triangles[i]);
        if (runtime.triangle_count() > out.target_triangles[i])
            out.notes.push_back("level " + std::to_string(i + 1) + ": LODStrips stops at " +
                                std::to_string(runtime.triangle_count()) + " triangles (asked " +
                                std::to_string(out.target_triangles[i]) + ")");
        Mesh level = lodstrips_mesh(runtime);
        keep_materials(mesh, level);
        out.levels.push_back(std::move(level));
    }
    return out;
}

MethodLevels build_mcoctree_levels(const Mesh& mesh, const Preset& preset, const std::string& source_path,
                                   Progress* progress) {
    MethodLevels out;
    out.target_triangles = targets_of(mesh, preset, "mcoctree");
    McOctreeParams params;
    params.resolution = preset.mcoctree.resolution;
    ProgressRange build_progress(progress, 0.0, 0.9);
    McOctreeBuildResult built = build_mc_octree(mesh, params, &build_progress);
    for (const std::string& w : built.warnings) out.notes.push_back(w);
    McOctreeExtractor extractor(built.tree);
    for (std::size_t i = 0; i < out.target_triangles.size(); ++i) {
        check_progress(progress, 0.9 + 0.1 * double(i) / double(out.target_triangles.size()), "MC octree levels");
        const McExtraction& e = extractor.extract_triangles(out.target_triangles[i]);
        if (e.mesh.triangle_count() == 0)
            throw_error(Error::Kind::invalid, source_path,
                        "level " + std::to_string(i + 1) + ": the marching-cube octree has no level with at most " +
                            std::to_string(out.target_triangles[i]) + " triangles (its root has " +
                            std::to_string(mc_triangles_at(built.tree, 0)) + ")");
        out.levels.push_back(e.mesh);
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
    return out;
}

MethodLevels build_octree_levels(const Mesh& mesh, const Preset& preset, const std::string& source_path,
                                 Progress* progress) {
    MethodLevels out;
    out.target_triangles = targets_of(mesh, preset, "octree");
    TempDir temp;
    // The octree streams a PLY from disk; other formats (already in memory here) are written as one.
    std::string ply = source_path;
    if (!is_ply(source_path)) {
        ply = temp.file("input.ply").string();
        write_mesh(mesh, ply);
    }
    OctreeBuildParams params;
    params.max_triangles = preset.octree.max_triangles_per_node;
    params.max_depth = static_cast<int>(preset.octree.max_depth);
    params.memory_bytes = std::size_t{preset.octree.memory_mb} << 20;
    params.weights = preset.weights;
    const std::string asset = temp.file("asset.lfoct").string();
    ProgressRange build_progress(progress, 0.0, 0.8);
    OctreeBuildResult built = build_octree(ply, asset, params, &build_progress);
    for (const std::string& w : built.warnings) out.notes.push_back(w);

    OctreeStore store(asset);
    out.octree_stats = store.stats();
    for (const OctreeCell& c : store.cells())
        out.cells.push_back({{c.min[0], c.min[1], c.min[2]}, c.size, c.depth, c.leaf, c.triangles});
    const std::vector<std::uint64_t>& per_level = built.stats.triangles_per_level;
    for (std::size_t i = 0; i < out.target_triangles.size(); ++i) {
        check_progress(progress, 0.8 + 0.2 * double(i) / double(out.target_triangles.size()), "Octree levels");
        // The finest tree level at or below the target; the root level when none is.
        int level = static_cast<int>(per_level.size()) - 1;
        for (int l = 1; l < static_cast<int>(per_level.size()); ++l)
            if (per_level[static_cast<std::size_t>(l)] <= out.target_triangles[i]) {
                level = l;
                break;
            }
        if (per_level[static_cast<std::size_t>(level)] > out.target_triangles[i])
            out.notes.push_back("level " + std::to_string(i + 1) + ": the octree's coarsest level has " +
                                std::to_string(per_level[static_cast<std::size_t>(level)]) + " triangles (asked " +
                                std::to_string(out.target_triangles[i]) + "); raise max triangles per node");
        Mesh m = extract_mesh(store, level_cut(store, level));
        keep_materials(mesh, m);
        out.levels.push_back(std::move(m));
    }
    return out;
}

MethodLevels build_method_levels(const Mesh& mesh, const Preset& preset, const std::string& source_path,
                                 Progress* progress) {
    switch (preset.method) {
    case LodMethod::lodstrips: return build_lodstrips_levels(mesh, preset, source_path, progress);
    case LodMethod::mcoctree: return build_mcoctree_levels(mesh, preset, source_path, progress);
    case LodMethod::octree: return build_octree_levels(mesh, preset, source_path, progress);
    case LodMethod::collapse:
    case LodMethod::cluster: break;
    }
    throw Error(Error::Kind::argument, "build_method_levels: '" + std::string(to_string(preset.method)) +
                                           "' levels are built by the LOD chain or the clustering");
}

}  // namespace lodforge
