// Shipped presets are found beside the program (its prefix's share/) rather than at a path fixed at
// build time, so the build tree, an installed package and a relocated prefix all find their own copy.
#include "lodforge/pack/preset_library.h"

#include "lodforge/error.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <system_error>

namespace lodforge {

namespace fs = std::filesystem;

namespace {

void add_dir(std::vector<std::string>& dirs, const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    const std::string s = fs::weakly_canonical(dir, ec).string();
    if (std::find(dirs.begin(), dirs.end(), s) == dirs.end()) dirs.push_back(s);
}

bool is_file_argument(const std::string& arg) {
    return arg.find('/') != std::string::npos || fs::path(arg).extension() == ".json";
}

}  // namespace

std::vector<std::string> shipped_preset_dirs() {
    std::vector<std::string> dirs;
    if (const char* env = std::getenv("LODFORGE_PRESETS_DIR"); env && *env) add_dir(dirs, env);
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) add_dir(dirs, exe.parent_path().parent_path() / "share" / "lodforge" / "presets");
#ifdef LODFORGE_INSTALL_PRESETS_DIR
    add_dir(dirs, LODFORGE_INSTALL_PRESETS_DIR);
#endif
    return dirs;
}

std::vector<std::string> shipped_preset_names() {
    std::set<std::string> names;
    for (const std::string& dir : shipped_preset_dirs()) {
        std::error_code ec;
        for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
            if (e.path().extension() == ".json") names.insert(e.path().stem().string());
    }
    return {names.begin(), names.end()};
}

Preset load_shipped_preset(std::string_view name) {
    for (const std::string& dir : shipped_preset_dirs()) {
        const fs::path file = fs::path(dir) / (std::string(name) + ".json");
        std::error_code ec;
        if (fs::is_regular_file(file, ec)) return load_preset(file.string());
    }
    std::string known;
    for (const std::string& n : shipped_preset_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error(Error::Kind::argument,
                "'" + std::string(name) + "' is not a shipped preset (shipped: " +
                    (known.empty() ? std::string("none found; set LODFORGE_PRESETS_DIR") : known) +
                    "); a preset file needs a path with '/' or a .json name");
}

Preset resolve_preset(const std::string& name_or_path) {
    if (name_or_path.empty()) throw Error(Error::Kind::argument, "--preset: give a shipped preset name or a file");
    return is_file_argument(name_or_path) ? load_preset(name_or_path) : load_shipped_preset(name_or_path);
}

}  // namespace lodforge
