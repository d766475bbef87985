#include "commands.h"
#include "mesh_output.h"
#include "terminal_progress.h"

#include "lodforge/io/mesh_io.h"

#include <cstdio>

namespace lodforge::cli {

void add_convert_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string input, output;
        std::string encoding = "binary";
        bool float_colors = false;
        bool no_normals = false, no_colors = false, no_texcoords = false;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("convert", "Convert any supported input to PLY, OBJ or GLB");
    cmd->add_option("IN", options->input, "Input mesh (.ply, .obj, .gltf, .glb)")->required();
    cmd->add_option("OUT", options->output, "Output mesh (.ply, .obj or .glb)")->required();
    cmd->add_option("--encoding", options->encoding, "PLY encoding")
        ->check(CLI::IsMember({"ascii", "binary", "binary-be"}))
        ->capture_default_str();
    cmd->add_flag("--float-colors", options->float_colors, "PLY: write colours as float instead of uchar");
    cmd->add_flag("--no-normals", options->no_normals, "Drop normals");
    cmd->add_flag("--no-colors", options->no_colors, "Drop vertex colours");
    cmd->add_flag("--no-texcoords", options->no_texcoords, "Drop texture coordinates");
    cmd->callback([options, &global] {
        check_mesh_output("convert", options->output);
        TerminalProgress progress(!global.quiet && stderr_is_terminal());
        const Mesh mesh = read_mesh(options->input, {}, &progress);
        WriteOptions write;
        write.ply_encoding = options->encoding == "ascii"       ? PlyEncoding::ascii
                             : options->encoding == "binary-be" ? PlyEncoding::binary_big_endian
                                                                : PlyEncoding::binary_little_endian;
        write.ply_colors_as_uchar = !options->float_colors;
        write.write_normals = !options->no_normals;
        write.write_colors = !options->no_colors;
        write.write_texcoords = !options->no_texcoords;
        write_mesh_output(mesh, options->output, write, &progress);
        progress.finish();
        if (!global.quiet)
            std::fprintf(stderr, "wrote %s: %zu vertices, %zu triangles\n", options->output.c_str(),
                         mesh.point_count(), mesh.triangle_count());
    });
}

}  // namespace lodforge::cli
