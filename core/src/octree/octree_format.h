// Byte layout of the octree asset file, version 3 (specified in docs/formats/lfo.md). Private to the
// builder and the store; all fields little endian. The index (header fields and node table) is a
// container of the one binary module (io/binary_io.h) placed after the node mesh chunks, as a zip keeps
// its directory at the end: the builder streams chunks without knowing the table, and the store reads
// the index once and each chunk on demand.
#pragma once

#include "io/binary_io.h"
#include "lodforge/runtime/lodstrips_runtime.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lodforge::ooc {

inline constexpr char kAssetMagic[8] = {'L', 'F', 'O', 'C', 'T', 'R', 'E', 'E'};
inline constexpr char kAssetEndMagic[8] = {'L', 'F', 'O', 'C', 'T', 'E', 'N', 'D'};
// Version 2 added the CRC-32s; version 3 moved the header and the node table into a binary_io container
// (the index). Older files are refused with a message that says to rebuild them.
inline constexpr std::uint32_t kAssetVersion = 3;
inline constexpr std::uint32_t kNodeChunkMagic = 0x4d4e464c;  // "LFNM"

// The file starts with the magic, the version and the byte-order tag (16 bytes); node chunks follow.
inline constexpr std::size_t kAssetLeadBytes = 16;
inline std::vector<std::uint8_t> asset_lead() {
    binary::Writer lead;
    lead.bytes.assign(kAssetMagic, kAssetMagic + 8);
    lead.put(kAssetVersion);
    lead.put(lodstrips::endian_tag);
    return std::move(lead.bytes);
}
// The file ends with the index's offset and the end magic (16 bytes).
inline constexpr std::size_t kAssetFooterBytes = 16;
// Bytes of a node chunk before its arrays: magic, vertex count, triangle count, floats per vertex.
inline constexpr std::size_t kNodeChunkHeaderBytes = 16;

}  // namespace lodforge::ooc
