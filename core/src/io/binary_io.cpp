#include "io/binary_io.h"

#include "lodforge/error.h"
#include "lodforge/io/atomic_file.h"
#include "lodforge/io/input_file.h"
#include "lodforge/runtime/lodstrips_runtime.h"

#include <fstream>
#include <iterator>

namespace lodforge::binary {

std::uint32_t checksum(const std::uint8_t* p, std::size_t n) { return lodstrips::detail::crc32(p, n); }

void Writer::varint(std::uint64_t v) {
    for (; v >= 0x80; v >>= 7) bytes.push_back(static_cast<std::uint8_t>(v | 0x80));
    bytes.push_back(static_cast<std::uint8_t>(v));
}

void Writer::zigzag(std::int64_t v) { varint((static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63)); }

void Writer::str(const std::string& s) {
    varint(s.size());
    bytes.insert(bytes.end(), s.begin(), s.end());
}

Reader::Reader(const std::uint8_t* data, std::size_t size, const std::string& file, std::size_t offset, std::string section)
    : data_(data), size_(size), file_(file), offset_(offset), section_(std::move(section)) {}

std::string Reader::get_string(std::uint32_t length, const char* what) {
    need(1, length, what);
    std::string s(reinterpret_cast<const char*>(data_ + pos_), length);
    pos_ += length;
    return s;
}

void Reader::expect_end(const char* what) const {
    if (pos_ != size_) fail(std::to_string(size_ - pos_) + " unexpected bytes after the " + what);
}

void Reader::fail(const std::string& what) const {
    throw_error(Error::Kind::format, file_,
                (section_.empty() ? "" : section_ + ": ") + what + " (byte " + std::to_string(offset_ + pos_) + ")");
}

void Reader::need(std::size_t size, std::uint64_t count, const char* what) const {
    if (count > (size_ - pos_) / size)
        fail(std::string("truncated: the ") + what + " need " + std::to_string(count) + " × " + std::to_string(size) +
             " bytes, " + std::to_string(size_ - pos_) + " left");
}

std::vector<std::uint8_t> write_container(const char (&magic)[8], std::uint32_t version,
                                          std::initializer_list<SectionOut> sections) {
    Writer out;
    out.bytes.assign(magic, magic + 8);
    out.put(version);
    out.put(lodstrips::endian_tag);
    out.put(static_cast<std::uint32_t>(sections.size()));
    out.put(checksum(out.bytes.data(), 20));
    std::size_t total = 32;
    for (const SectionOut& s : sections) total += 12 + s.payload->size();
    out.put(static_cast<std::uint64_t>(total));
    out.bytes.reserve(total);
    for (const SectionOut& s : sections) {
        if (s.payload->size() > 0xFFFFFFFFu)
            throw Error(Error::Kind::invalid, std::string("section ") + s.tag + " exceeds 4 GiB");
        std::uint32_t tag = 0;
        for (int k = 0; k < 4; ++k) tag |= std::uint32_t(std::uint8_t(s.tag[k])) << (8 * k);
        out.put(tag);
        out.put(static_cast<std::uint32_t>(s.payload->size()));
        out.put(checksum(s.payload->data(), s.payload->size()));
        out.bytes.insert(out.bytes.end(), s.payload->begin(), s.payload->end());
    }
    return std::move(out.bytes);
}

std::size_t container_size(std::initializer_list<std::size_t> payload_sizes) {
    std::size_t total = 32;
    for (std::size_t n : payload_sizes) total += 12 + n;
    return total;
}

std::uint32_t peek_version(const std::vector<std::uint8_t>& bytes, const std::string& file, const char (&magic)[8],
                           const char* kind) {
    if (bytes.size() < 8 || std::memcmp(bytes.data(), magic, 8) != 0)
        throw_error(Error::Kind::format, file, std::string("not a ") + kind + " file: bad magic bytes");
    if (bytes.size() < 12) throw_error(Error::Kind::format, file, "truncated: the file ends inside the header");
    std::uint32_t version;
    std::memcpy(&version, bytes.data() + 8, 4);
    return version;
}

std::vector<Section> read_container(const std::vector<std::uint8_t>& bytes, const std::string& file,
                                    const char (&magic)[8], const char* kind, std::initializer_list<const char*> tags) {
    std::uint32_t version = 0;
    std::vector<lodstrips::detail::Section> raw;
    std::string why;
    if (!lodstrips::detail::read_container(bytes.data(), bytes.size(), magic, kind, version, raw, &why) ||
        !lodstrips::detail::expect_sections(raw, tags.begin(), tags.size(), &why))
        throw_error(Error::Kind::format, file, why);
    std::vector<Section> out;
    for (std::size_t i = 0; i < raw.size(); ++i)
        out.push_back({raw[i].data, raw[i].size, static_cast<std::size_t>(raw[i].data - bytes.data()), tags.begin()[i]});
    return out;
}

std::vector<std::uint8_t> read_file(const std::string& path, const char* kind) {
    check_input_file(path, kind);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_error(Error::Kind::io, path, "cannot open for reading");
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw_error(Error::Kind::io, path, "read error");
    return bytes;
}

void write_file(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    AtomicFile file(path);
    file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.commit();
}

std::uint64_t legacy_fnv1a(const std::uint8_t* p, std::size_t n, std::uint64_t basis) {
    std::uint64_t h = basis;
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
    return h;
}

}  // namespace lodforge::binary
