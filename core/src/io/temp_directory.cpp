#include "lodforge/io/temp_directory.h"

#include "lodforge/io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string_view>
#include <system_error>

namespace lodforge {

namespace fs = std::filesystem;

TempDirectory::TempDirectory(const std::string& parent) {
    static std::atomic<unsigned> counter{0};
    const fs::path base = parent.empty() ? fs::path(".") : fs::path(parent);
    if (!fs::is_directory(base))
        throw_error(Error::Kind::io, base.string(), "cannot create temporary files: not a directory");
    remove_stale_temporaries(base.string());
    for (int attempt = 0; attempt < 100; ++attempt) {
        const fs::path p = base / (".lodforge-tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        std::error_code ec;
        if (fs::create_directory(p, ec)) {
            path_ = p.string();
            return;
        }
        if (ec && ec != std::errc::file_exists)
            throw_error(Error::Kind::io, base.string(), "cannot create a temporary directory in it: " + ec.message());
    }
    throw_error(Error::Kind::io, base.string(), "cannot create a temporary directory");
}

TempDirectory::~TempDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
}

Error without_temporary_names(const Error& e, const std::string& owner) {
    const std::string message = e.what();
    constexpr std::string_view kTag = ".lodforge-tmp-";
    const std::size_t first = message.find(kTag);
    if (first == std::string::npos) return e;
    // The path starts after the last space or the message start; its directory held the temporaries.
    const std::size_t space = message.rfind(' ', first);
    const std::size_t start = space == std::string::npos ? 0 : space + 1;
    const std::size_t slash = message.rfind('/', first);
    const std::string dir = slash == std::string::npos || slash < start ? "." : message.substr(start, slash - start);
    // The problem is what follows the last temporary path (errors may nest one in another).
    const std::size_t colon = message.find(": ", message.rfind(kTag));
    const std::string problem = colon == std::string::npos ? "failed" : message.substr(colon + 2);
    return Error(e.kind(), owner + ": temporary files in " + (dir.empty() ? "/" : dir) + ": " + problem);
}

std::string TempDirectory::file(const std::string& name) const { return (fs::path(path_) / name).string(); }

std::string TempDirectory::beside(const std::string& output_path) {
    const fs::path parent = fs::path(output_path).parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace lodforge
