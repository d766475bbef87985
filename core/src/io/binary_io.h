// The one byte writer, bounded byte reader, checksum and tagged section container of LodForge's own
// binary formats (.lfo, .mco, .lodstrips, .lfmorph, .lfmstrips; docs/formats/README.md, "Container").
// Little-endian throughout; the container and its CRC-32 are those of the engine runtime
// (lodforge/runtime/lodstrips_runtime.h), so the core and the engines parse one layout with one parser.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <vector>

namespace lodforge::binary {

static_assert(std::endian::native == std::endian::little, "the formats are little-endian; writers copy memory as is");

// CRC-32 (IEEE 802.3) of n bytes: the checksum of every container header and section.
std::uint32_t checksum(const std::uint8_t* p, std::size_t n);

// Appends values to a byte buffer. Trivially copyable values are written as their memory (little-endian).
class Writer {
public:
    template <class T> void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    template <class T> void put_array(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
        bytes.insert(bytes.end(), p, p + v.size() * sizeof(T));
    }
    void varint(std::uint64_t v);  // LEB128
    void zigzag(std::int64_t v);   // signed, as a varint of the zigzag code
    void str(const std::string& s);  // varint length, then the bytes
    std::vector<std::uint8_t> bytes;
};

// Reads values from [data, data + size) of the file `file`; any read past the end throws
// Error(format) naming the file, the part being read (`what`) and the byte offset in the file.
class Reader {
public:
    // `offset`: where data starts in the file (for messages); `section`: prefixes messages when not empty.
    Reader(const std::uint8_t* data, std::size_t size, const std::string& file, std::size_t offset = 0,
           std::string section = {});
    template <class T> T get(const char* what) {
        static_assert(std::is_trivially_copyable_v<T>);
        need(sizeof(T), 1, what);
        T v;
        std::memcpy(&v, data_ + pos_, sizeof(T));
        pos_ += sizeof(T);
        return v;
    }
    // `count` values, checked against the bytes left before anything is allocated.
    template <class T> std::vector<T> get_array(std::uint64_t count, const char* what) {
        need(sizeof(T), count, what);
        std::vector<T> v(static_cast<std::size_t>(count));
        if (count) std::memcpy(v.data(), data_ + pos_, v.size() * sizeof(T));
        pos_ += v.size() * sizeof(T);
        return v;
    }
    std::string get_string(std::uint32_t length, const char* what);
    std::size_t position() const { return pos_; }
    std::size_t left() const { return size_ - pos_; }
    // Throws unless every byte was read ("N unexpected bytes after <what>").
    void expect_end(const char* what) const;
    [[noreturn]] void fail(const std::string& what) const;

private:
    void need(std::size_t size, std::uint64_t count, const char* what) const;
    const std::uint8_t* data_;
    std::size_t size_;
    const std::string& file_;
    std::size_t offset_;
    std::string section_;
    std::size_t pos_ = 0;
};

// A section to write: a four-character tag and its payload.
struct SectionOut {
    const char* tag;
    const std::vector<std::uint8_t>* payload;
};

// The container image: magic, version, byte-order tag, section count, header CRC, file size, then each
// section's tag, length, CRC and payload. Throws Error(invalid) if a payload exceeds 4 GiB.
std::vector<std::uint8_t> write_container(const char (&magic)[8], std::uint32_t version,
                                          std::initializer_list<SectionOut> sections);
// Size of the container image holding payloads of these sizes.
std::size_t container_size(std::initializer_list<std::size_t> payload_sizes);

// The version field (bytes 8..11) after checking the magic; throws Error(format) naming `file` with
// "not a <kind> file" when the magic differs, "truncated header" when there is no version.
std::uint32_t peek_version(const std::vector<std::uint8_t>& bytes, const std::string& file, const char (&magic)[8],
                           const char* kind);

// A parsed section: its payload and where it starts in the file.
struct Section {
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
    std::size_t offset = 0;
    std::string tag;
    Reader reader(const std::string& file) const { return Reader(data, size, file, offset, "section " + tag); }
};

// Parses a container whose sections must be exactly `tags`, in order, and checks every checksum and
// size; throws Error(format) naming `file` and the problem.
std::vector<Section> read_container(const std::vector<std::uint8_t>& bytes, const std::string& file,
                                    const char (&magic)[8], const char* kind, std::initializer_list<const char*> tags);

// The whole of an input file (check_input_file first, so a FIFO or directory is an Error(io)).
// `kind` completes "not ___", e.g. "a .mco file".
std::vector<std::uint8_t> read_file(const std::string& path, const char* kind);
// Writes bytes to path atomically (AtomicFile: a crash leaves the old file or none).
void write_file(const std::string& path, const std::vector<std::uint8_t>& bytes);

// 64-bit FNV-1a: only to verify files of the formats' versions before the container (.mco 2, .lfmorph 1).
// `basis`: the offset basis those writers used (.lfmorph 1's lacks the standard basis' last digit).
constexpr std::uint64_t fnv1a_basis = 0xcbf29ce484222325ULL, lfmorph1_fnv1a_basis = 1469598103934665603ULL;
std::uint64_t legacy_fnv1a(const std::uint8_t* p, std::size_t n, std::uint64_t basis);

}  // namespace lodforge::binary
