#include "commands.h"
#include "mesh_output.h"
#include "simplify_options.h"
#include "terminal_progress.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/staged_directory.h"
#include "lodforge/metrics/distance_json.h"
#include "lodforge/pack/preset_levels.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace lodforge::cli {
namespace {

// The float as its shortest decimal (0.001f prints as 0.001, not 0.0010000000474974513).
double float_as_written(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.7g", static_cast<double>(v));
    return std::strtod(buf, nullptr);
}

const char* stop_key(LevelStop s) {
    switch (s) {
    case LevelStop::target_reached: return "target_reached";
    case LevelStop::error_limit: return "error_limit";
    case LevelStop::topology_limit: return "topology_limit";
    case LevelStop::closest: return "closest";
    }
    return "unknown";
}

}  // namespace

void add_lod_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string input, output_dir, preset;
        std::string levels, level_triangles, level_errors;
        std::string format = "ply";
        std::string weights, importance, lock, seams, placement;
        bool lock_border = false;
        bool no_measure = false;
        long long samples = 0;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("lod", "Build levels of detail (by default a chain, each simplified from the previous one)");
    cmd->add_option("IN", options->input, "Input mesh (.ply, .obj, .gltf, .glb)")->required();
    cmd->add_option("-o,--output", options->output_dir, "Output directory (created when missing)")->required();
    add_preset_option(cmd, options->preset);
    add_level_options(cmd, options->levels, options->level_triangles, options->level_errors);
    cmd->add_option("--format", options->format, "Level file format")
        ->check(CLI::IsMember({"ply", "obj", "glb"}))
        ->capture_default_str();
    cmd->add_option("--weights", options->weights, kWeightsHelp);
    cmd->add_flag("--lock-border", options->lock_border, "Never move border vertices");
    add_paint_options(cmd, options->importance, options->lock, options->seams);
    add_placement_option(cmd, options->placement);
    cmd->add_flag("--no-measure", options->no_measure, "Skip measuring each level against the input");
    cmd->add_option("--samples", options->samples, "Samples per surface for the measurements (0 = automatic)");
    cmd->callback([options, &global] {
        const Options& o = *options;
        // Without a preset: the edge-collapse chain with the default weights; the flags say the levels.
        Preset preset = preset_from_option(o.preset).value_or(Preset{});
        if (o.preset.empty()) preset.levels.clear();
        apply_level_options(preset, o.levels, o.level_triangles, o.level_errors, "lod");
        if (preset.levels.empty() && !preset.auto_levels)
            throw Error(Error::Kind::argument, "lod: give one of --levels, --level-triangles and --level-errors (or --preset)");
        if (!o.weights.empty()) parse_weights(o.weights, preset.weights);
        preset.lock_border = preset.lock_border || o.lock_border;
        if (!o.importance.empty()) preset.importance = o.importance;
        if (!o.lock.empty()) preset.lock = o.lock;
        if (!o.seams.empty()) preset.seams = o.seams;
        if (!o.placement.empty()) preset.placement = placement_from_string(o.placement);
        if (o.samples < 0) throw Error(Error::Kind::argument, "lod: --samples must be >= 0");
        PresetLevelsParams params;
        params.source_path = o.input;
        params.measure = !o.no_measure;
        params.distance.samples = static_cast<std::size_t>(o.samples);

        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        // Read first: bad input must not leave an empty output directory behind.
        const Mesh mesh = read_triangle_mesh("lod", o.input, &progress);
        // Every file goes into a staging directory and moves into place at the end: a failed or
        // cancelled run leaves no partial chain (earlier levels without lods.json) in the target.
        StagedDirectory staging(o.output_dir);
        const PresetLevels built = build_preset_levels(mesh, preset, params, &progress);
        const LodChainResult* chain = built.chain ? &*built.chain : nullptr;
        const std::size_t count = built.levels.size() + 1;
        const auto level_mesh = [&](std::size_t i) -> const Mesh& { return i == 0 ? mesh : built.levels[i - 1]; };
        const auto measured = [&](std::size_t i) { return params.measure && i > 0; };

        nlohmann::ordered_json doc;
        doc["input"] = o.input;
        doc["format"] = o.format;
        if (!chain) doc["method"] = std::string(to_string(preset.method));
        else doc["placement"] = std::string(to_string(preset.placement));
        // Half-edge levels index one shared vertex buffer; optimal levels each have their own.
        const bool shared = chain && !chain->shared.levels.empty();
        doc["diagonal"] = mesh.bounds().diagonal();
        doc["measured"] = params.measure;
        nlohmann::ordered_json levels_json = nlohmann::ordered_json::array();
        for (std::size_t i = 0; i < count; ++i) {
            const Mesh& m = level_mesh(i);
            const std::string name = "lod" + std::to_string(i) + "." + o.format;
            write_mesh_output(m, staging.file(name).string(), {}, &progress);
            nlohmann::ordered_json j;
            j["level"] = i;
            j["file"] = name;
            j["triangles"] = m.triangle_count();
            j["vertices"] = m.point_count();
            j["wedges"] = m.vertex_count();
            j["ratio"] = static_cast<double>(m.triangle_count()) / static_cast<double>(mesh.triangle_count());
            if (i == 0) {
                j["stop_reason"] = "input";
            } else {
                const LodTarget& t = built.targets[i - 1];
                if (built.target_triangles[i - 1]) j["target_triangles"] = built.target_triangles[i - 1];
                else j["target_max_error"] = float_as_written(static_cast<float>(t.value));
                j["stop_reason"] = stop_key(built.stops[i - 1]);
            }
            nlohmann::ordered_json e;
            if (chain) {
                const LodLevel& level = chain->levels[i];
                e["step"] = level.step_error;
                e["step_relative"] = level.step_error_relative;
                e["accumulated"] = level.accumulated_error;
                e["accumulated_relative"] = level.accumulated_error_relative;
            }
            if (measured(i) || i == 0) {
                e.update(nlohmann::ordered_json::parse(distance_json(i == 0 ? DistanceResult{} : built.distance[i - 1])));
            }
            j["error"] = e;
            if (shared) {
                const LodIndexRange& r = chain->shared.levels[i];
                j["shared"] = {{"first_index", r.first_index}, {"index_count", r.index_count}, {"vertex_count", r.vertex_count}};
            }
            levels_json.push_back(j);
        }
        doc["levels"] = levels_json;
        if (shared) doc["shared_vertices"] = chain->shared.vertices.vertex_count();
        if (!built.notes.empty()) doc["notes"] = built.notes;
        AtomicFile file(staging.file("lods.json").string(), false);
        file.stream() << doc.dump(2) << "\n";
        file.commit();
        staging.commit();
        progress.finish();
        for (const std::string& note : built.notes) std::fprintf(stderr, "lodforge: note: %s\n", note.c_str());

        for (std::size_t i = 0; i < count; ++i) {
            const Mesh& m = level_mesh(i);
            std::printf("lod%zu: %zu triangles, %zu vertices", i, m.triangle_count(), m.point_count());
            if (measured(i))
                std::printf(", hausdorff %.3g, mean %.3g of the diagonal", built.distance[i - 1].hausdorff_relative,
                            built.distance[i - 1].mean_relative);
            if (i > 0 && built.stops[i - 1] != LevelStop::target_reached)
                std::printf(" (stopped: %s)", stop_key(built.stops[i - 1]));
            std::printf("\n");
        }
        std::printf("wrote %zu levels and lods.json to %s\n", count, o.output_dir.c_str());
    });
}

}  // namespace lodforge::cli
