#include "commands.h"
#include "terminal_progress.h"

#include "lodforge/io/mesh_info.h"
#include "lodforge/io/mesh_io.h"

#include <cstdio>

namespace lodforge::cli {

void add_info_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string file;
        bool json = false;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("info", "Print counts, attributes, materials, bounds and validation findings");
    cmd->add_option("FILE", options->file, "Mesh file (.ply, .obj, .gltf, .glb)")->required();
    cmd->add_flag("--json", options->json, "Print JSON (keys: vertices, wedges, triangles, attributes, bounds, ...)");
    cmd->callback([options, &global] {
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        ReadOptions read;
        read.validate = false;  // info reports findings instead of refusing the file
        Mesh mesh = read_mesh(options->file, read, &progress);
        progress.finish();
        const MeshInfo info = mesh_info(mesh, options->file, format_name(detect_format(options->file)));
        const std::string text = options->json ? to_json(info) + "\n" : to_text(info);
        std::fputs(text.c_str(), stdout);
    });
}

}  // namespace lodforge::cli
