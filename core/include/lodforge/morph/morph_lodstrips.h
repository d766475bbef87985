// LODStrips on a morphing mesh: one strip set for every frame, with one change set per collapse sequence
// of the MorphLod (single/naive: one; per-frame: one per keyframe) and the frames' positions and normals
// (docs/morph.md, "Morph LODStrips").
//
//   MorphLod lod = build_morph_lod(morph, {});                    // the single collapse order
//   MorphStripsBuild b = build_morph_lodstrips(morph, lod);
//   write_morph_lodstrips(b.data, "horse.lfmstrips");
//   lodstrips::MorphLodStrips rt;  rt.assign(b.data);             // morph_lodstrips_runtime.h
//   rt.set_frame(0.4);  rt.go_to_lod(0.25);                       // same faces as extract_morph(.., 0.4, 0.25)
//
// The strips are recorded from the MorphLod's own collapse sequences (not a new simplification), so the
// runtime's level for LOD factor f at time t is exactly the face set extract_morph gives for (t, f).
#pragma once

#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_file.h"
#include "lodforge/morph/morph_lod.h"
#include "lodforge/runtime/morph_lodstrips_runtime.h"
#include "lodforge/progress.h"
#include "lodforge/strips/stripify.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

struct MorphStripsParams {
    StripJoin join = StripJoin::restart;
    std::size_t max_strip_length = 256;  // strip pieces, as LodStripsParams::max_strip_length
    std::size_t cache_size = 16;
};

struct MorphStripsBuild {
    lodstrips::MorphData data;
    std::vector<std::uint32_t> canonical;     // morph vertex → vertex of the file (change set 0's numbering), UINT32_MAX if unused
    std::vector<std::uint32_t> input_vertex;  // vertex of the file → morph vertex
    std::size_t degenerate_runs = 0;          // removals recorded, all change sets
};

// Change set q records lod.sequences[q] (up to its coarsest level) in its own canonical numbering over
// the one strip set (laid out in sequence 0's numbering, the file's). Error(argument) for bad params,
// Error(invalid) for a LOD whose sequences are not increasing keyframes or disagree on the points.
MorphStripsBuild build_morph_lodstrips(const MorphMesh& morph, const MorphLod& lod, const MorphStripsParams& params = {},
                                       Progress* progress = nullptr);

struct MorphStripsStorage {
    std::size_t file_bytes = 0;
    std::size_t strips_bytes = 0;   // the embedded .lodstrips image (strips, changes, frame-0 vertices)
    std::size_t frame_bytes = 0;    // positions + normals of one frame
    std::size_t sets_bytes = 0;     // section SETS: the change sets' frames and change sets 1.. (per-frame orders)
    double bytes_per_frame = 0;     // file_bytes / frames
};

// The .lfmstrips image (format in docs/morph.md). Throws Error(invalid) for data the runtime refuses.
std::vector<std::uint8_t> encode_morph_lodstrips(const lodstrips::MorphData& data,
                                                 MorphEncoding encoding = MorphEncoding::quantized16);
MorphStripsStorage morph_lodstrips_storage(const lodstrips::MorphData& data,
                                           MorphEncoding encoding = MorphEncoding::quantized16);
// Writes through AtomicFile; Error(io) names the file.
void write_morph_lodstrips(const lodstrips::MorphData& data, const std::string& path,
                           MorphEncoding encoding = MorphEncoding::quantized16);
// Reads and decodes with the runtime's decoder; Error(io) / Error(format) name the file and the problem.
lodstrips::MorphData read_morph_lodstrips(const std::string& path);

// The mesh the runtime draws now (lodstrips_mesh of its strips: the vertex prefix of the level, every
// attribute and material, the strips' triangles) with the positions and normals of its current time.
Mesh morph_lodstrips_mesh(const lodstrips::MorphLodStrips& runtime);
// True when the file starts with the .lfmstrips magic (false when it cannot be read).
bool is_morph_lodstrips_file(const std::string& path);

}  // namespace lodforge
