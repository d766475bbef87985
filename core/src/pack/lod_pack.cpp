// LOD pack export: levels from a preset, measured, written as a .glb (MSFT_lod), per-level PLY/OBJ and
// a pack.json manifest (docs/pack.md).
//
// The levels follow the method's own papers (lod_chain.cpp: Garland & Heckbert 1998 / Hoppe 1999
// generalized quadrics; simplify_cluster.cpp: Rossignac & Borrel 1993, Lindstrom 2000); each is
// measured against the input with the Metro distance (Cignoni et al. 1998). The screen-coverage hint
// projects the measured error onto a reference screen (docs/pack.md, "Screen coverage"), as the
// MSFT_lod extension's MSFT_screencoverage extras expect one switching threshold per level.
//
// Atomicity: everything is written into a staging directory beside output_dir (same file system) and
// renamed into place at the end; the staging directory, and any parent directory this call created,
// are removed on failure or cancellation.
#include "lodforge/pack/lod_pack.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"
#include "lodforge/io/file_hash.h"
#include "lodforge/io/gltf_writer.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/staged_directory.h"
#include "lodforge/metrics/distance_json.h"
#include "lodforge/pack/preset_levels.h"
#include "lodforge/pack/switch_points.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <system_error>

namespace lodforge {
namespace fs = std::filesystem;

namespace {

using nlohmann::ordered_json;

// The levels of a pack: the preset's levels (preset_levels.h) with the input as level 0.
struct BuiltLevels {
    PresetLevels built;
    std::vector<const Mesh*> meshes;        // every level kept, level 0 = the input
    std::vector<DistanceResult> distance;   // per level kept (level 0: zero)
    std::vector<std::size_t> dropped;       // preset levels (1-based) equal to the level before them
    std::optional<Mesh> input;              // level 0 when it differs from the input (skin renormalised)
    bool shared_buffer = false;             // false: the GLB takes the levels one by one (optimal placement,
                                            // methods other than collapse, or skinned levels whose
                                            // influence counts differ cannot share vertices)
};

// Every level of a skinned input bound to its skeleton (docs/skinning.md): level 0 keeps all its
// influences, level k (preset level kept_ranges[k]) at most the preset's count, each renormalised to
// sum 1. A method that does not keep input vertices (cluster, octree, mcoctree) has no influences to
// give: the pack is then static, in the bind pose, with a note.
void bind_skins(const Mesh& mesh, const Preset& preset, const std::vector<std::size_t>& kept_ranges,
                BuiltLevels& out) {
    const SkinOptions& options = preset.skin;
    if (!mesh.has_skin()) return;
    Mesh& input = out.input.emplace(mesh);
    out.meshes[0] = &input;
    const bool carried = std::all_of(out.meshes.begin(), out.meshes.end(), [](const Mesh* m) { return m->has_skin(); });
    if (!carried) {
        out.built.notes.push_back("the " + std::string(to_string(preset.method)) +
                                  " method's levels carry no skin: the pack is static, in the bind pose");
        for (std::size_t k = 1; k < out.meshes.size(); ++k) {
            Mesh& level = out.built.levels[kept_ranges[k] - 1];
            level.joints.clear();
            level.weights.clear();
            level.skeleton.reset();
        }
        input.joints.clear();
        input.weights.clear();
        input.skeleton.reset();
        return;
    }
    const std::size_t most = max_influence_count(mesh);
    limit_influences(input, most);
    bool all_kept = true;
    for (std::size_t k = 1; k < out.meshes.size(); ++k) {
        const std::size_t preset_level = kept_ranges[k] - 1;
        const std::size_t limit = options.max_influences.empty()
                                      ? most
                                      : options.max_influences[std::min(preset_level, options.max_influences.size() - 1)];
        all_kept = all_kept && limit >= most;
        limit_influences(out.built.levels[preset_level], std::min(limit, std::max<std::size_t>(most, 1)));
    }
    out.shared_buffer = out.shared_buffer && all_kept;
    if (out.shared_buffer) limit_influences(out.built.chain->shared.vertices, most);
}

BuiltLevels make_levels(const Mesh& mesh, const PackParams& params, Progress* progress) {
    PresetLevelsParams p;
    p.source_path = params.source_path;
    p.distance = params.distance;
    BuiltLevels out;
    out.built = build_preset_levels(mesh, params.preset, p, progress);
    out.meshes.push_back(&mesh);
    out.distance.emplace_back();
    // A level equal to the one before it (a method that cannot go lower repeats its coarsest level)
    // is left out: it would add an empty switch range and bytes, nothing an engine can show.
    std::vector<std::size_t> kept_ranges{0};  // chain index ranges kept (0: the input)
    for (std::size_t k = 0; k < out.built.levels.size(); ++k) {
        if (same_surface(out.built.levels[k], *out.meshes.back())) {
            out.dropped.push_back(k + 1);
            out.built.notes.push_back("level " + std::to_string(k + 1) + " (" +
                                      std::to_string(out.built.levels[k].triangle_count()) +
                                      " triangles) is identical to the level before it; left out of the pack");
            continue;
        }
        out.meshes.push_back(&out.built.levels[k]);
        out.distance.push_back(out.built.distance[k]);
        kept_ranges.push_back(k + 1);
    }
    // Optimal placement gives every level its own vertices: the chain has no shared buffer to write.
    out.shared_buffer = out.built.chain && !out.built.chain->shared.levels.empty();
    if (out.shared_buffer && !out.dropped.empty()) {
        std::vector<LodIndexRange> ranges;
        for (std::size_t k : kept_ranges) ranges.push_back(out.built.chain->shared.levels[k]);
        out.built.chain->shared.levels = std::move(ranges);
    }
    bind_skins(mesh, params.preset, kept_ranges, out);
    return out;
}

// Files a method adds beyond the levels (the .lodstrips file of the lodstrips method).
void write_method_files(const BuiltLevels& built, const PackParams& params, const fs::path& dir,
                        const std::string& stem) {
    if (!params.preset.exports.lodstrips) return;
    if (built.built.lodstrips_file.empty())
        throw_error(Error::Kind::argument, params.source_path,
                    "the .lodstrips export needs the lodstrips method (the preset's method is '" +
                        std::string(to_string(params.preset.method)) + "')");
    AtomicFile file((dir / (stem + ".lodstrips")).string(), true);
    file.stream().write(reinterpret_cast<const char*>(built.built.lodstrips_file.data()),
                        static_cast<std::streamsize>(built.built.lodstrips_file.size()));
    file.commit();
}

std::string manifest(const Mesh& mesh, const PackParams& params, const BuiltLevels& built, const PackResult& r) {
    ordered_json j;
    j["format"] = "lodforge-pack";
    j["version"] = pack_format_version;
    // The file name only: the same source reached by another path (studio, CLI) gives the same pack.
    j["source"] = {{"file", fs::path(params.source_path).filename().string()},
                   {"sha256", r.source_sha256},
                   {"triangles", mesh.triangle_count()},
                   {"vertices", mesh.point_count()},
                   {"diagonal", mesh.bounds().diagonal()}};
    j["method"] = std::string(to_string(params.preset.method));
    // Where the levels' vertices come from: collapse follows the preset (half-edge with pose sampling),
    // lodstrips always keeps input vertices; the other methods build new surfaces (null).
    if (params.preset.method == LodMethod::collapse)
        j["placement"] = std::string(to_string(built.built.vertices_on_input ? Placement::half_edge : Placement::optimal));
    else if (params.preset.method == LodMethod::lodstrips) j["placement"] = std::string(to_string(Placement::half_edge));
    else j["placement"] = nullptr;
    const SwitchParams& sw = params.preset.switching;
    j["screen_reference"] = {{"width", sw.width}, {"height", sw.height}};
    j["switch"] = {{"pixels", sw.pixels}, {"screen", {sw.width, sw.height}}, {"fov_deg", sw.fov_deg},
                   {"hysteresis", sw.hysteresis}};
    j["glb"] = r.glb.empty() ? ordered_json(nullptr) : ordered_json(r.glb);
    ordered_json levels = ordered_json::array();
    for (std::size_t k = 0; k < r.levels.size(); ++k) {
        const PackLevel& level = r.levels[k];
        ordered_json l;
        l["level"] = k;
        l["triangles"] = level.triangles;
        l["vertices"] = level.vertices;
        l["wedges"] = level.wedges;
        l["ratio"] = static_cast<double>(level.triangles) / static_cast<double>(mesh.triangle_count());
        l["error"] = ordered_json::parse(distance_json(built.distance[k]));
        if (level.image_error) l["image_error"] = ordered_json::parse(image_error_json(*level.image_error, true));
        l["screen_coverage"] = level.screen_coverage;
        l["screen_size"] = level.screen_size;
        l["switch"] = ordered_json::parse(level_switch_json(level.switching));
        l["files"] = level.files;
        levels.push_back(l);
    }
    j["levels"] = levels;
    j["dropped_levels"] = built.dropped;
    j["notes"] = built.built.notes;
    std::vector<std::string> files = r.files;
    files.push_back("pack.json");
    j["files"] = files;
    j["preset"] = ordered_json::parse(preset_to_json(params.preset));
    // File names need not be UTF-8 (JSON must be): bad bytes become U+FFFD.
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace

bool same_surface(const Mesh& a, const Mesh& b) {
    if (a.indices != b.indices || a.positions != b.positions || a.colors != b.colors ||
        a.texcoords != b.texcoords || a.face_materials != b.face_materials || a.normals.size() != b.normals.size() ||
        a.joints != b.joints || a.weights != b.weights)
        return false;
    for (std::size_t i = 0; i < a.normals.size(); ++i)
        for (int c = 0; c < 3; ++c)
            if (std::abs(a.normals[i][c] - b.normals[i][c]) > 1e-5f) return false;
    return true;
}

PackResult write_lod_pack(const Mesh& mesh, const PackParams& params, Progress* progress) {
    if (params.source_path.empty())
        throw Error(Error::Kind::argument, "pack: no source path given (it names the outputs and is hashed)");
    if (params.output_dir.empty()) throw Error(Error::Kind::argument, "pack: no output directory given");
    if (mesh.triangle_count() == 0) throw_error(Error::Kind::invalid, params.source_path, "the mesh has no triangles");
    if (params.preset.levels.empty() && !params.preset.auto_levels) throw_error(Error::Kind::argument, params.source_path, "the preset has no levels");

    PackResult result;
    check_progress(progress, 0.0, "hashing source");
    result.source_sha256 = sha256_file(params.source_path);
    check_progress(progress, 1.0, "hashing source");

    // Before the long part, so an unwritable output fails at once.
    StagedDirectory staging(params.output_dir);
    const BuiltLevels built = make_levels(mesh, params, progress);
    result.notes = built.built.notes;
    result.dropped_levels = built.dropped;
    const std::size_t n = built.meshes.size();

    // Level k is shown down to the coverage at which level k+1's error is `pixels` pixels; the coarsest
    // is never culled (switch_points.h).
    std::vector<double> errors;
    for (const DistanceResult& d : built.distance) errors.push_back(d.hausdorff_relative);
    const SwitchPoints switches = switch_points(errors, mesh.bounds(), params.preset.switching);
    result.levels.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        PackLevel& level = result.levels[k];
        const Mesh& m = *built.meshes[k];
        level.triangles = m.triangle_count();
        level.vertices = m.point_count();
        level.wedges = m.vertex_count();
        level.error = built.distance[k].hausdorff;
        level.error_relative = built.distance[k].hausdorff_relative;
        level.mean_error = built.distance[k].mean;
        level.mean_error_relative = built.distance[k].mean_relative;
        if (k < switches.levels.size()) level.switching = switches.levels[k];
        level.screen_coverage = level.switching.coverage;
        level.screen_size = level.switching.screen_size;
    }

    if (params.preset.exports.image_error && !params.image_error)
        throw_error(Error::Kind::argument, params.source_path,
                    "the preset asks for image errors (export.image_error) but this program cannot render them");
    if (params.preset.exports.image_error) {
        for (std::size_t k = 1; k < n; ++k) {
            check_progress(progress, static_cast<double>(k - 1) / static_cast<double>(n - 1), "rendering levels");
            result.levels[k].image_error = params.image_error(mesh, *built.meshes[k]);
        }
    }

    std::string stem = fs::path(params.source_path).stem().string();
    if (stem.empty()) stem = "mesh";
    const ExportOptions& exports = params.preset.exports;

    if (exports.glb) {
        GlbOptions o;
        o.name = stem;
        for (const PackLevel& level : result.levels) o.screen_coverage.push_back(level.screen_coverage);
        result.glb = stem + ".glb";
        const std::string path = staging.file(result.glb).string();
        if (built.shared_buffer) {
            write_glb(built.built.chain->shared, o, path, progress);
        } else {
            std::vector<Mesh> copies;  // the writer takes the levels by value-list; the input is level 0
            copies.reserve(n);
            for (const Mesh* m : built.meshes) copies.push_back(*m);
            write_glb(copies, o, path, progress);
        }
        for (const std::string& f : staging.new_files()) result.files.push_back(f);
    }
    for (std::size_t k = 0; k < n; ++k) {
        check_progress(progress, static_cast<double>(k) / static_cast<double>(n), "writing level files");
        const std::string base = stem + "_lod" + std::to_string(k);
        if (exports.ply) write_mesh(*built.meshes[k], staging.file(base + ".ply").string(), {}, progress);
        if (exports.obj) write_mesh(*built.meshes[k], staging.file(base + ".obj").string(), {}, progress);
        result.levels[k].files = staging.new_files();
        for (const std::string& f : result.levels[k].files) result.files.push_back(f);
    }
    write_method_files(built, params, staging.dir(), stem);
    for (const std::string& f : staging.new_files()) result.files.push_back(f);

    check_progress(progress, 0.0, "writing pack.json");
    result.manifest = manifest(mesh, params, built, result);
    {
        AtomicFile file(staging.file("pack.json").string(), true);
        file.stream() << result.manifest;
        file.commit();
    }
    result.files.push_back("pack.json");
    check_progress(progress, 1.0, "writing pack.json");
    staging.commit();
    return result;
}

}  // namespace lodforge
