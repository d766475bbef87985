#include "commands.h"
#include "simplify_options.h"
#include "terminal_progress.h"

#include "lodforge/error.h"
#include "lodforge/pack/lod_pack.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/pack/preset.h"
#ifdef LODFORGE_HAVE_RENDER
#include "lodforge/render/image_compare.h"
#endif

#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>
#include <optional>

namespace lodforge::cli {

namespace {

template <class Options>
void apply_switch_options(const Options& o, SwitchParams& s) {
    if (o.pixels) s.pixels = *o.pixels;
    if (o.fov) s.fov_deg = *o.fov;
    if (o.hysteresis) s.hysteresis = *o.hysteresis;
    if (o.screen.empty()) return;
    unsigned w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(o.screen.c_str(), "%u%c%u%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 ||
        h < 1 || w > 65536 || h > 65536)
        throw Error(Error::Kind::argument, "--switch-screen: '" + o.screen + "' is not WIDTHxHEIGHT (e.g. 1920x1080)");
    s.width = w;
    s.height = h;
}

}  // namespace

void add_pack_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string input, preset, output_dir, method, weights, importance, lock, seams, placement;
        std::string levels, level_triangles, level_errors;
        bool lock_border = false;
        bool json = false;
        bool image_error = false;
        std::optional<double> pixels, fov, hysteresis, min_screen_pixels;
        std::string screen;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "pack", "Export a LOD pack (.glb with MSFT_lod, per-level PLY/OBJ, pack.json) as a preset describes it\n"
                "(the studio's default without --preset); the studio's export button writes the same pack");
    cmd->add_option("IN", options->input, "Input mesh (.ply, .obj, .gltf, .glb)")->required();
    add_preset_option(cmd, options->preset);
    cmd->add_option("-o,--output", options->output_dir, "Pack directory (created when missing)")->required();
    cmd->add_option("--method", options->method, "LOD method (overrides the preset's)")
        ->check(CLI::IsMember({"collapse", "cluster", "octree", "lodstrips", "mcoctree"}));
    add_level_options(cmd, options->levels, options->level_triangles, options->level_errors);
    cmd->add_option("--weights", options->weights, kWeightsHelp);
    cmd->add_flag("--lock-border", options->lock_border, "Never move border vertices");
    add_paint_options(cmd, options->importance, options->lock, options->seams);
    add_placement_option(cmd, options->placement);
    cmd->add_flag("--json", options->json, "Print the levels and files written as JSON");
    cmd->add_flag("--image-error", options->image_error,
                  "Measure each level's image-space error and write it into pack.json (sets the preset's "
                  "export.image_error; docs/image-compare.md)");
    cmd->add_option("--switch-pixels", options->pixels,
                    "Pixel tolerance of the switch points (sets the preset's switch.pixels)")
        ->check(CLI::Range(0.01, 1e4));
    cmd->add_option("--switch-screen", options->screen, "Reference screen WIDTHxHEIGHT of the switch points, e.g. 1920x1080");
    cmd->add_option("--switch-fov", options->fov, "Vertical field of view in degrees, for the switch distances")
        ->check(CLI::Range(1.0, 179.0));
    cmd->add_option("--switch-hysteresis", options->hysteresis,
                    "Margin of the switch distances, a fraction of each (Godot's visibility range margins)")
        ->check(CLI::Range(0.0, 0.99));
    cmd->add_option("--min-screen-pixels", options->min_screen_pixels,
                    "Smallest on-screen size that matters, pixels (--levels auto stops there)")
        ->check(CLI::Range(1.0, 1e5));
    cmd->callback([options, &global] {
        const Options& o = *options;
        PackParams params;
        // Without --preset: the studio's default preset.
        params.preset = preset_from_option(o.preset).value_or(Preset{});
        if (!o.method.empty()) params.preset.method = lod_method_from_string(o.method);
        apply_level_options(params.preset, o.levels, o.level_triangles, o.level_errors, "pack");
        apply_switch_options(o, params.preset.switching);
        if (o.min_screen_pixels) params.preset.min_screen_pixels = *o.min_screen_pixels;
        if (!o.weights.empty()) parse_weights(o.weights, params.preset.weights);
        params.preset.lock_border = params.preset.lock_border || o.lock_border;
        if (!o.importance.empty()) params.preset.importance = o.importance;
        if (!o.lock.empty()) params.preset.lock = o.lock;
        if (!o.seams.empty()) params.preset.seams = o.seams;
        if (!o.placement.empty()) params.preset.placement = placement_from_string(o.placement);
        params.source_path = o.input;
        params.output_dir = o.output_dir;
        if (o.image_error) params.preset.exports.image_error = true;
#ifdef LODFORGE_HAVE_RENDER
        if (params.preset.exports.image_error) params.image_error = render::packImageError();
#endif

        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        // Every placement of an instanced glTF mesh, baked at its node's world transform, as the studio
        // loads it: a pack is the whole model (a wheel mesh placed by two nodes is two wheels).
        ReadOptions read;
        read.place_every_instance = true;
        const Mesh mesh = read_mesh(o.input, read, &progress);
        PackResult r;
        try {
            r = write_lod_pack(mesh, params, &progress);
        } catch (const Error& e) {
            // Options that parse but do not fit together (a preset's key, or an override, the method
            // cannot honour) are reported as invalid input (exit 1), as before the flags existed.
            if (e.kind() != Error::Kind::argument) throw;
            throw Error(Error::Kind::invalid, e.what());
        }
        progress.finish();
        for (const std::string& note : r.notes) std::fprintf(stderr, "lodforge: note: %s\n", note.c_str());

        if (o.json) {
            nlohmann::ordered_json j;
            j["output_dir"] = o.output_dir;
            j["glb"] = r.glb.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.glb);
            j["source_sha256"] = r.source_sha256;
            nlohmann::ordered_json levels = nlohmann::ordered_json::array();
            for (const PackLevel& l : r.levels)
                levels.push_back({{"triangles", l.triangles}, {"vertices", l.vertices}, {"wedges", l.wedges},
                                  {"error", l.error}, {"error_relative", l.error_relative},
                                  {"screen_coverage", l.screen_coverage}, {"screen_size", l.screen_size},
                                  {"switch", nlohmann::ordered_json::parse(level_switch_json(l.switching))},
                                  {"files", l.files}});
            for (std::size_t k = 0; k < r.levels.size(); ++k)
                if (r.levels[k].image_error)
                    levels[k]["image_error"] = nlohmann::ordered_json::parse(image_error_json(*r.levels[k].image_error, false));
            j["levels"] = levels;
            j["files"] = r.files;
            j["dropped_levels"] = r.dropped_levels;
            j["notes"] = r.notes;
            std::printf("%s\n", j.dump(2).c_str());
            return;
        }
        for (std::size_t k = 0; k < r.levels.size(); ++k) {
            const PackLevel& l = r.levels[k];
            std::printf("lod%zu: %zu triangles, %zu vertices, hausdorff %.3g of the diagonal, screen coverage %.4g", k,
                        l.triangles, l.vertices, l.error_relative, l.screen_coverage);
            const LevelSwitch& s = l.switching;
            if (k > 0) std::printf(", takes over at distance %.4g (Unreal screen size %.4g)", s.godot.range_begin, s.unreal_screen_size);
            if (k + 1 < r.levels.size())
                std::printf(", gives way at distance %.4g (Unity height %.4g)", s.godot.range_end, s.unity_transition_height);
            if (l.image_error)
                std::printf(", image error %.3f (over threshold %.4f, silhouette %.4f)", l.image_error->mean_abs,
                            l.image_error->over_threshold, l.image_error->silhouette);
            std::printf("\n");
        }
        std::printf("wrote %zu files to %s\n", r.files.size(), o.output_dir.c_str());
    });
}

}  // namespace lodforge::cli
