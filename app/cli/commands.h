// Each subcommand registers itself on the CLI11 app and runs through a callback; one file per
// command keeps main.cpp a table of contents.
#pragma once

#include <CLI/CLI.hpp>

namespace lodforge::cli {

struct GlobalOptions {
    bool quiet = false;     // no progress bar
};

void add_info_command(CLI::App& app, const GlobalOptions& global);
void add_convert_command(CLI::App& app, const GlobalOptions& global);
void add_simplify_command(CLI::App& app, const GlobalOptions& global);
void add_lod_command(CLI::App& app, const GlobalOptions& global);
void add_compare_command(CLI::App& app, const GlobalOptions& global);
void add_pack_command(CLI::App& app, const GlobalOptions& global);
void add_morph_command(CLI::App& app, const GlobalOptions& global);
void add_mcoctree_command(CLI::App& app, const GlobalOptions& global);
void add_strips_command(CLI::App& app, const GlobalOptions& global);
void add_octree_command(CLI::App& app, const GlobalOptions& global);
void add_batch_command(CLI::App& app, const GlobalOptions& global);

}  // namespace lodforge::cli
