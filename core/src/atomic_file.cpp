#include "lodforge/atomic_file.h"

#include "lodforge/error.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <unistd.h>

namespace lodforge {
namespace fs = std::filesystem;

namespace {
std::string temp_name_for(const std::string& target) {
    // Same directory as the target so the final rename stays on one file system (atomic).
    static std::atomic<unsigned> counter{0};
    fs::path p(target);
    // Built by appending: GCC 12 at -O3 reports a false -Wrestrict for the chained operator+ form.
    std::string name = ".";
    name.append(p.filename().string()).append(".tmp-").append(std::to_string(::getpid()));
    name.append("-").append(std::to_string(counter++));
    return (p.parent_path() / name).string();
}
}  // namespace

AtomicFile::AtomicFile(std::string target_path, bool binary)
    : target_path_(std::move(target_path)), temp_path_(temp_name_for(target_path_)) {
    const fs::path parent = fs::path(target_path_).parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
        throw_error(Error::Kind::io, target_path_, "cannot write: directory " + parent.string() + " does not exist");
    if (fs::is_directory(target_path_))
        throw_error(Error::Kind::io, target_path_, "cannot write: it is a directory");
    out_.open(temp_path_, binary ? std::ios::out | std::ios::binary | std::ios::trunc
                                 : std::ios::out | std::ios::trunc);
    if (!out_)
        throw_error(Error::Kind::io, target_path_, std::string("cannot create output file: ") + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    out_.close();
    std::error_code ignored;
    fs::remove(temp_path_, ignored);
}

void AtomicFile::commit() {
    out_.flush();
    const bool write_ok = static_cast<bool>(out_);
    const int saved_errno = errno;
    out_.close();
    if (!write_ok || out_.fail()) {
        std::error_code ignored;
        fs::remove(temp_path_, ignored);
        throw_error(Error::Kind::io, target_path_,
                    std::string("write failed (disk full or I/O error): ") +
                        (saved_errno ? std::strerror(saved_errno) : "unknown error"));
    }
    std::error_code ec;
    fs::rename(temp_path_, target_path_, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(temp_path_, ignored);
        throw_error(Error::Kind::io, target_path_, "cannot move output into place: " + ec.message());
    }
    committed_ = true;
}

}  // namespace lodforge
