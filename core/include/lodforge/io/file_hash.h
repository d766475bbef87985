// Content hashes of files, for manifests that must say exactly which source a pack was built from.
#pragma once

#include <string>

namespace lodforge {

// SHA-256 of the file's bytes as 64 lowercase hex digits (OpenSSL's EVP interface, read in chunks so
// large scans are not loaded twice). Throws Error(io) naming the file when it cannot be read.
std::string sha256_file(const std::string& path);

}  // namespace lodforge
