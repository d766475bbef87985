// Files kept in the repository beside a test suite (its data/ folder).
#pragma once

#include <filesystem>
#include <string>

namespace lodforge::test {

// `relative` to the suite's own source folder (LODFORGE_TESTS_DIR, set per suite by tests/CMakeLists.txt),
// e.g. "data/cube-v2.mco" in tests/mcoctree.
inline std::string suite_file(const std::string& relative) {
    return (std::filesystem::path(LODFORGE_TESTS_DIR) / relative).string();
}

}  // namespace lodforge::test
