// Vertex cache metrics over index buffers: triangle lists and triangle strips (see docs/stripify.md).
//
//   double r = acmr(indices, vertex_count, 16, Primitive::strip_restart);
//
// The cache model is a FIFO of `cache_size` post-transform vertices, the model of the classic
// measurements (Hoppe 1999, Forsyth 2006) and of meshopt_analyzeVertexCache without warps: an index that
// is in the FIFO is a hit and changes nothing; a miss transforms the vertex and pushes it, evicting the
// oldest entry. Restart indices touch no cache state. Degenerate strip triangles (joins, swaps) cost their
// index fetches but are not counted as triangles.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace lodforge {

// The primitive restart index used by strip_restart buffers (GL_PRIMITIVE_RESTART_FIXED_INDEX for 32 bit).
inline constexpr std::uint32_t restart_index = 0xFFFFFFFFu;

enum class Primitive {
    triangles,         // a triangle list: three indices per triangle, all triangles count
    strip_restart,     // triangle strips separated by restart_index
    strip_degenerate,  // one strip; strips are joined by degenerate triangles
};

// Average cache miss ratio: vertex transforms per (non-degenerate) triangle; 0 when there is no triangle.
// cache_size >= 1. Indices must be < vertex_count (restart_index excepted for strip_restart); an index out
// of range throws Error(Kind::argument).
double acmr(std::span<const std::uint32_t> indices, std::size_t vertex_count, std::size_t cache_size,
            Primitive primitive = Primitive::triangles);

// Number of triangles a buffer draws, degenerate ones excluded for strips (for a triangle list: size / 3).
std::size_t drawn_triangle_count(std::span<const std::uint32_t> indices, Primitive primitive);

// Index buffer size per drawn triangle, restart indices and join indices included; 0 for no triangle.
double indices_per_triangle(std::span<const std::uint32_t> indices, Primitive primitive);

// The triangle list a strip buffer draws, degenerate triangles dropped and odd strip positions swapped
// back, so every triangle has the winding the strip gives it on the GPU. `mode` is strip_restart or
// strip_degenerate (triangles returns the input, truncated to a multiple of 3).
std::vector<std::uint32_t> expand_strips_to_triangles(std::span<const std::uint32_t> strip, Primitive mode);

}  // namespace lodforge
