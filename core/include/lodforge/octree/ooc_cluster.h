// Out-of-core vertex clustering on a uniform grid (Lindstrom's OoCS), the fast second mode of
// `lodforge octree build --mode cluster` (docs/octree.md, "OoCS mode").
//
//     OocClusterResult r = ooc_cluster("scan.ply", {.grid_resolution = 256, .memory_bytes = 64 << 20});
//     write_ply(r.mesh, "scan_lod.ply");
//
// One pass over the triangle soup: per occupied cell a plane quadric and area-weighted attribute sums;
// a triangle survives when its corners fall in three different cells (once per cell triple). Memory is
// proportional to the output (occupied cells and surviving triangles), not to the input.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/octree/ooc_soup.h"
#include "lodforge/progress.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace lodforge {

struct OocClusterParams {
    std::size_t grid_resolution = 256;  // cells along the longest side of the bounding box (2 .. 2^20)
    std::size_t memory_bytes = std::size_t{256} << 20;  // for the soup conversion
    std::string temp_dir;               // empty: the system temporary directory
};

struct OocClusterResult {
    Mesh mesh;
    SoupResult soup;
    std::uint64_t input_triangles = 0;
    std::size_t occupied_cells = 0;
    std::uint32_t grid_dims[3] = {0, 0, 0};
    float cell_size = 0;
};

// Optional profile of a run (not part of the result).
struct OocClusterStats {
    double soup_seconds = 0;     // PLY → soup (0 for ooc_cluster_soup)
    double cluster_seconds = 0;  // soup → mesh
};

// Throws Error(argument) for a resolution outside [2, 2^20], Error(io / format / invalid) for the input,
// Error(cancelled). Temporary files are removed in every case.
OocClusterResult ooc_cluster(const std::string& input_ply, const OocClusterParams& params = {},
                             Progress* progress = nullptr, OocClusterStats* stats = nullptr);

// The same over a soup that already exists (the benchmark times the two steps separately).
OocClusterResult ooc_cluster_soup(const std::string& soup_path, const OocClusterParams& params = {},
                                  Progress* progress = nullptr, OocClusterStats* stats = nullptr);

}  // namespace lodforge
