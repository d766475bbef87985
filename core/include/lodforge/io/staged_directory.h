// A directory of outputs written as one: files go into a staging directory beside the target (same file
// system) and move into place only on commit(), so a failure or a cancel part-way through a multi-file
// output (a LOD pack, a `lod` chain) leaves neither half of it nor a new empty directory behind.
// Usage: StagedDirectory d(dir); write d.file("a.ply"), ...; d.commit(). Destruction without commit()
// removes the staging directory and any parent directory the constructor created.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace lodforge {

class StagedDirectory {
public:
    // Throws Error(argument) for an unusable path, Error(io) when the target exists and is not a writable
    // directory or the staging directory cannot be made.
    explicit StagedDirectory(const std::string& output_dir);
    ~StagedDirectory();
    StagedDirectory(const StagedDirectory&) = delete;
    StagedDirectory& operator=(const StagedDirectory&) = delete;

    std::filesystem::path file(const std::string& name) const { return dir_ / name; }
    const std::filesystem::path& dir() const { return dir_; }

    // Files that appeared in the staging directory since the last call, in name order.
    std::vector<std::string> new_files();

    // A new target: the staging directory is renamed to it. An existing one: every file written into the
    // staging directory moves into it, replacing files of the same names (after checking none of them is
    // a directory). Throws Error(io) when a destination is a directory or a rename fails.
    void commit();

private:
    void cleanup();

    std::filesystem::path target_, dir_;
    std::string shown_;
    bool target_existed_ = false, staging_created_ = false, committed_ = false;
    std::vector<std::filesystem::path> created_parents_;
    std::set<std::string> seen_;
};

}  // namespace lodforge
