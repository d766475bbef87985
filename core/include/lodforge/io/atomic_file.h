// Write-then-rename, so a crash, a full disk or a cancelled job never leaves a truncated output that
// looks valid. Usage: AtomicFile f(path); write to f.stream(); f.commit(). Destruction without commit()
// removes the temporary file. A symbolic link is written through (its destination is replaced); a
// target that exists and is not a regular file (/dev/full, a FIFO) is written in place, without
// a temporary, so a full device is an error and the node survives.
#pragma once

#include <fstream>
#include <string>

namespace lodforge {

// The name (no directory) of a hidden temporary beside `target`: "." + its name + `tag` + pid-counter,
// unique within the process. The copy of the target's name is cut so the result fits the 255-byte
// limit of a file name: an output named near the limit can still be written.
std::string temp_sibling_name(const std::string& target, const std::string& tag);

// Removes from `directory` the temporaries that runs killed without a chance to clean up (SIGKILL,
// power loss) left behind: ".*.tmp-PID-N" files (AtomicFile), ".*.lodforge-tmp-PID-N" directories
// (octree scratch, staged outputs) and "lodforge-method-PID-N" directories, whose process PID no longer
// exists. Entries of live processes (this one included) and any other name are left alone; errors are
// ignored (it is housekeeping). Called where those temporaries are created.
void remove_stale_temporaries(const std::string& directory);

class AtomicFile {
public:
    explicit AtomicFile(std::string target_path, bool binary = true);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ofstream& stream() { return out_; }
    const std::string& temp_path() const { return temp_path_; }
    const std::string& target_path() const { return target_path_; }
    // Flushes, checks every write succeeded (disk full shows up here), renames over the target.
    void commit();

private:
    std::string target_path_;
    std::string final_path_;  // target_path_ with a symbolic link resolved; empty when direct_
    std::string temp_path_;   // empty when direct_
    std::ofstream out_;
    bool direct_ = false;
    bool committed_ = false;
};

}  // namespace lodforge
