// Option parsing shared by the commands that make levels: the preset, attribute weights, level targets
// and comma-separated number lists. Bad values throw lodforge::Error(argument) naming the option, so they
// exit 1 with a clear message.
//
// One options model (docs/presets.md): `--preset NAME|FILE` gives every option of the command the
// preset's value, and each flag given on the command line overrides that key. Without --preset each
// command keeps its own defaults.
#pragma once

#include "lodforge/pack/preset.h"
#include "lodforge/simplify/simplify.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace lodforge::cli {

// "normal=0.02,color=0.1,uv=0.1,uv1=0.4" (keys: normal, color or colour, uv or texcoord, uvN or texcoordN
// for set N; values finite, >= 0)
// applied over `weights`.
// The --weights option's help, shared by every command that simplifies.
inline constexpr const char* kWeightsHelp =
    "Attribute weights, e.g. normal=0.02,color=0.1,uv=0.1; uv0=, uv1=, ... weigh one texcoord set";
void parse_weights(const std::string& text, SimplifyWeights& weights);

// "0.5,0.25,0.1": finite numbers; `option` names the option in messages.
std::vector<double> parse_number_list(const std::string& text, const std::string& option);

// Adds `--preset NAME|FILE` (a shipped preset or a preset file) to `cmd`.
CLI::Option* add_preset_option(CLI::App* cmd, std::string& value);
// The preset the option named (resolve_preset), or none when it was not given.
std::optional<Preset> preset_from_option(const std::string& value);

// The levels given by --levels (ratios in (0, 1)), --level-triangles (positive integers) or
// --level-errors (> 0); empty when none is given. Throws when more than one is given (`command`
// names the command).
std::vector<LodTarget> parse_level_targets(const std::string& ratios, const std::string& triangles,
                                           const std::string& errors, const std::string& command);
// Adds --importance FILE|color:CHANNEL, --lock FILE and --seams weight=CLASS:W,... (artist control,
// docs/artist-control.md) to `cmd`.
void add_paint_options(CLI::App* cmd, std::string& importance, std::string& lock, std::string& seams);

// The same options applied to `preset`: `--levels auto` sets "levels": "auto" (alone), other levels
// replace the preset's list. Returns whether any was given.
bool apply_level_options(Preset& preset, const std::string& ratios, const std::string& triangles,
                         const std::string& errors, const std::string& command);
// Adds those three options to `cmd`.
void add_level_options(CLI::App* cmd, std::string& ratios, std::string& triangles, std::string& errors);

// Adds `--placement optimal|half-edge` (the preset's "placement" key, collapse method) to `cmd`.
CLI::Option* add_placement_option(CLI::App* cmd, std::string& value);

}  // namespace lodforge::cli
