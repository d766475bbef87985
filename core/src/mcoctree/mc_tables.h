// Marching-cube tables of the octree (internal): the 3x3x3 sample lattice of a node, the 60 sub-edges on
// its boundary, and the one triangulation rule every node at every level uses (docs/mcoctree.md, "Tables").
#pragma once

#include <array>
#include <cstdint>

namespace lodforge::mc {

// Samples of a node: s = i + 3j + 9k, i, j, k in {0, 1, 2} (0 and 2 are the node's corners).
constexpr int sample_index(int i, int j, int k) { return i + 3 * j + 9 * k; }
// Corner c (bit 0 = +x, bit 1 = +y, bit 2 = +z) as a sample.
constexpr int corner_sample(int c) { return sample_index((c & 1) * 2, ((c >> 1) & 1) * 2, ((c >> 2) & 1) * 2); }

constexpr int full_edges = 12;     // ids 0..11: the node's edges (edge e: axis e / 4)
constexpr int sub_edge_count = 60; // 12..35: half edges (12 + 2e lower half, 13 + 2e upper), 36..59:
                                   // face-interior edges (36 + 4f + k, from face centre f outwards)
constexpr int max_triangles = 64;

struct SubEdge {
    std::uint8_t a = 0, b = 0;  // samples, a below b along `axis`
    std::uint8_t axis = 0;
    std::uint8_t length = 0;    // 2 = a full edge, 1 = half the node size
};
const std::array<SubEdge, sub_edge_count>& sub_edges();

// Neighbour slots of a node (McOctree::neighbours): 6 faces (f = 2 * axis + (side is +)), then 12 edges
// (6 + e: the cube across edge e). Offsets in units of the node size.
constexpr int neighbour_slots = 18;
std::array<int, 3> neighbour_offset_of(int slot);
inline const std::array<int, 3>& neighbour_offset(int slot) {
    static const std::array<std::array<int, 3>, neighbour_slots> table = [] {
        std::array<std::array<int, 3>, neighbour_slots> t{};
        for (int s = 0; s < neighbour_slots; ++s) t[std::size_t(s)] = neighbour_offset_of(s);
        return t;
    }();
    return table[std::size_t(slot)];
}

// Refinement of a node's boundary: bit e (0..11) = edge e is split at its midpoint; bit 12 + f = face f
// is split into 4 (its edges must be split too). A refined part is shared with a node one level finer.
constexpr std::uint32_t face_bit(int f) { return 1u << (12 + f); }
// The edge bits a refined face implies.
std::uint32_t face_edges_mask(int f);
// The three neighbour slots around edge e (two faces and the edge slot).
std::array<int, 3> edge_neighbour_slots(int e);

// Triangulates a node: `inside` has bit s set for inside samples (only the samples the refinement uses
// are read), `refine` as above. Writes triangles as sub-edge id triples, counter-clockwise seen from
// outside; returns the triangle count. Integer work only.
int triangulate(std::uint32_t inside, std::uint32_t refine, std::uint8_t* out_sub_edges);

// The same for an unrefined node, by corner configuration (bit c = corner c inside): the classic table.
struct CaseTable {
    std::array<std::uint8_t, 256> count{};
    std::array<std::array<std::uint8_t, 3 * 12>, 256> edges{};  // full-edge ids 0..11
};
const CaseTable& case_table();

// Corner configuration (8 bits) from a 27-sample mask (corner samples 0, 2, 6, 8, 18, 20, 24, 26).
inline std::uint32_t corner_config(std::uint32_t inside) {
    return (inside & 1u) | ((inside >> 1) & 2u) | ((inside >> 4) & 4u) | ((inside >> 5) & 8u) |
           ((inside >> 14) & 16u) | ((inside >> 15) & 32u) | ((inside >> 18) & 64u) | ((inside >> 19) & 128u);
}

}  // namespace lodforge::mc
