// The parallel parse of an ASCII PLY element, for readers that consume a huge element in file order
// (the out-of-core soup, core/src/octree/ooc_soup.cpp). Private to the core.
//
// ASCII PLY records are one per line (blank lines may separate them), so the rest of an element can be
// cut into segments of whole lines by counting non-blank lines, which costs little next to parsing their
// numbers. A helper thread counts ahead and parses every second segment with a reader of its own
// (PlyReader::seek_ascii_record); this thread parses the others and consumes all of them in file order,
// so everything downstream is the same as with one reader. The helper never reports an error: where it
// cannot parse a segment, or the data ends early, this thread is left at the start of that segment and
// reads on by itself, with the message and line number one reader gives.
#pragma once

#include "io/ply_internal.h"

#include "lodforge/error.h"
#include "lodforge/io/ply.h"

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace lodforge::ply_detail {

struct Unit {};  // a slot that carries nothing

struct AsciiSegment {
    std::uint64_t begin = 0, line = 0;  // byte offset of its first line and the newlines before it
    std::uint64_t end = 0, end_line = 0;
    std::uint64_t first = 0, count = 0;  // records
};

// Parses the rest of the reader's current element. `parse(reader, segment, slot)` reads the segment's
// records into `slot` (either thread); `consume(slot, segment)` runs here, in file order. Returns with
// the reader after the element, or at the first record it must read alone.
template <class Slot, class Parse, class Consume>
void parse_ascii_in_two(PlyReader& reader, const std::string& path, std::size_t segment_bytes, Parse parse, Consume consume) {
    const PlyHeader& header = reader.header();
    const std::size_t element = static_cast<std::size_t>(reader.current_element() - header.elements.data());
    const std::uint64_t total = header.elements[element].count;
    std::mutex mutex;
    std::condition_variable changed;
    std::vector<AsciiSegment> segments;                      // counted so far
    std::size_t alone_from = std::numeric_limits<std::size_t>::max();  // segments this thread reads alone
    bool counted_all = false;
    std::optional<Slot> handed;  // the helper's parsed segment, not consumed yet
    std::size_t handed_index = 0;
    bool stop = false;
    const std::uint64_t start = reader.position(), start_line = reader.line(), start_record = total - reader.remaining();

    std::thread helper([&] {
        std::size_t j = 0;
        try {
            ply_detail::Input file;
            file.open_file(path);
            const std::uint64_t size = file.size();
            PlyReader own(path);
            if (!file.skip(start)) throw Error(Error::Kind::format, path + ": the data ends before the element");
            const char* buffer = nullptr;
            std::uint64_t pos = start, line = start_line, record = start_record;
            std::uint64_t have = 0, at = start;  // buffer holds [at, at + have)
            bool in_line_blank = true;           // the line being scanned has only blanks so far
            while (record < total) {
                AsciiSegment s{pos, line, 0, 0, record, 0};
                bool ended = false;  // the data ended before `total` records
                for (bool full = false; !full;) {
                    if (pos == at + have) {
                        if (pos >= size) {
                            if (!in_line_blank) ++s.count, ++record, in_line_blank = true;  // a last line without '\n'
                            ended = record < total;
                            break;
                        }
                        // The window read before is used up: the input's next byte is `pos`.
                        if (buffer) file.cur = buffer + have;
                        file.prefetch(std::size_t{1} << 20);
                        if (file.cur == file.lim) throw Error(Error::Kind::format, path + ": truncated");
                        at = pos;
                        buffer = file.cur;
                        have = static_cast<std::uint64_t>(file.lim - file.cur);
                    }
                    // Line by line (memchr finds the ends); a line counts when it has a non-blank byte.
                    const char* const lim = buffer + have;
                    for (const char* p = buffer + (pos - at); p < lim;) {
                        if (in_line_blank) {
                            while (p < lim && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\f' || *p == '\v')) ++p;
                            if (p == lim) break;
                            if (*p != '\n') in_line_blank = false;
                        }
                        const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(lim - p)));
                        if (!nl) {
                            p = lim;
                            break;
                        }
                        p = nl + 1;
                        ++line;
                        if (!in_line_blank) {
                            ++s.count;
                            ++record;
                            in_line_blank = true;
                            if (record == total || static_cast<std::uint64_t>(p - buffer) + at - s.begin >= segment_bytes) {
                                pos = at + static_cast<std::uint64_t>(p - buffer);
                                full = true;
                                break;
                            }
                        }
                    }
                    if (!full) pos = at + have;
                }
                if (ended) break;  // this thread reads the short tail itself, and reports it
                s.end = pos;
                s.end_line = line;
                {
                    std::lock_guard lock(mutex);
                    segments.push_back(s);
                }
                changed.notify_all();
                if (j % 2 == 1) {
                    Slot slot;
                    own.seek_ascii_record(element, s.first, s.begin, s.line);
                    parse(own, s, slot);
                    std::unique_lock lock(mutex);
                    changed.wait(lock, [&] { return !handed || stop; });
                    if (stop) return;
                    handed.emplace(std::move(slot));
                    handed_index = j;
                    changed.notify_all();
                }
                ++j;
            }
        } catch (...) {
        }
        std::lock_guard lock(mutex);
        alone_from = std::min(alone_from, j);
        counted_all = true;
        changed.notify_all();
    });
    struct Join {
        std::mutex& m;
        std::condition_variable& c;
        bool& stop;
        std::thread& t;
        ~Join() {
            {
                std::lock_guard lock(m);
                stop = true;
            }
            c.notify_all();
            t.join();
        }
    } join{mutex, changed, stop, helper};

    for (std::size_t j = 0;; ++j) {
        AsciiSegment s;
        {
            std::unique_lock lock(mutex);
            changed.wait(lock, [&] { return segments.size() > j || counted_all; });
            if (j >= alone_from || j >= segments.size()) return;  // read alone from here (or done)
            s = segments[j];
            if (j % 2 == 1) {
                changed.wait(lock, [&] { return (handed && handed_index == j) || j >= alone_from; });
                if (!handed || handed_index != j) return;
            }
        }
        if (j % 2 == 0) {
            Slot slot;
            parse(reader, s, slot);
            consume(slot, s);
        } else {
            Slot slot = std::move(*handed);
            {
                std::lock_guard lock(mutex);
                handed.reset();
            }
            changed.notify_all();
            reader.seek_ascii_record(element, s.first + s.count, s.end, s.end_line);
            consume(slot, s);
        }
    }
}

}  // namespace lodforge::ply_detail
