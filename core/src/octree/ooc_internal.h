// Private helpers of the out-of-core pipeline (ooc_soup, octree_build, octree_store, ooc_cluster):
// unbuffered POSIX files with big caller-owned buffers (the page cache does the rest), and a flat
// open-addressing hash map from 64-bit keys to 32-bit values (node-local vertex and edge tables, where
// std::unordered_map's per-node allocations would cost more than the work itself).
#pragma once

#include "lodforge/error.h"

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fcntl.h>
#include <string>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>
#include <utility>
#include <vector>

namespace lodforge::ooc {

inline std::uint64_t mix64(std::uint64_t x) {  // splitmix64 finaliser
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// The centroid of a soup triangle (records of `corner_bytes`, position after the 4-byte id), in double:
// the one definition the octant assignment and the planning paths both use (docs/octree.md).
inline void centroid(const std::byte* tri, std::size_t corner_bytes, double c[3]) {
    float p[3][3];
    for (int k = 0; k < 3; ++k) std::memcpy(p[k], tri + static_cast<std::size_t>(k) * corner_bytes + 4, sizeof p[k]);
    for (int a = 0; a < 3; ++a) c[a] = (static_cast<double>(p[0][a]) + p[1][a] + p[2][a]) / 3.0;
}

// The octant about `mid` of a soup triangle: the octant of its centroid; a centroid on a splitting
// plane goes to the upper half (the assignment rule). Bit a is set for the upper half along axis a.
inline int centroid_octant(const std::byte* tri, std::size_t corner_bytes, const double mid[3]) {
    double c[3];
    centroid(tri, corner_bytes, c);
    int o = 0;
    for (int a = 0; a < 3; ++a)
        if (c[a] >= mid[a]) o |= 1 << a;
    return o;
}

// A file descriptor that closes itself; every failure is an Error(io) naming the file.
class File {
public:
    File() = default;
    File(const std::string& path, int flags) : path_(path) {
        fd_ = ::open(path.c_str(), flags | O_CLOEXEC, 0644);
        if (fd_ < 0) throw_error(Error::Kind::io, path, std::string("cannot open: ") + std::strerror(errno));
    }
    ~File() { close(); }
    File(File&& o) noexcept : fd_(std::exchange(o.fd_, -1)), path_(std::move(o.path_)) {}
    File& operator=(File&& o) noexcept {
        if (this != &o) {
            close();
            fd_ = std::exchange(o.fd_, -1);
            path_ = std::move(o.path_);
        }
        return *this;
    }
    File(const File&) = delete;
    File& operator=(const File&) = delete;

    bool is_open() const { return fd_ >= 0; }
    const std::string& path() const { return path_; }
    void close() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }
    std::uint64_t size() const {
        struct stat st{};
        if (::fstat(fd_, &st) != 0) throw_error(Error::Kind::io, path_, std::string("cannot stat: ") + std::strerror(errno));
        return static_cast<std::uint64_t>(st.st_size);
    }
    void write_at(const void* data, std::size_t bytes, std::uint64_t offset) {
        const char* p = static_cast<const char*>(data);
        while (bytes > 0) {
            const ssize_t n = ::pwrite(fd_, p, bytes, static_cast<off_t>(offset));
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0)
                throw_error(Error::Kind::io, path_, std::string("write failed (disk full or I/O error): ") +
                                                        (n < 0 ? std::strerror(errno) : "no progress"));
            p += n;
            bytes -= static_cast<std::size_t>(n);
            offset += static_cast<std::uint64_t>(n);
        }
    }
    // Reads exactly `bytes` or throws Error(format) ("truncated") when the file ends first.
    void read_at(void* data, std::size_t bytes, std::uint64_t offset) const { read_at_fd(fd_, path_, data, bytes, offset); }
    static void read_at_fd(int fd, const std::string& path, void* data, std::size_t bytes, std::uint64_t offset) {
        char* p = static_cast<char*>(data);
        while (bytes > 0) {
            const ssize_t n = ::pread(fd, p, bytes, static_cast<off_t>(offset));
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) throw_error(Error::Kind::io, path, std::string("read failed: ") + std::strerror(errno));
            if (n == 0)
                throw_error(Error::Kind::format, path, "truncated: the file ends at byte " + std::to_string(offset));
            p += n;
            bytes -= static_cast<std::size_t>(n);
            offset += static_cast<std::uint64_t>(n);
        }
    }

private:
    int fd_ = -1;
    std::string path_;
};

// Sequential writer with one buffer; offset() is the logical end of the file.
class SequentialWriter {
public:
    SequentialWriter(const std::string& path, std::size_t buffer_bytes)
        : file_(path, O_WRONLY | O_CREAT | O_TRUNC), buffer_(buffer_bytes < 4096 ? 4096 : buffer_bytes) {}
    void write(const void* data, std::size_t bytes) {
        if (used_ + bytes > buffer_.size()) {
            flush();
            if (bytes > buffer_.size()) {
                file_.write_at(data, bytes, written_);
                written_ += bytes;
                return;
            }
        }
        std::memcpy(buffer_.data() + used_, data, bytes);
        used_ += bytes;
    }
    void flush() {
        if (used_ == 0) return;
        file_.write_at(buffer_.data(), used_, written_);
        written_ += used_;
        used_ = 0;
    }
    void close() {
        flush();
        file_.close();
        std::vector<char>().swap(buffer_);
    }
    std::uint64_t offset() const { return written_ + used_; }
    const std::string& path() const { return file_.path(); }

private:
    File file_;
    std::vector<char> buffer_;
    std::size_t used_ = 0;
    std::uint64_t written_ = 0;
};

// Flat hash map uint64 → uint32 with linear probing; the key ~0 is reserved (never inserted).
class FlatMap {
public:
    static constexpr std::uint64_t kEmpty = ~0ull;
    explicit FlatMap(std::size_t expected = 16) { reset(expected); }
    void reset(std::size_t expected) {
        std::size_t cap = 16;
        while (cap < 2 * expected) cap <<= 1;
        keys_.assign(cap, kEmpty);
        values_.resize(cap);
        size_ = 0;
    }
    // Returns a reference to the value of `key`, inserting `init` when absent; `inserted` says which.
    std::uint32_t& find_or_insert(std::uint64_t key, std::uint32_t init, bool& inserted) {
        if (2 * (size_ + 1) > keys_.size()) grow();
        std::size_t mask = keys_.size() - 1, slot = mix64(key) & mask;
        while (keys_[slot] != kEmpty && keys_[slot] != key) slot = (slot + 1) & mask;
        inserted = keys_[slot] == kEmpty;
        if (inserted) {
            keys_[slot] = key;
            values_[slot] = init;
            ++size_;
        }
        return values_[slot];
    }
    const std::uint32_t* find(std::uint64_t key) const {
        std::size_t mask = keys_.size() - 1, slot = mix64(key) & mask;
        while (keys_[slot] != kEmpty) {
            if (keys_[slot] == key) return &values_[slot];
            slot = (slot + 1) & mask;
        }
        return nullptr;
    }
    std::size_t size() const { return size_; }
    template <class F>
    void for_each(F&& f) const {
        for (std::size_t i = 0; i < keys_.size(); ++i)
            if (keys_[i] != kEmpty) f(keys_[i], values_[i]);
    }
    std::size_t memory_bytes() const { return keys_.capacity() * 8 + values_.capacity() * 4; }

private:
    void grow() {
        std::vector<std::uint64_t> old_keys(keys_.size() * 2, kEmpty);
        std::vector<std::uint32_t> old_values(keys_.size() * 2);
        old_keys.swap(keys_);
        old_values.swap(values_);
        const std::size_t mask = keys_.size() - 1;
        for (std::size_t i = 0; i < old_keys.size(); ++i) {
            if (old_keys[i] == kEmpty) continue;
            std::size_t slot = mix64(old_keys[i]) & mask;
            while (keys_[slot] != kEmpty) slot = (slot + 1) & mask;
            keys_[slot] = old_keys[i];
            values_[slot] = old_values[i];
        }
    }
    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> values_;
    std::size_t size_ = 0;
};

// Runs body(w) for w < workers: worker 0 on this thread (it alone reports progress and polls cancel),
// worker 1 on a helper that returns when `stop` is set. The first error stops both and is rethrown here
// once both have ended.
template <class Body>
void run_workers(int workers, std::atomic<bool>& stop, Body body) {
    if (workers < 2) {
        body(0);
        return;
    }
    std::exception_ptr helper_error;
    std::thread helper([&] {
        try {
            body(1);
        } catch (...) {
            helper_error = std::current_exception();
            stop = true;
        }
    });
    try {
        body(0);
    } catch (...) {
        stop = true;
        helper.join();
        throw;
    }
    helper.join();
    if (helper_error) std::rethrow_exception(helper_error);
}

}  // namespace lodforge::ooc
