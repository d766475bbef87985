// The .lfmorph file: a morphing mesh with its LOD collapse sequences (format in docs/formats/lfmorph.md).
//
//   write_morph_lod("horse.lfmorph", morph, lod);          // 16-bit positions by default
//   MorphLodFile f = read_morph_lod("horse.lfmorph");      // f.morph, f.lod → extract_morph(...)
//
// Little-endian binary, versioned, with a 64-bit checksum over everything before it; written through
// AtomicFile. The reader checks every count against the file size and every index against its range,
// so truncated, corrupt or lying files give Error(format) naming the file and the section.
#pragma once

#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_lod.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace lodforge {

// 2: the tagged section container (docs/formats/lfmorph.md); version 1 files are still read.
constexpr std::uint32_t kMorphFileVersion = 2;

enum class MorphEncoding {
    float32,      // positions and normals as 32-bit floats (lossless)
    quantized16,  // positions 16 bits per axis over the sequence's bounding box, normals octahedral
                  // 2 × 16 bits (error ≤ diagonal / 2·65535 per axis, normals within ~0.003°)
};

struct MorphWriteOptions {
    MorphEncoding encoding = MorphEncoding::quantized16;
};

struct MorphFileStats {
    std::size_t header_bytes = 0;        // container, counts, levels, quantisation box
    std::size_t connectivity_bytes = 0;  // faces, point ids, base attributes
    std::size_t frame_bytes = 0;         // positions (+ normals) of one frame
    std::size_t sequence_bytes = 0;      // all collapse sequences
    std::size_t total_bytes = 0;
};
// The sizes write_morph_lod produces for these inputs (without writing).
MorphFileStats morph_file_stats(const MorphMesh& morph, const MorphLod& lod, const MorphWriteOptions& options = {});

// Throws Error(io) when the file cannot be written (nothing is left behind), Error(argument) when lod
// does not belong to morph.
void write_morph_lod(const std::string& path, const MorphMesh& morph, const MorphLod& lod,
                     const MorphWriteOptions& options = {}, Progress* progress = nullptr);

struct MorphLodFile {
    std::uint32_t version = kMorphFileVersion;
    MorphEncoding encoding = MorphEncoding::quantized16;
    MorphMesh morph;  // normals the file does not store are recomputed from the faces, per frame
    MorphLod lod;
    std::size_t file_bytes = 0;
};

MorphLodFile read_morph_lod(const std::string& path, Progress* progress = nullptr);

}  // namespace lodforge
