// Helpers shared by the OBJ / glTF / image tests: scratch files, expected-error checks and mesh facts
// computed independently of the importers.
#pragma once


#include "lodforge/error.h"
#include "lodforge/mesh.h"
#include "lodforge/progress.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace lodforge::test {

// Keeps every fraction reported, to check progress is monotone and ends at 1.
struct RecordingProgress : Progress {
    std::vector<double> fractions;
    void report(double fraction, std::string_view) override { fractions.push_back(fraction); }
};

inline void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    ASSERT_TRUE(out.good()) << path;
}

inline void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    ASSERT_TRUE(out.good()) << path;
}

inline std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs `fn`, expects a lodforge::Error of `kind` whose message contains every string of `needles`.
inline void expect_error(const std::function<void()>& fn, Error::Kind kind, const std::vector<std::string>& needles) {
    try {
        fn();
        ADD_FAILURE() << "expected lodforge::Error, nothing was thrown";
    } catch (const Error& e) {
        EXPECT_EQ(static_cast<int>(e.kind()), static_cast<int>(kind)) << e.what();
        for (const std::string& needle : needles)
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
                << "message '" << e.what() << "' does not mention '" << needle << "'";
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected lodforge::Error, got std::exception: " << e.what();
    }
}

// Structural invariants of the Mesh contract that every importer must honour.
inline void expect_well_formed(const Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    ASSERT_EQ(mesh.position_ids.size(), n);
    if (mesh.has_normals()) {
        EXPECT_EQ(mesh.normals.size(), n);
    }
    if (mesh.has_colors()) {
        EXPECT_EQ(mesh.colors.size(), n);
    }
    for (const auto& set : mesh.texcoords) EXPECT_EQ(set.size(), n);
    ASSERT_EQ(mesh.indices.size() % 3, 0u);
    for (std::uint32_t i : mesh.indices) ASSERT_LT(i, n);
    if (!mesh.face_materials.empty()) {
        ASSERT_EQ(mesh.face_materials.size(), mesh.triangle_count());
        for (std::uint32_t m : mesh.face_materials) ASSERT_LT(m, mesh.materials.size());
    }
    // Stored points come first: vertex i is point i for i < point_count, wedges share their point's position.
    const std::size_t points = mesh.point_count();
    ASSERT_LE(points, n);
    for (std::size_t i = 0; i < points; ++i) ASSERT_EQ(mesh.position_ids[i], i);
    for (std::size_t i = points; i < n; ++i) {
        ASSERT_LT(mesh.position_ids[i], points);
        ASSERT_EQ(mesh.positions[i], mesh.positions[mesh.position_ids[i]]) << "wedge " << i;
    }
}

// Number of distinct (point, uv) pairs used by triangle corners.
inline std::size_t distinct_point_uv_pairs(const Mesh& mesh) {
    std::set<std::tuple<std::uint32_t, float, float>> pairs;
    for (std::uint32_t v : mesh.indices)
        pairs.emplace(mesh.position_ids[v], mesh.texcoords.at(0)[v].x, mesh.texcoords.at(0)[v].y);
    return pairs.size();
}

}  // namespace lodforge::test
