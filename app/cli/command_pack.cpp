#include "commands.h"
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

namespace lodforge::cli {

void add_pack_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string input, preset, output_dir;
        bool json = false;
        bool image_error = false;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "pack", "Export a LOD pack (.glb with MSFT_lod, per-level PLY/OBJ, pack.json) as a preset describes it;\n"
                "the studio's export button writes the same pack from the same preset");
    cmd->add_option("IN", options->input, "Input mesh (.ply, .obj, .gltf, .glb)")->required();
    cmd->add_option("--preset", options->preset, "Preset JSON (docs/presets.md), as the studio saves it")->required();
    cmd->add_option("-o,--output", options->output_dir, "Pack directory (created when missing)")->required();
    cmd->add_flag("--json", options->json, "Print the levels and files written as JSON");
    cmd->add_flag("--image-error", options->image_error,
                  "Measure each level's image-space error and write it into pack.json (sets the preset's "
                  "export.image_error; docs/image-compare.md)");
    cmd->callback([options, &global] {
        const Options& o = *options;
        PackParams params;
        params.preset = load_preset(o.preset);
        params.source_path = o.input;
        params.output_dir = o.output_dir;
        if (o.image_error) params.preset.exports.image_error = true;
#ifdef LODFORGE_HAVE_RENDER
        if (params.preset.exports.image_error) params.image_error = render::packImageError();
#endif

        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const Mesh mesh = read_mesh(o.input, {}, &progress);
        const PackResult r = write_lod_pack(mesh, params, &progress);
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
                                  {"files", l.files}});
            for (std::size_t k = 0; k < r.levels.size(); ++k)
                if (r.levels[k].image_error)
                    levels[k]["image_error"] = nlohmann::ordered_json::parse(image_error_json(*r.levels[k].image_error, false));
            j["levels"] = levels;
            j["files"] = r.files;
            j["notes"] = r.notes;
            std::printf("%s\n", j.dump(2).c_str());
            return;
        }
        for (std::size_t k = 0; k < r.levels.size(); ++k) {
            const PackLevel& l = r.levels[k];
            std::printf("lod%zu: %zu triangles, %zu vertices, hausdorff %.3g of the diagonal, screen coverage %.4g", k,
                        l.triangles, l.vertices, l.error_relative, l.screen_coverage);
            if (l.image_error)
                std::printf(", image error %.3f (over threshold %.4f, silhouette %.4f)", l.image_error->mean_abs,
                            l.image_error->over_threshold, l.image_error->silhouette);
            std::printf("\n");
        }
        std::printf("wrote %zu files to %s\n", r.files.size(), o.output_dir.c_str());
    });
}

}  // namespace lodforge::cli
