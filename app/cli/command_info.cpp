#include "commands.h"
#include "terminal_progress.h"

#include "lodforge/io/mesh_info.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/simplify/seams.h"

#include <nlohmann/json.hpp>

#include <cstdio>

namespace lodforge::cli {

void add_info_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string file;
        bool json = false;
        bool seams = false;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("info", "Print counts, attributes, materials, bounds and validation findings");
    cmd->add_option("FILE", options->file, "Mesh file (.ply, .obj, .gltf, .glb)")->required();
    cmd->add_flag("--json", options->json, "Print JSON (keys: vertices, wedges, triangles, attributes, bounds, ...)");
    cmd->add_flag("--seams", options->seams,
                  "Print the edges per seam class instead (uv, uv_mirror, crease, material, color, border, non_manifold)");
    cmd->callback([options, &global] {
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        ReadOptions read;
        read.validate = false;  // info reports findings instead of refusing the file
        Mesh mesh = read_mesh(options->file, read, &progress);
        progress.finish();
        if (options->seams) {
            const SeamReport r = classify_seams(mesh);
            nlohmann::ordered_json j;
            j["edges"] = r.edge_count;
            for (int c = 0; c < kSeamClasses; ++c) j[std::string(to_string(SeamClass(c)))] = r.edges[c].size();
            j["uv_sets"] = r.uv_set_edges;
            if (options->json) {
                std::printf("%s\n", j.dump(2).c_str());
                return;
            }
            std::printf("edges: %zu\n", r.edge_count);
            for (int c = 0; c < kSeamClasses; ++c)
                std::printf("%s: %zu\n", std::string(to_string(SeamClass(c))).c_str(), r.edges[c].size());
            for (std::size_t s = 0; s < r.uv_set_edges.size(); ++s) std::printf("uv set %zu: %zu\n", s, r.uv_set_edges[s]);
            return;
        }
        const MeshInfo info = mesh_info(mesh, options->file, format_name(detect_format(options->file)));
        const std::string text = options->json ? to_json(info) + "\n" : to_text(info);
        std::fputs(text.c_str(), stdout);
    });
}

}  // namespace lodforge::cli
