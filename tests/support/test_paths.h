// Paths the tests share: the real meshes beside the checkout and a scratch directory per test.
#pragma once

#include <filesystem>
#include <string>
#include <unistd.h>

namespace lodforge::test {

inline std::string shared_data(const std::string& relative) {
    return (std::filesystem::path(LODFORGE_SHARED_DATA) / relative).string();
}
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
