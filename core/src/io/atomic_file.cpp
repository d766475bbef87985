#include "lodforge/io/atomic_file.h"

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

namespace {
// Where the bytes go. A symbolic link is written through, as a shell redirection does (renaming over
// it would replace the link with a file); an existing target that is not a regular file (/dev/full,
// /dev/null, a FIFO) is written in place: renaming a temporary over it would replace the device node
// (which root is allowed to do) and report success on a "disk" that is full.
struct Destination {
    std::string path;
    bool direct = false;
};
Destination destination_of(const std::string& target) {
    std::error_code ec;
    Destination d{target, false};
    if (fs::is_symlink(fs::symlink_status(target, ec))) {
        const fs::path resolved = fs::weakly_canonical(target, ec);
        if (!ec) d.path = resolved.string();
    }
    const fs::file_status st = fs::status(d.path, ec);
    if (!ec && fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st)) d.direct = true;
    return d;
}
}  // namespace

AtomicFile::AtomicFile(std::string target_path, bool binary) : target_path_(std::move(target_path)) {
    const Destination dest = destination_of(target_path_);
    if (dest.direct) {
        // No temporary: a device or pipe cannot be replaced atomically; failures still surface in commit().
        direct_ = true;
        out_.open(dest.path, binary ? std::ios::out | std::ios::binary : std::ios::out);
        if (!out_)
            throw_error(Error::Kind::io, target_path_, std::string("cannot open output: ") + std::strerror(errno));
        return;
    }
    final_path_ = dest.path;
    temp_path_ = temp_name_for(final_path_);
    const fs::path parent = fs::path(final_path_).parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
        throw_error(Error::Kind::io, target_path_, "cannot write: directory " + parent.string() + " does not exist");
    if (fs::is_directory(final_path_))
        throw_error(Error::Kind::io, target_path_, "cannot write: it is a directory");
    out_.open(temp_path_, binary ? std::ios::out | std::ios::binary | std::ios::trunc
                                 : std::ios::out | std::ios::trunc);
    if (!out_)
        throw_error(Error::Kind::io, target_path_, std::string("cannot create output file: ") + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    out_.close();
    if (direct_) return;
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
        if (!direct_) fs::remove(temp_path_, ignored);
        throw_error(Error::Kind::io, target_path_,
                    std::string("write failed (disk full or I/O error): ") +
                        (saved_errno ? std::strerror(saved_errno) : "unknown error"));
    }
    if (direct_) {
        committed_ = true;
        return;
    }
    std::error_code ec;
    fs::rename(temp_path_, final_path_, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(temp_path_, ignored);
        throw_error(Error::Kind::io, target_path_, "cannot move output into place: " + ec.message());
    }
    committed_ = true;
}

}  // namespace lodforge
