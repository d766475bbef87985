// Byte layout of the octree asset file, version 2 (specified in docs/formats/lfo.md). Private
// to the builder and the store; all fields little endian.
#pragma once

#include "lodforge/runtime/lodstrips_runtime.h"

#include <cstdint>
#include <span>

namespace lodforge::ooc {

inline constexpr char kAssetMagic[8] = {'L', 'F', 'O', 'C', 'T', 'R', 'E', 'E'};
inline constexpr char kAssetEndMagic[8] = {'L', 'F', 'O', 'C', 'T', 'E', 'N', 'D'};
// Version 2 added the CRC-32s (header, node table, every node chunk); version 1 files had none, so a
// flipped byte went unnoticed, and are refused with a message that says to rebuild them.
inline constexpr std::uint32_t kAssetVersion = 2;
inline constexpr std::uint32_t kNodeChunkMagic = 0x4d4e464c;  // "LFNM"

struct AssetHeader {
    char magic[8];
    std::uint32_t version;
    std::uint32_t layout;  // VertexLayout::flags()
    std::uint64_t input_vertices;
    std::uint64_t input_triangles;
    std::uint32_t max_triangles;
    std::uint32_t max_depth;
    float bounds[6];       // min xyz, max xyz
    float root_min[3];
    float root_size;
    std::uint64_t node_count;
    std::uint64_t table_offset;
    float weights[3];      // normal, color, texcoord
    std::uint32_t table_crc;   // CRC-32 of the node table
    std::uint32_t header_crc;  // CRC-32 of these 128 bytes with header_crc = 0
    std::uint8_t pad[12];
};
static_assert(sizeof(AssetHeader) == 128);

struct AssetFooter {
    std::uint64_t table_offset;
    char magic[8];
};
static_assert(sizeof(AssetFooter) == 16);

struct NodeChunkHeader {
    std::uint32_t magic;
    std::uint32_t vertices;
    std::uint32_t triangles;
    std::uint32_t floats;
};

// CRC-32 of an asset's header, node table or chunk: the checksum of the LODStrips formats.
inline std::uint32_t chunk_crc(std::span<const char> bytes) {
    return lodstrips::detail::crc32(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace lodforge::ooc
