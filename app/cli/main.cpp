// lodforge: the command line face of the LodForge core. Same library, same presets as the studio.
#include "commands.h"
#include "terminal_progress.h"

#include "lodforge/error.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    using namespace lodforge::cli;
    CLI::App app{"LodForge: level-of-detail authoring for heavy meshes.\n"
                 "Reads PLY (ASCII, binary LE/BE), OBJ (+MTL) and glTF 2.0 (.gltf/.glb).",
                 "lodforge"};
    app.set_version_flag("--version", std::string("lodforge ") + LODFORGE_VERSION);
    app.require_subcommand(1);
    GlobalOptions global;
    app.add_flag("-q,--quiet", global.quiet, "Do not draw progress bars");

    add_info_command(app, global);
    add_convert_command(app, global);
    add_simplify_command(app, global);
    add_lod_command(app, global);
    add_compare_command(app, global);
    add_pack_command(app, global);
    add_morph_command(app, global);
    add_mcoctree_command(app, global);
    add_strips_command(app, global);
    add_octree_command(app, global);

    install_interrupt_handler();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);  // prints help or the usage error; non-zero for errors
    } catch (const lodforge::Error& e) {
        std::fprintf(stderr, "lodforge: error: %s\n", e.what());
        return e.kind() == lodforge::Error::Kind::cancelled ? 130 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lodforge: internal error: %s\n", e.what());
        return 3;
    }
    return 0;
}
