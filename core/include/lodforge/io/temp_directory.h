// A directory for temporary files that goes with everything in it when its owner goes (success,
// exception or cancel alike), and the rule that keeps its generated names out of users' messages.
// Used by the out-of-core octree (soup, node files) and the pack's octree method.
#pragma once

#include "lodforge/error.h"

#include <string>

namespace lodforge {

// A directory for temporary files, removed with everything in it when the object dies (success,
// exception or cancel alike).
class TempDirectory {
public:
    // Creates a fresh uniquely named directory inside `parent` (which must exist).
    explicit TempDirectory(const std::string& parent);
    ~TempDirectory();
    TempDirectory(const TempDirectory&) = delete;
    TempDirectory& operator=(const TempDirectory&) = delete;

    const std::string& path() const { return path_; }
    std::string file(const std::string& name) const;
    // The directory an output file lives in ("." for a bare file name).
    static std::string beside(const std::string& output_path);

private:
    std::string path_;
};

// `e` reworded when its message names a file inside a TempDirectory (".lodforge-tmp-PID-N/..."): the
// user never named those files, so the message names `owner` (the user's output or input) and the
// directory that held the temporaries, then the problem. Other errors come back unchanged.
Error without_temporary_names(const Error& e, const std::string& owner);

}  // namespace lodforge
