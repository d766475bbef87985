// The first check of every reader: is there a regular file to read at this path?
#pragma once

#include <string>
#include <string_view>

namespace lodforge {

// Throws Error(io) naming `path` when it does not exist, is a directory, or is not a regular file
// (a FIFO would block the reader forever, /dev/zero would be read until memory runs out). `kind`
// completes "is a directory, not ___", e.g. "a mesh file". Runs before the file is opened.
void check_input_file(const std::string& path, std::string_view kind);

// The whole of a small text input (a preset, a manifest, a state file) after check_input_file; throws
// Error(io) naming `path` when it cannot be read.
std::string read_input_text(const std::string& path, std::string_view kind);

}  // namespace lodforge
