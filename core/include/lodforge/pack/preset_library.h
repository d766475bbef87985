// The presets LodForge ships (resources/presets/*.json, installed to <prefix>/share/lodforge/presets and
// copied to <build>/share/lodforge/presets), and the one rule by which the CLI and the studio turn a
// `--preset` argument into a Preset (docs/presets.md, "Shipped presets").
//
//   Preset p = resolve_preset("mobile");         // a shipped preset
//   Preset q = resolve_preset("presets/my.json"); // a file
#pragma once

#include "lodforge/pack/preset.h"

#include <string>
#include <string_view>
#include <vector>

namespace lodforge {

// Where shipped presets are looked for, in order: $LODFORGE_PRESETS_DIR when set, then
// share/lodforge/presets under the running program's prefix (the directory above its bin/), then the
// data directory of the installation this library was built for. Directories that do not exist are left out.
std::vector<std::string> shipped_preset_dirs();

// The names (file stems) of the shipped presets, sorted, each once (the first directory wins).
std::vector<std::string> shipped_preset_names();

// Throws Error(argument) listing the shipped names when `name` is not one of them.
Preset load_shipped_preset(std::string_view name);

// A shipped preset's name, or a file: an argument containing a '/' or ending in ".json" is a file
// (load_preset), anything else a shipped name.
Preset resolve_preset(const std::string& name_or_path);

}  // namespace lodforge
