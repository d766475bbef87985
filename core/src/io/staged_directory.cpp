#include "lodforge/io/staged_directory.h"

#include "lodforge/error.h"
#include "lodforge/io/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <system_error>
#include <unistd.h>

namespace lodforge {

namespace fs = std::filesystem;

StagedDirectory::StagedDirectory(const std::string& output_dir) {
    std::error_code ec;
    fs::path target = fs::absolute(fs::path(output_dir), ec).lexically_normal();
    if (ec || output_dir.empty()) throw_error(Error::Kind::argument, output_dir, "not a usable output directory");
    if (target.filename().empty()) target = target.parent_path();  // "dir/" → "dir"
    target_ = target;
    shown_ = output_dir;
    if (fs::exists(target_, ec)) {
        if (!fs::is_directory(target_, ec))
            throw_error(Error::Kind::io, shown_, "exists and is not a directory");
        if (::access(target_.c_str(), W_OK | X_OK) != 0)
            throw_error(Error::Kind::io, shown_, "output directory is not writable");
        target_existed_ = true;
    }
    // Create missing parents, remembering them so a failed write can remove them again.
    std::vector<fs::path> missing;
    for (fs::path p = target_.parent_path(); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
        if (!fs::create_directory(*it, ec) || ec) {
            cleanup();
            throw_error(Error::Kind::io, shown_, "cannot create directory " + it->string() +
                                                     (ec ? ": " + ec.message() : std::string()));
        }
        created_parents_.push_back(*it);
    }
    remove_stale_temporaries(target_.parent_path().string());
    const std::string name = temp_sibling_name(target_.string(), ".lodforge-tmp-");
    dir_ = target_.parent_path() / name;
    if ((!fs::create_directory(dir_, ec) || ec) && target_existed_) {
        // A writable target in a read-only parent: stage inside the target instead (still one
        // file system, still removed on failure).
        dir_ = target_ / name;
        ec.clear();
        fs::create_directory(dir_, ec);
    }
    if (ec || !fs::is_directory(dir_)) {
        cleanup();
        throw_error(Error::Kind::io, shown_,
                    "cannot create the output directory" + (ec ? ": " + ec.message() : std::string()));
    }
    staging_created_ = true;
}

StagedDirectory::~StagedDirectory() {
    if (!committed_) cleanup();
}

std::vector<std::string> StagedDirectory::new_files() {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_))
        if (entry.is_regular_file() && seen_.insert(entry.path().filename().string()).second)
            names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

void StagedDirectory::commit() {
    std::error_code ec;
    if (!target_existed_) {
        fs::rename(dir_, target_, ec);
        if (ec) throw_error(Error::Kind::io, shown_, "cannot move the output into place: " + ec.message());
    } else {
        new_files();  // everything written since the last call moves too
        // Check every destination before moving anything, so a target that cannot be replaced (a directory
        // of the same name) fails the commit with the old files untouched rather than half replaced.
        for (const std::string& name : seen_) {
            const fs::path to = target_ / name;
            if (fs::is_directory(fs::symlink_status(to, ec)))
                throw_error(Error::Kind::io, to.string(), "is a directory; cannot replace it with the new file");
        }
        for (const std::string& name : seen_) {
            fs::rename(dir_ / name, target_ / name, ec);
            if (ec) throw_error(Error::Kind::io, (target_ / name).string(), "cannot move into place: " + ec.message());
        }
        fs::remove(dir_, ec);
    }
    committed_ = true;
}

void StagedDirectory::cleanup() {
    std::error_code ignored;
    if (staging_created_) fs::remove_all(dir_, ignored);
    for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it) fs::remove(*it, ignored);
}

}  // namespace lodforge
