#include "commands.h"
#include "mesh_output.h"
#include "simplify_options.h"
#include "terminal_progress.h"

#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"
#include "lodforge/simplify/lod_chain.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/io/staged_directory.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace lodforge::cli {
namespace {

const char* reason_key(SimplifyResult::StopReason r) {
    switch (r) {
    case SimplifyResult::StopReason::target_reached: return "target_reached";
    case SimplifyResult::StopReason::error_limit: return "error_limit";
    case SimplifyResult::StopReason::topology_limit: return "topology_limit";
    }
    return "unknown";
}

// The float as its shortest decimal (0.001f prints as 0.001, not 0.0010000000474974513).
double float_as_written(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.7g", static_cast<double>(v));
    return std::strtod(buf, nullptr);
}

std::vector<LodLevelTarget> level_targets(const std::string& ratios, const std::string& triangles,
                                          const std::string& errors) {
    const int given = static_cast<int>(!ratios.empty()) + static_cast<int>(!triangles.empty()) +
                      static_cast<int>(!errors.empty());
    if (given != 1)
        throw Error(Error::Kind::argument, "lod: give exactly one of --levels, --level-triangles and --level-errors");
    std::vector<LodLevelTarget> levels;
    if (!ratios.empty()) {
        for (double r : parse_number_list(ratios, "--levels")) {
            if (!(r > 0 && r < 1))
                throw Error(Error::Kind::argument, "--levels: ratio " + std::to_string(r) +
                                                       " is outside (0, 1) (level 0 is the input itself)");
            levels.push_back({.ratio = static_cast<float>(r), .triangles = 0,
                              .max_error = std::numeric_limits<float>::infinity()});
        }
    } else if (!triangles.empty()) {
        for (double t : parse_number_list(triangles, "--level-triangles")) {
            if (!(t >= 1) || t != std::floor(t))
                throw Error(Error::Kind::argument, "--level-triangles: " + std::to_string(t) + " is not a positive integer");
            levels.push_back({.ratio = 0.f, .triangles = static_cast<std::size_t>(t),
                              .max_error = std::numeric_limits<float>::infinity()});
        }
    } else {
        for (double e : parse_number_list(errors, "--level-errors")) {
            if (!(e > 0)) throw Error(Error::Kind::argument, "--level-errors: errors must be > 0");
            levels.push_back({.ratio = 0.f, .triangles = 0, .max_error = static_cast<float>(e)});
        }
    }
    return levels;
}

}  // namespace

void add_lod_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string input, output_dir;
        std::string levels, level_triangles, level_errors;
        std::string format = "ply";
        std::string weights;
        bool lock_border = false;
        bool no_measure = false;
        long long samples = 0;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("lod", "Build a chain of levels of detail, each simplified from the previous one");
    cmd->add_option("IN", options->input, "Input mesh (.ply, .obj, .gltf, .glb)")->required();
    cmd->add_option("-o,--output", options->output_dir, "Output directory (created when missing)")->required();
    cmd->add_option("--levels", options->levels, "Triangle ratios of the input, decreasing, e.g. 0.5,0.25,0.1,0.03");
    cmd->add_option("--level-triangles", options->level_triangles, "Triangle counts, decreasing, e.g. 20000,5000,1000");
    cmd->add_option("--level-errors", options->level_errors,
                    "Error bounds per step (fraction of the diagonal), increasing, e.g. 0.001,0.004");
    cmd->add_option("--format", options->format, "Level file format")
        ->check(CLI::IsMember({"ply", "obj", "glb"}))
        ->capture_default_str();
    cmd->add_option("--weights", options->weights, kWeightsHelp);
    cmd->add_flag("--lock-border", options->lock_border, "Never move border vertices");
    cmd->add_flag("--no-measure", options->no_measure, "Skip measuring each level against the input");
    cmd->add_option("--samples", options->samples, "Samples per surface for the measurements (0 = automatic)");
    cmd->callback([options, &global] {
        const Options& o = *options;
        LodChainParams params;
        params.levels = level_targets(o.levels, o.level_triangles, o.level_errors);
        if (!o.weights.empty()) parse_weights(o.weights, params.simplify.weights);
        params.simplify.lock_border = o.lock_border;
        params.measure = !o.no_measure;
        if (o.samples < 0) throw Error(Error::Kind::argument, "lod: --samples must be >= 0");
        params.distance.samples = static_cast<std::size_t>(o.samples);

        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        // Read first: bad input must not leave an empty output directory behind.
        const Mesh mesh = read_triangle_mesh("lod", o.input, &progress);
        // Every file goes into a staging directory and moves into place at the end: a failed or
        // cancelled run leaves no partial chain (earlier levels without lods.json) in the target.
        StagedDirectory staging(o.output_dir);
        const LodChainResult chain = build_lod_chain(mesh, params, &progress);

        nlohmann::ordered_json doc;
        doc["input"] = o.input;
        doc["format"] = o.format;
        doc["diagonal"] = mesh.bounds().diagonal();
        doc["measured"] = params.measure;
        nlohmann::ordered_json levels = nlohmann::ordered_json::array();
        for (std::size_t i = 0; i < chain.levels.size(); ++i) {
            const LodLevel& level = chain.levels[i];
            const std::string name = "lod" + std::to_string(i) + "." + o.format;
            write_mesh_output(level.mesh, staging.file(name).string(), {}, &progress);
            nlohmann::ordered_json j;
            j["level"] = i;
            j["file"] = name;
            j["triangles"] = level.triangles;
            j["vertices"] = level.mesh.point_count();
            j["wedges"] = level.mesh.vertex_count();
            j["ratio"] = static_cast<double>(level.triangles) / static_cast<double>(mesh.triangle_count());
            if (i == 0) {
                j["stop_reason"] = "input";
            } else {
                const LodLevelTarget& t = params.levels[i - 1];
                if (level.target_triangles) j["target_triangles"] = level.target_triangles;
                else j["target_max_error"] = float_as_written(t.max_error);
                j["stop_reason"] = reason_key(level.reason);
            }
            nlohmann::ordered_json e;
            e["step"] = level.step_error;
            e["step_relative"] = level.step_error_relative;
            e["accumulated"] = level.accumulated_error;
            e["accumulated_relative"] = level.accumulated_error_relative;
            if (level.measured || i == 0) {
                const DistanceResult& d = level.distance;
                e["hausdorff"] = d.hausdorff;
                e["hausdorff_relative"] = d.hausdorff_relative;
                e["mean"] = d.mean;
                e["mean_relative"] = d.mean_relative;
                e["rms"] = d.rms;
                e["rms_relative"] = d.rms_relative;
                if (d.has_color_error) e["color_rms"] = d.color_rms;
                if (d.has_texcoord_error) e["texcoord_rms"] = d.texcoord_rms;
            }
            j["error"] = e;
            const LodIndexRange& r = chain.shared.levels[i];
            j["shared"] = {{"first_index", r.first_index}, {"index_count", r.index_count}, {"vertex_count", r.vertex_count}};
            levels.push_back(j);
        }
        doc["levels"] = levels;
        doc["shared_vertices"] = chain.shared.vertices.vertex_count();
        AtomicFile file(staging.file("lods.json").string(), false);
        file.stream() << doc.dump(2) << "\n";
        file.commit();
        staging.commit();
        progress.finish();

        for (std::size_t i = 0; i < chain.levels.size(); ++i) {
            const LodLevel& level = chain.levels[i];
            std::printf("lod%zu: %zu triangles, %zu vertices", i, level.triangles, level.mesh.point_count());
            if (level.measured)
                std::printf(", hausdorff %.3g, mean %.3g of the diagonal", level.distance.hausdorff_relative,
                            level.distance.mean_relative);
            if (i > 0 && level.reason != SimplifyResult::StopReason::target_reached)
                std::printf(" (stopped: %s)", reason_key(level.reason));
            std::printf("\n");
        }
        std::printf("wrote %zu levels and lods.json to %s\n", chain.levels.size(), o.output_dir.c_str());
    });
}

}  // namespace lodforge::cli
