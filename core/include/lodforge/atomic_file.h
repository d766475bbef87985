// Write-then-rename, so a crash, a full disk or a cancelled job never leaves a truncated output that
// looks valid. Usage: AtomicFile f(path); write to f.stream(); f.commit(). Destruction without commit()
// removes the temporary file.
#pragma once

#include <fstream>
#include <string>

namespace lodforge {

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
    std::string temp_path_;
    std::ofstream out_;
    bool committed_ = false;
};

}  // namespace lodforge
