// Checksums of the own formats recomputed over edited bytes, as the author of a crafted file would.
// The fuzzers seal every input with these before the reader sees it: otherwise almost every mutation of
// a .lodstrips, .lfmstrips, .mco, .lfmorph or .lfo stops at a CRC-32 or FNV mismatch and the fuzzers
// would test only the checksum, not the decoding and validation behind it. Tests use them to build
// files that are damaged but correctly summed. (The checksum checks themselves: the unit tests and
// CliBadFiles, with flipped bytes.) Needs core/src on the include path.
#pragma once

#include "io/binary_io.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/runtime/lodstrips_runtime.h"
#include "octree/octree_format.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace lodforge::test {

inline std::uint32_t seal_u32(const std::string& b, std::size_t at) {
    std::uint32_t v = 0;
    if (at + 4 <= b.size()) std::memcpy(&v, b.data() + at, 4);
    return v;
}

inline void seal_put_u32(std::string& b, std::size_t at, std::uint32_t v) {
    if (at + 4 <= b.size()) std::memcpy(b.data() + at, &v, 4);
}

inline std::uint32_t seal_crc(const std::string& b, std::size_t at, std::size_t n) {
    return lodstrips::detail::crc32(reinterpret_cast<const std::uint8_t*>(b.data()) + at, n);
}

// The section container (docs/formats): header CRC over bytes 0..20, the file size at 24, then per
// section a tag, a length and the CRC of its payload. Sections that do not fit are left as they are.
inline void seal_container(std::string& b) {
    if (b.size() < 32) return;
    const std::uint64_t size = b.size();
    seal_put_u32(b, 24, static_cast<std::uint32_t>(size));
    seal_put_u32(b, 28, static_cast<std::uint32_t>(size >> 32));
    seal_put_u32(b, 20, seal_crc(b, 0, 20));
    std::size_t at = 32;
    for (std::uint32_t i = 0, count = seal_u32(b, 16); i < count && at + 12 <= b.size(); ++i) {
        const std::size_t len = seal_u32(b, at + 4);
        if (len > b.size() - at - 12) return;
        seal_put_u32(b, at + 8, seal_crc(b, at + 12, len));
        at += 12 + len;
    }
}

// The formats before the container (.mco 2, .lfmorph 1): a 64-bit FNV-1a of everything before it at the end.
inline void seal_flat(std::string& b, std::uint64_t basis) {
    if (b.size() < 20) return;
    const std::size_t body = b.size() - 8;
    const std::uint64_t h = binary::legacy_fnv1a(reinterpret_cast<const std::uint8_t*>(b.data()), body, basis);
    std::memcpy(b.data() + body, &h, 8);
}

// A container file, or the flat form when the version field says `flat_version`.
inline void seal_own_format(std::string& b, std::uint32_t flat_version, std::uint64_t basis) {
    if (b.size() >= 12 && seal_u32(b, 8) == flat_version)
        seal_flat(b, basis);
    else
        seal_container(b);
}

// The octree asset (version 3): the footer locates the index, a container whose NODE section holds the
// node records; every node chunk's CRC that lies inside the file, then the index's own CRCs.
inline void seal_lfo(std::string& b) {
    const std::uint64_t size = b.size();
    if (size < ooc::kAssetLeadBytes + ooc::kAssetFooterBytes + 32) return;
    const std::uint64_t end = size - ooc::kAssetFooterBytes;
    std::uint64_t index = 0;
    std::memcpy(&index, b.data() + end, 8);
    if (index < ooc::kAssetLeadBytes || index > end || end - index < 32) return;
    std::string c = b.substr(index, end - index);
    const auto inside = [&](std::uint64_t offset, std::uint64_t bytes) { return bytes <= size && offset <= size - bytes; };
    std::size_t at = 32;
    for (std::uint32_t i = 0, count = seal_u32(c, 16); i < count && at + 12 <= c.size(); ++i) {
        const std::size_t len = seal_u32(c, at + 4);
        if (len > c.size() - at - 12) break;
        if (std::memcmp(c.data() + at, "NODE", 4) == 0) {
            for (std::size_t r = at + 12; r + sizeof(OctreeNode) <= at + 12 + len; r += sizeof(OctreeNode)) {
                OctreeNode d;
                std::memcpy(&d, c.data() + r, sizeof d);
                if (inside(d.mesh_offset, d.mesh_bytes)) d.mesh_crc = seal_crc(b, d.mesh_offset, d.mesh_bytes);
                if (inside(d.raw_offset, d.raw_bytes)) d.raw_crc = seal_crc(b, d.raw_offset, d.raw_bytes);
                std::memcpy(c.data() + r, &d, sizeof d);
            }
        }
        at += 12 + len;
    }
    seal_container(c);
    b.replace(index, c.size(), c);
}

}  // namespace lodforge::test
