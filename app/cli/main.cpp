// lodforge: the command line face of the LodForge core. Same library, same presets as the studio.
#include "commands.h"
#include "terminal_progress.h"

#include "lodforge/error.h"

#include <cstdio>
#include <exception>
#include <new>

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
    add_batch_command(app, global);

    install_interrupt_handler();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11 gives every parse error its own code (105, 109, ...); a usage error is 2 for all of them.
        return app.exit(e) == 0 ? 0 : kExitUsage;
    } catch (const lodforge::Error& e) {
        std::fprintf(stderr, "lodforge: error: %s\n", e.what());
        switch (e.kind()) {
            case lodforge::Error::Kind::cancelled: return cancelled_exit_code();
            case lodforge::Error::Kind::argument: return kExitUsage;  // an option value out of range
            default: return 1;
        }
    } catch (const std::bad_alloc&) {
        // Readers check sizes against the file before allocating; this is a real shortage of memory.
        std::fprintf(stderr, "lodforge: error: out of memory (the input needs more memory than is available)\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lodforge: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
