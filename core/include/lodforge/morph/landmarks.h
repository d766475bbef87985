// Landmark correspondences between two meshes, given by the user to align them (issue 8, case (b):
// a supermesh from two genus-0 meshes with different connectivity; docs/morph.md).
//
// File format (`L.json`, UTF-8 JSON):
//   { "format": "lodforge-landmarks", "version": 1, "pairs": [[a0, b0], [a1, b1], ...] }
// a_i is a vertex index of mesh A and b_i one of mesh B, both as `read_mesh` returns the meshes (a wedge
// index; any wedge of a point names that point). The CLI (`lodforge morph build A B --landmarks L.json`)
// and the studio's landmark picking read and write the same file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lodforge {

struct LandmarkPair {
    std::uint32_t a = 0;  // vertex of mesh A
    std::uint32_t b = 0;  // vertex of mesh B
    bool operator==(const LandmarkPair&) const = default;
};

struct Landmarks {
    std::vector<LandmarkPair> pairs;
};

// Throws Error(io) when the file cannot be read, Error(format) naming the file and the entry when it is
// not a landmark file of a known version (bad JSON, wrong "format", negative or non-integer index, a
// pair that is not two numbers).
Landmarks read_landmarks(const std::string& path);

// Written through AtomicFile (temporary file, then rename). Throws Error(io).
void write_landmarks(const Landmarks& landmarks, const std::string& path);

// Throws Error(invalid) naming `source` and the pair when an index is out of range for the meshes'
// vertex counts or a vertex of A (or of B) appears in two pairs.
void check_landmarks(const Landmarks& landmarks, std::size_t a_vertex_count, std::size_t b_vertex_count,
                     const std::string& source);

}  // namespace lodforge
