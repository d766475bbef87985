// Content hashes of files, for manifests that must say exactly which source a pack was built from.
#pragma once

#include <string>
#include <string_view>

namespace lodforge {

// SHA-256 of the file's bytes as 64 lowercase hex digits (OpenSSL's EVP interface, read in chunks so
// large scans are not loaded twice). Throws Error(io) naming the file when it cannot be read.
std::string sha256_file(const std::string& path);

// SHA-256 of bytes in memory (a preset's canonical JSON, so a batch notices a changed preset), same format.
std::string sha256_text(std::string_view text);

}  // namespace lodforge
