// Internals shared by ply_header.cpp, ply_reader.cpp and ply_writer.cpp: the buffered byte source and
// the header parser. Not installed.
#pragma once

#include "lodforge/io/ply.h"

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace lodforge::ply_detail {

// Parses a type name ("uchar", "uint8", "float32", ...); PlyType::none when unknown.
PlyType parse_type(std::string_view name);
inline bool is_integer(PlyType type) {
    return type != PlyType::none && type != PlyType::float32 && type != PlyType::float64;
}
// A token from the file made safe for a message: quoted, control characters replaced, cut at 40.
std::string show(std::string_view token);

// A window [cur, lim) over a file or a memory buffer. Files are read with large sequential reads into
// one buffer that only grows when a single item needs more contiguous bytes than it holds, so memory
// stays bounded whatever the file size. Memory sources expose the whole buffer at once.
class Input {
public:
    Input() = default;
    Input(const Input&) = delete;
    Input& operator=(const Input&) = delete;
    ~Input();

    void open_file(const std::string& path);  // throws Error(io)
    void open_memory(const char* data, std::size_t size);

    const char* cur = nullptr;
    const char* lim = nullptr;

    // Makes at least n bytes available at cur; false when the data ends first.
    bool ensure(std::size_t n) { return static_cast<std::size_t>(lim - cur) >= n || refill(n); }
    // Makes at least n bytes available, or everything up to the end of the data.
    void prefetch(std::size_t n) {
        if (static_cast<std::size_t>(lim - cur) < n) refill(n);
    }
    bool at_end() const { return cur == lim && offset() >= size_; }
    // The window holds everything up to the end of the data.
    bool lim_is_end() const { return base_ + static_cast<std::uint64_t>(lim - start_) >= size_; }
    // Skips n bytes (seeks past the buffer when needed); false when the data ends first.
    bool skip(std::uint64_t n);

    std::uint64_t offset() const { return base_ + static_cast<std::uint64_t>(cur - start_); }
    std::uint64_t size() const { return size_; }
    const std::string& path() const { return path_; }
    void set_name(std::string name) { path_ = std::move(name); }

private:
    bool refill(std::size_t n);

    std::FILE* file_ = nullptr;
    std::vector<char> storage_;
    const char* start_ = nullptr;  // data offset `base_` is at start_
    std::uint64_t base_ = 0;
    std::uint64_t size_ = 0;
    std::string path_;
};

// Size of the read buffer of file inputs opened after the call (default 1 MiB). Tests and the fuzzer
// shrink it to a few bytes so every refill and boundary path runs on small files.
void set_file_buffer_size(std::size_t bytes);

// Parses the header at the start of `in`, leaving in.cur at the first data byte. Throws Error(format).
PlyHeader parse_header(Input& in);

}  // namespace lodforge::ply_detail
