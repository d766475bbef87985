// Paths the tests share: the real meshes beside the checkout and a scratch directory per test.
#pragma once

#include <filesystem>
#include <string>
#include <unistd.h>

namespace lodforge::test {

inline std::string shared_data(const std::string& relative) {
    return (std::filesystem::path(LODFORGE_SHARED_DATA) / relative).string();
}
#ifdef LODFORGE_TESTS_DIR  // defined for the GoogleTest suites (tests/CMakeLists.txt), not the fixture programs
// Files kept in the repository beside the tests (e.g. "mcoctree/data/cube-v2.mco").
inline std::string test_file(const std::string& relative) {
    return (std::filesystem::path(LODFORGE_TESTS_DIR) / relative).string();
}
#endif
inline std::string sample(const std::string& relative) {
    return (std::filesystem::path(LODFORGE_SAMPLES_DIR) / relative).string();
}

// A fresh directory under the system temp dir, removed when the object dies.
class ScratchDir {
public:
    explicit ScratchDir(const std::string& name) {
        path_ = std::filesystem::temp_directory_path() /
                ("lodforge-test-" + name + "-" + std::to_string(::getpid()));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

}  // namespace lodforge::test
