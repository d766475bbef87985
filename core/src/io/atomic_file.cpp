#include "lodforge/io/atomic_file.h"

#include "lodforge/error.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <csignal>
#include <string_view>
#include <system_error>
#include <unistd.h>

namespace lodforge {
namespace fs = std::filesystem;

std::string temp_sibling_name(const std::string& target, const std::string& tag) {
    static std::atomic<unsigned> counter{0};
    std::string suffix = tag;
    suffix.append(std::to_string(::getpid())).append("-").append(std::to_string(counter++));
    constexpr std::size_t kNameMax = 255;
    std::string base = fs::path(target).filename().string();
    base.resize(std::min(base.size(), kNameMax - 1 - std::min(suffix.size(), kNameMax - 1)));
    // Built by appending: GCC 12 at -O3 reports a false -Wrestrict for the chained operator+ form.
    std::string name = ".";
    name.append(base).append(suffix);
    return name;
}

namespace {
// The PID of a temporary's name (see remove_stale_temporaries), 0 when the name is not one.
long temporary_owner(const std::string& name) {
    auto digits = [](std::string_view s) {
        return !s.empty() && s.size() < 12 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
    };
    const std::size_t dash = name.rfind('-');
    if (dash == std::string::npos || !digits(std::string_view(name).substr(dash + 1))) return 0;
    const std::size_t pid_start = name.rfind('-', dash - 1);
    if (pid_start == std::string::npos) return 0;
    const std::string_view pid = std::string_view(name).substr(pid_start + 1, dash - pid_start - 1);
    if (!digits(pid)) return 0;
    const std::string_view head = std::string_view(name).substr(0, pid_start + 1);
    const bool ours = (name[0] == '.' && (head.ends_with(".tmp-") || head.ends_with(".lodforge-tmp-"))) ||
                      head == "lodforge-method-";
    return ours ? std::stol(std::string(pid)) : 0;
}
}  // namespace

void remove_stale_temporaries(const std::string& directory) {
    std::error_code ec;
    fs::directory_iterator it(directory.empty() ? fs::path(".") : fs::path(directory), ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        const long pid = temporary_owner(it->path().filename().string());
        if (pid <= 0 || pid == ::getpid()) continue;
        if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
        std::error_code ignored;
        fs::remove_all(it->path(), ignored);
    }
}

namespace {
std::string temp_name_for(const std::string& target) {
    // Same directory as the target so the final rename stays on one file system (atomic).
    return (fs::path(target).parent_path() / temp_sibling_name(target, ".tmp-")).string();
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
    // Followed link by link (not weakly_canonical): a link whose destination does not exist yet must
    // create that destination, as `>` does, not be replaced by a file.
    fs::path p = target;
    for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
        const fs::path link = fs::read_symlink(p, ec);
        if (ec) break;
        p = link.is_absolute() ? link : p.parent_path() / link;
    }
    d.path = p.lexically_normal().string();
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
    remove_stale_temporaries(fs::path(final_path_).parent_path().string());
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
