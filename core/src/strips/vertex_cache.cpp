// Vertex cache metrics: FIFO simulation of the post-transform cache.
//
// Hoppe, "Optimization of mesh locality for transparent vertex caching", SIGGRAPH 1999 (ACMR, FIFO model).
// Forsyth, "Linear-speed vertex cache optimisation", 2006 (the same FIFO measurement).

#include "lodforge/strips/vertex_cache.h"

#include "lodforge/error.h"

#include <string>

namespace lodforge {

namespace {

bool degenerate(std::uint32_t a, std::uint32_t b, std::uint32_t c) { return a == b || b == c || a == c; }

// Calls emit(a, b, c) for every non-degenerate triangle in drawing order, with the GPU's winding.
template <class Emit>
void for_each_triangle(std::span<const std::uint32_t> idx, Primitive primitive, Emit&& emit) {
    if (primitive == Primitive::triangles) {
        for (std::size_t i = 0; i + 2 < idx.size(); i += 3) emit(idx[i], idx[i + 1], idx[i + 2]);
        return;
    }
    std::size_t begin = 0;
    while (begin < idx.size()) {
        std::size_t end = begin;
        if (primitive == Primitive::strip_restart) {
            while (end < idx.size() && idx[end] != restart_index) ++end;
        } else {
            end = idx.size();
        }
        for (std::size_t i = begin; i + 2 < end; ++i) {
            const std::uint32_t a = idx[i], b = idx[i + 1], c = idx[i + 2];
            if (degenerate(a, b, c)) continue;
            if ((i - begin) % 2 == 0) {
                emit(a, b, c);
            } else {
                emit(b, a, c);
            }
        }
        begin = end + 1;
    }
}

}  // namespace

double acmr(std::span<const std::uint32_t> indices, std::size_t vertex_count, std::size_t cache_size,
            Primitive primitive) {
    if (cache_size == 0) throw Error(Error::Kind::argument, "acmr: cache size must be at least 1");
    // stamp[v] = the push counter value when v entered the FIFO; v is cached while pushes - stamp < size.
    std::vector<std::uint64_t> stamp(vertex_count, 0);
    std::uint64_t pushes = 0;
    std::size_t transforms = 0;
    for (std::size_t i = 0; i < indices.size(); ++i) {
        const std::uint32_t v = indices[i];
        if (primitive == Primitive::strip_restart && v == restart_index) continue;
        if (v >= vertex_count) {
            throw Error(Error::Kind::argument, "acmr: index " + std::to_string(v) + " at position " +
                                                   std::to_string(i) + " is out of range (vertex count " +
                                                   std::to_string(vertex_count) + ")");
        }
        if (stamp[v] != 0 && pushes - stamp[v] < cache_size) continue;
        ++pushes;
        stamp[v] = pushes;
        ++transforms;
    }
    const std::size_t tris = drawn_triangle_count(indices, primitive);
    return tris ? double(transforms) / double(tris) : 0.0;
}

std::size_t drawn_triangle_count(std::span<const std::uint32_t> indices, Primitive primitive) {
    if (primitive == Primitive::triangles) return indices.size() / 3;
    std::size_t n = 0;
    for_each_triangle(indices, primitive, [&](std::uint32_t, std::uint32_t, std::uint32_t) { ++n; });
    return n;
}

double indices_per_triangle(std::span<const std::uint32_t> indices, Primitive primitive) {
    const std::size_t tris = drawn_triangle_count(indices, primitive);
    return tris ? double(indices.size()) / double(tris) : 0.0;
}

std::vector<std::uint32_t> expand_strips_to_triangles(std::span<const std::uint32_t> strip, Primitive mode) {
    std::vector<std::uint32_t> out;
    out.reserve(mode == Primitive::triangles ? strip.size() : strip.size() * 3);
    for_each_triangle(strip, mode, [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        out.push_back(a);
        out.push_back(b);
        out.push_back(c);
    });
    return out;
}

}  // namespace lodforge
