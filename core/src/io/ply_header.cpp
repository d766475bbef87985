// PLY header: the type table, the header model, the buffered byte source and the header parser.
// Format reference: Greg Turk, "The PLY Polygon File Format" (1994), and the PLY notes of the
// Stanford 3D Scanning Repository and MeshLab/VCG (TextureFile comments, `texcoord` lists, tristrips).

#include "io/ply_internal.h"

#include "lodforge/error.h"
#include "lodforge/io/input_file.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace lodforge {

std::size_t ply_type_size(PlyType type) {
    switch (type) {
        case PlyType::int8:
        case PlyType::uint8: return 1;
        case PlyType::int16:
        case PlyType::uint16: return 2;
        case PlyType::int32:
        case PlyType::uint32:
        case PlyType::float32: return 4;
        case PlyType::float64: return 8;
        case PlyType::none: break;
    }
    return 0;
}

const char* ply_type_name(PlyType type) {
    switch (type) {
        case PlyType::int8: return "char";
        case PlyType::uint8: return "uchar";
        case PlyType::int16: return "short";
        case PlyType::uint16: return "ushort";
        case PlyType::int32: return "int";
        case PlyType::uint32: return "uint";
        case PlyType::float32: return "float";
        case PlyType::float64: return "double";
        case PlyType::none: break;
    }
    return "";
}

int PlyElement::find_property(std::string_view property_name) const {
    for (std::size_t i = 0; i < properties.size(); ++i)
        if (properties[i].name == property_name) return static_cast<int>(i);
    return -1;
}

const PlyElement* PlyHeader::find_element(std::string_view element_name) const {
    for (const PlyElement& e : elements)
        if (e.name == element_name) return &e;
    return nullptr;
}

namespace ply_detail {

PlyType parse_type(std::string_view name) {
    struct Entry {
        std::string_view name;
        PlyType type;
    };
    static constexpr Entry table[] = {
        {"char", PlyType::int8},       {"int8", PlyType::int8},       {"uchar", PlyType::uint8},
        {"uint8", PlyType::uint8},     {"short", PlyType::int16},     {"int16", PlyType::int16},
        {"ushort", PlyType::uint16},   {"uint16", PlyType::uint16},   {"int", PlyType::int32},
        {"int32", PlyType::int32},     {"uint", PlyType::uint32},     {"uint32", PlyType::uint32},
        {"float", PlyType::float32},   {"float32", PlyType::float32}, {"double", PlyType::float64},
        {"float64", PlyType::float64},
    };
    for (const Entry& e : table)
        if (e.name == name) return e.type;
    return PlyType::none;
}

std::string show(std::string_view token) {
    constexpr std::size_t kMax = 40;
    std::string out = "'";
    for (char c : token.substr(0, kMax)) out += (static_cast<unsigned char>(c) < 32 || c == 127) ? '?' : c;
    if (token.size() > kMax) out += "...";
    return out + "'";
}

// ---- Input --------------------------------------------------------------------------------------

namespace {
std::atomic<std::size_t> g_buffer_size{std::size_t(1) << 20};  // large sequential reads, bounded memory

bool seek(std::FILE* f, std::uint64_t offset) {
#ifdef _WIN32
    return _fseeki64(f, static_cast<long long>(offset), SEEK_SET) == 0;
#else
    return fseeko(f, static_cast<off_t>(offset), SEEK_SET) == 0;
#endif
}
}  // namespace

void set_file_buffer_size(std::size_t bytes) { g_buffer_size.store(bytes, std::memory_order_relaxed); }

Input::~Input() {
    if (file_) std::fclose(file_);
}

void Input::open_file(const std::string& path) {
    namespace fs = std::filesystem;
    path_ = path;
    check_input_file(path, "a PLY file");
    std::error_code ec;
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) throw_error(Error::Kind::io, path, std::string("cannot open: ") + std::strerror(errno));
    const auto size = fs::file_size(path, ec);
    if (ec) throw_error(Error::Kind::io, path, "cannot read the file size: " + ec.message());
    size_ = size;
    storage_.resize(std::max<std::size_t>(1, g_buffer_size.load(std::memory_order_relaxed)));
    start_ = cur = lim = storage_.data();
    base_ = 0;
}

void Input::open_memory(const char* data, std::size_t size) {
    start_ = cur = data;
    lim = data + size;
    base_ = 0;
    size_ = size;
}

bool Input::refill(std::size_t n) {
    if (!file_) return false;  // memory: everything is already in the window
    const std::uint64_t here = offset();
    const std::uint64_t left = size_ > here ? size_ - here : 0;
    // Never grow the buffer past what the file can still deliver (a lying count asks for terabytes).
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(n, left));
    const std::size_t keep = static_cast<std::size_t>(lim - cur);
    if (want > storage_.size()) {
        std::vector<char> bigger(std::max(want, storage_.size() * 2));
        std::memcpy(bigger.data(), cur, keep);
        storage_.swap(bigger);
    } else if (keep) {
        std::memmove(storage_.data(), cur, keep);
    }
    base_ = here;
    start_ = cur = storage_.data();
    lim = cur + keep;
    char* end = storage_.data() + storage_.size();
    while (static_cast<std::size_t>(lim - cur) < want) {
        const std::size_t got = std::fread(const_cast<char*>(lim), 1, static_cast<std::size_t>(end - lim), file_);
        if (got == 0) {
            if (std::ferror(file_))
                throw_error(Error::Kind::io, path_,
                            "read error at byte " + std::to_string(base_ + (lim - start_)) + ": " +
                                std::strerror(errno));
            size_ = base_ + static_cast<std::uint64_t>(lim - start_);  // the file shrank under us
            break;
        }
        lim += got;
    }
    return static_cast<std::size_t>(lim - cur) >= n;
}

bool Input::skip(std::uint64_t n) {
    const auto in_window = static_cast<std::uint64_t>(lim - cur);
    if (n <= in_window) {
        cur += n;
        return true;
    }
    const std::uint64_t target = offset() + n;
    if (!file_ || target > size_) {
        cur = lim;
        if (file_) {
            base_ = size_;
            start_ = cur = lim = storage_.data();
        }
        return false;
    }
    if (!seek(file_, target))
        throw_error(Error::Kind::io, path_, "cannot seek to byte " + std::to_string(target));
    base_ = target;
    start_ = cur = lim = storage_.data();
    return true;
}

// ---- Header parser --------------------------------------------------------------------------------

namespace {

constexpr std::size_t kMaxHeaderLine = 64 * 1024;
constexpr std::uint64_t kMaxHeaderBytes = 16u << 20;

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
    return s;
}

// Splits off the first whitespace-separated word of `s`.
std::string_view next_word(std::string_view& s) {
    s = trim(s);
    std::size_t n = 0;
    while (n < s.size() && !is_blank(s[n])) ++n;
    std::string_view word = s.substr(0, n);
    s.remove_prefix(n);
    return word;
}

class HeaderParser {
public:
    explicit HeaderParser(Input& in) : in_(in) {}

    PlyHeader run() {
        if (in_.size() == 0) fail_at_start("empty file");
        in_.prefetch(4);
        const auto avail = static_cast<std::size_t>(in_.lim - in_.cur);
        if (avail < 3 || std::memcmp(in_.cur, "ply", 3) != 0 ||
            (avail > 3 && in_.cur[3] != '\n' && in_.cur[3] != '\r'))
            fail_at_start("not a PLY file (it does not start with the line 'ply')");
        std::string_view first;
        if (!next_line(first) || trim(first) != "ply") fail("the header has no end_header line");
        bool have_format = false;
        PlyElement* element = nullptr;
        for (;;) {
            std::string_view line;
            if (!next_line(line)) fail("the header has no end_header line");
            std::string_view rest = line;
            const std::string_view keyword = next_word(rest);
            if (keyword.empty()) continue;
            if (keyword == "end_header") {
                if (!have_format) fail("the header has no format line");
                header_.data_offset = in_.offset();
                header_.header_lines = line_;
                return std::move(header_);
            }
            if (keyword == "comment") {
                comment(rest);
            } else if (keyword == "obj_info") {
                header_.obj_info.emplace_back(trim(rest));
            } else if (keyword == "format") {
                if (have_format) fail("a second format line");
                format(rest);
                have_format = true;
            } else if (keyword == "element") {
                if (!have_format) fail("element before the format line");
                element = add_element(rest);
            } else if (keyword == "property") {
                if (!element) fail("property before any element");
                add_property(*element, rest);
            } else {
                fail("unknown header keyword " + show(keyword));
            }
        }
    }

private:
    [[noreturn]] void fail(const std::string& what) {
        throw_error(Error::Kind::format, in_.path(), "header line " + std::to_string(line_) + ": " + what);
    }
    [[noreturn]] void fail_at_start(const std::string& what) {
        throw_error(Error::Kind::format, in_.path(), what);
    }

    // The next line without its terminator; false at the end of the data.
    bool next_line(std::string_view& line) {
        if (in_.offset() > kMaxHeaderBytes) fail("the header is larger than 16 MiB (no end_header?)");
        in_.prefetch(kMaxHeaderLine);
        const char* nl = static_cast<const char*>(std::memchr(in_.cur, '\n', static_cast<std::size_t>(in_.lim - in_.cur)));
        if (!nl) {
            if (static_cast<std::size_t>(in_.lim - in_.cur) >= kMaxHeaderLine) {
                ++line_;
                fail("line longer than 64 KiB (binary data before end_header?)");
            }
            return false;  // the data ends inside the header
        }
        line = std::string_view(in_.cur, static_cast<std::size_t>(nl - in_.cur));
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        in_.cur = nl + 1;
        ++line_;
        return true;
    }

    void comment(std::string_view rest) {
        rest = trim(rest);
        header_.comments.emplace_back(rest);
        std::string_view words = rest;
        if (next_word(words) == "TextureFile") {
            const std::string_view file = trim(words);
            if (!file.empty()) header_.texture_files.emplace_back(file);
        }
    }

    void format(std::string_view rest) {
        const std::string_view name = next_word(rest);
        const std::string_view version = next_word(rest);
        if (name == "ascii") header_.format = PlyEncoding::ascii;
        else if (name == "binary_little_endian") header_.format = PlyEncoding::binary_little_endian;
        else if (name == "binary_big_endian") header_.format = PlyEncoding::binary_big_endian;
        else fail("unknown format " + show(name) + " (expected ascii, binary_little_endian or binary_big_endian)");
        if (version.empty() || version.front() != '1')
            fail("unsupported PLY version " + show(version) + " (expected 1.0)");
        if (!trim(rest).empty()) fail("unexpected " + show(trim(rest)) + " after the format version");
        header_.version = std::string(version);
    }

    PlyElement* add_element(std::string_view rest) {
        const std::string_view name = next_word(rest);
        const std::string_view count = next_word(rest);
        if (name.empty() || count.empty()) fail("expected 'element <name> <count>'");
        std::uint64_t n = 0;
        const auto r = std::from_chars(count.data(), count.data() + count.size(), n);
        if (r.ec != std::errc() || r.ptr != count.data() + count.size())
            fail("bad count " + show(count) + " for element " + show(name));
        if (!trim(rest).empty()) fail("unexpected " + show(trim(rest)) + " after the element count");
        for (const PlyElement& e : header_.elements)
            if (e.name == name) fail("element " + show(name) + " declared twice");
        PlyElement& e = header_.elements.emplace_back();
        e.name = std::string(name);
        e.count = n;
        return &e;
    }

    PlyType type_of(std::string_view word) {
        if (word.empty()) fail("expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
        const PlyType t = parse_type(word);
        if (t == PlyType::none) fail("unknown type " + show(word));
        return t;
    }

    void add_property(PlyElement& element, std::string_view rest) {
        PlyProperty p;
        std::string_view word = next_word(rest);
        if (word == "list") {
            p.count_type = type_of(next_word(rest));
            if (!is_integer(p.count_type))
                fail("list count type " + std::string(ply_type_name(p.count_type)) + " is not an integer type");
            word = next_word(rest);
        }
        p.type = type_of(word);
        const std::string_view name = next_word(rest);
        if (name.empty()) fail("property without a name");
        if (!trim(rest).empty()) fail("unexpected " + show(trim(rest)) + " after property " + show(name));
        if (element.find_property(name) >= 0)
            fail("property " + show(name) + " declared twice in element " + show(element.name));
        p.name = std::string(name);
        element.properties.push_back(std::move(p));
    }

    Input& in_;
    PlyHeader header_;
    std::uint64_t line_ = 0;
};

}  // namespace

PlyHeader parse_header(Input& in) { return HeaderParser(in).run(); }

}  // namespace ply_detail
}  // namespace lodforge
