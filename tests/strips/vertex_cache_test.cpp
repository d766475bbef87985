#include "lodforge/error.h"
#include "lodforge/strips/vertex_cache.h"

#include <gtest/gtest.h>

#include <vector>

using namespace lodforge;

namespace {
constexpr std::uint32_t R = restart_index;
using Idx = std::vector<std::uint32_t>;
}  // namespace

TEST(VertexCache, AcmrOfAStripCountsEachVertexOnce) {
    const Idx strip = {0, 1, 2, 3, 4, 5};  // 4 triangles, 6 vertices
    EXPECT_DOUBLE_EQ(acmr(strip, 6, 16, Primitive::strip_restart), 1.5);
    EXPECT_DOUBLE_EQ(acmr(strip, 6, 16, Primitive::strip_degenerate), 1.5);
    // As a list the same triangles cost the same transforms.
    const Idx list = expand_strips_to_triangles(strip, Primitive::strip_restart);
    EXPECT_EQ(list, (Idx{0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5}));
    EXPECT_DOUBLE_EQ(acmr(list, 6, 16), 1.5);
}

TEST(VertexCache, AcmrIsFifoNotLru) {
    // FIFO of 3: the hit on 0 does not refresh it, so 0 is evicted by 3 and 4 and missed again (8 transforms);
    // an LRU cache would keep 0 (7 transforms).
    const Idx list = {0, 1, 2, 0, 3, 4, 0, 5, 6};
    EXPECT_DOUBLE_EQ(acmr(list, 7, 3), 8.0 / 3.0);
    EXPECT_DOUBLE_EQ(acmr(list, 7, 16), 7.0 / 3.0);
    EXPECT_DOUBLE_EQ(acmr(list, 7, 1), 9.0 / 3.0);
}

TEST(VertexCache, RestartIndicesSeparateStripsAndTouchNoCache) {
    const Idx buf = {0, 1, 2, 3, R, 4, 5, 6};
    EXPECT_EQ(drawn_triangle_count(buf, Primitive::strip_restart), 3u);
    EXPECT_EQ(expand_strips_to_triangles(buf, Primitive::strip_restart), (Idx{0, 1, 2, 2, 1, 3, 4, 5, 6}));
    EXPECT_DOUBLE_EQ(acmr(buf, 7, 16, Primitive::strip_restart), 7.0 / 3.0);
    EXPECT_DOUBLE_EQ(indices_per_triangle(buf, Primitive::strip_restart), 8.0 / 3.0);
    // Each strip restarts on an even position: the second strip's first triangle is not swapped.
    const Idx odd_first = {0, 1, 2, R, 3, 4, 5, 6};
    EXPECT_EQ(expand_strips_to_triangles(odd_first, Primitive::strip_restart), (Idx{0, 1, 2, 3, 4, 5, 5, 4, 6}));
}

TEST(VertexCache, DegenerateJoinsAreDroppedAndParityFollowsThePosition) {
    // positions: 0 (0 1 2), 1..4 degenerate, 5 (3 4 5) on an odd position: drawn as (4 3 5).
    const Idx buf = {0, 1, 2, 2, 3, 3, 4, 5};
    EXPECT_EQ(drawn_triangle_count(buf, Primitive::strip_degenerate), 2u);
    EXPECT_EQ(expand_strips_to_triangles(buf, Primitive::strip_degenerate), (Idx{0, 1, 2, 4, 3, 5}));
    EXPECT_DOUBLE_EQ(indices_per_triangle(buf, Primitive::strip_degenerate), 4.0);
    EXPECT_DOUBLE_EQ(acmr(buf, 6, 16, Primitive::strip_degenerate), 3.0);
    // A swap inside a strip: "a b a c" draws (a b c) with the winding of position 0.
    EXPECT_EQ(expand_strips_to_triangles(Idx{5, 6, 7, 6, 8}, Primitive::strip_degenerate), (Idx{5, 6, 7, 7, 6, 8}));
    EXPECT_EQ(expand_strips_to_triangles(Idx{0, 1, 0, 2}, Primitive::strip_degenerate), (Idx{0, 1, 2}));
}

TEST(VertexCache, EmptyAndShortBuffers) {
    const Idx none;
    EXPECT_EQ(acmr(none, 0, 16), 0.0);
    EXPECT_EQ(indices_per_triangle(none, Primitive::strip_restart), 0.0);
    EXPECT_TRUE(expand_strips_to_triangles(none, Primitive::strip_degenerate).empty());
    EXPECT_TRUE(expand_strips_to_triangles(Idx{0, 1}, Primitive::strip_restart).empty());
    EXPECT_TRUE(expand_strips_to_triangles(Idx{R}, Primitive::strip_restart).empty());
    EXPECT_EQ(acmr(Idx{0, 1}, 2, 16, Primitive::strip_restart), 0.0);
}

TEST(VertexCache, BadArgumentsThrow) {
    const Idx buf = {0, 1, 5};
    EXPECT_THROW(acmr(buf, 3, 16), Error);
    EXPECT_THROW(acmr(Idx{0, 1, 2}, 3, 0), Error);
    // The restart index is only an index in restart mode.
    EXPECT_THROW(acmr(Idx{0, 1, 2, R, 0, 1, 2}, 3, 16, Primitive::strip_degenerate), Error);
    try {
        acmr(buf, 3, 16);
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::argument);
        EXPECT_NE(std::string(e.what()).find("position 2"), std::string::npos) << e.what();
    }
}
