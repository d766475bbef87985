// The marching-cube table derived from the face rule: every case closes, neighbouring cubes agree.
#include "mcoctree/mc_tables.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

using namespace lodforge::mc;

namespace {

std::uint32_t corners_to_inside(std::uint32_t config) {
    std::uint32_t inside = 0;
    for (int c = 0; c < 8; ++c)
        if (config & (1u << c)) inside |= 1u << corner_sample(c);
    return inside;
}

// Every sub-edge of a triangulation that lies on the cube's boundary must be covered: each loop edge
// appears once per direction across the fan, so directed edges between distinct sub-edges pair up except
// for the loop (boundary) edges, which must form closed cycles visiting each crossing exactly once.
void expect_closed_loops(std::uint32_t inside, std::uint32_t refine, const std::set<int>& crossings) {
    std::uint8_t buf[3 * max_triangles];
    const int n = triangulate(inside, refine, buf);
    std::map<std::pair<int, int>, int> directed;
    std::set<int> used;
    for (int t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) {
            ++directed[{buf[3 * t + k], buf[3 * t + (k + 1) % 3]}];
            used.insert(buf[3 * t + k]);
        }
    // A loop of two crossings (both halves of one split edge, cut off on both faces) has no triangle: the
    // finer neighbours on those faces share the segment directly. Every other crossing is used.
    for (int v : crossings) {
        if (used.count(v)) continue;
        const bool half = v >= 12 && v < 36;
        const int other = half ? (((v - 12) % 2) ? v - 1 : v + 1) : -1;
        EXPECT_TRUE(half && crossings.count(other) && !used.count(other)) << "crossing " << v << " unused";
    }
    for (int v : used) EXPECT_TRUE(crossings.count(v)) << "sub-edge " << v << " does not cross";
    std::map<int, int> out_degree;
    for (const auto& [e, c] : directed) {
        const int back = directed.count({e.second, e.first}) ? directed[{e.second, e.first}] : 0;
        if (back == 0) out_degree[e.first] += c;  // boundary edge of the fan
        else EXPECT_EQ(back, c);
    }
    for (int v : used) EXPECT_EQ(out_degree[v], 1) << "crossing " << v << " inside " << inside;
}

}  // namespace

TEST(McTables, EveryCaseTriangulatesExactlyItsCrossingEdges) {
    const CaseTable& table = case_table();
    EXPECT_EQ(table.count[0], 0);
    EXPECT_EQ(table.count[255], 0);
    EXPECT_EQ(table.count[1], 1);
    EXPECT_EQ(table.count[0x0f], 2);  // a plane cutting four parallel edges
    for (std::uint32_t c = 1; c < 255; ++c) {
        const std::uint32_t inside = corners_to_inside(c);
        std::set<int> crossings;
        for (int e = 0; e < full_edges; ++e)
            if (((inside >> sub_edges()[e].a) & 1u) != ((inside >> sub_edges()[e].b) & 1u)) crossings.insert(e);
        expect_closed_loops(inside, 0, crossings);
    }
}

TEST(McTables, ComplementaryFacesAgreeBetweenNeighbours) {
    // Two cubes sharing a face see the same four samples; the segments they put on it must be the same
    // pairs of crossings (the ambiguous diagonal face included), or the surface tears along the face.
    std::uint8_t buf[3 * max_triangles];
    for (std::uint32_t c = 1; c < 255; ++c) {
        for (std::uint32_t d = 1; d < 255; ++d) {
            // cube A's +x face (corners 1,3,5,7) equals cube B's -x face (corners 0,2,4,6)
            bool same = true;
            for (int k = 0; k < 4; ++k) {
                const int a = 1 + 2 * k, b = 2 * k;
                same &= ((c >> a) & 1u) == ((d >> b) & 1u);
            }
            if (!same || (d & 0x55) != ((c & 0xaa) >> 1)) continue;
            // collect segments on the shared face as pairs of (y, z) edge positions
            auto face_pairs = [&](std::uint32_t config, int x_side) {
                std::set<std::pair<int, int>> pairs;
                const int n = triangulate(corners_to_inside(config), 0, buf);
                std::map<std::pair<int, int>, int> directed;
                for (int t = 0; t < n; ++t)
                    for (int k = 0; k < 3; ++k) ++directed[{buf[3 * t + k], buf[3 * t + (k + 1) % 3]}];
                for (const auto& [e, cnt] : directed) {
                    if (directed.count({e.second, e.first})) continue;
                    const SubEdge& a = sub_edges()[e.first];
                    const SubEdge& b = sub_edges()[e.second];
                    auto on_face = [&](const SubEdge& s) { return s.axis != 0 && (s.a % 3) == 2 * x_side; };
                    if (!on_face(a) || !on_face(b)) continue;
                    // the same face edge, named by its samples' y and z (x dropped)
                    const int ka = (a.a / 3) * 100 + (a.b / 3), kb = (b.a / 3) * 100 + (b.b / 3);
                    pairs.insert({std::min(ka, kb), std::max(ka, kb)});
                }
                return pairs;
            };
            EXPECT_EQ(face_pairs(c, 1), face_pairs(d, 0)) << c << " / " << d;
        }
    }
}

TEST(McTables, RefinedFacesCloseToo) {
    // Random refinements and samples: every crossing on the refined boundary is in exactly one loop.
    std::uint32_t seed = 12345;
    auto rnd = [&] { return seed = seed * 1664525u + 1013904223u; };
    for (int it = 0; it < 20000; ++it) {
        std::uint32_t refine = 0;
        for (int f = 0; f < 6; ++f)
            if ((rnd() >> 7) % 4 == 0) refine |= face_bit(f) | face_edges_mask(f);
        for (int e = 0; e < full_edges; ++e)
            if ((rnd() >> 9) % 3 == 0) refine |= 1u << e;
        const std::uint32_t inside = (rnd() ^ (rnd() << 13)) & 0x7ffffff & ~(1u << 13);
        // which samples the refinement uses, and so which sub-edges can cross
        std::set<int> crossings;
        for (int s = 0; s < sub_edge_count; ++s) {
            const SubEdge& se = sub_edges()[s];
            bool used = false;
            if (s < 12) {
                used = !(refine & (1u << s));
            } else if (s < 36) {
                used = refine & (1u << ((s - 12) / 2));
            } else {
                used = refine & face_bit((s - 36) / 4);
            }
            if (used && ((inside >> se.a) & 1u) != ((inside >> se.b) & 1u)) crossings.insert(s);
        }
        expect_closed_loops(inside, refine, crossings);
        if (HasFailure()) return;
    }
}

TEST(McTables, CornerConfigReadsTheEightCornerSamples) {
    for (std::uint32_t c = 0; c < 256; ++c) {
        EXPECT_EQ(corner_config(corners_to_inside(c)), c);
        // the other samples do not leak into the configuration
        EXPECT_EQ(corner_config(corners_to_inside(c) | (0x7ffffffu & ~corners_to_inside(255))), c);
    }
}
