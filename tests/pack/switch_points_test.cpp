// switch_points against values computed by hand, and the forms agreeing with each other and with the
// distance formula of the three.js runtime (resources/engines/lodforge-three.mjs).
#include "lodforge/error.h"
#include "lodforge/pack/switch_points.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>

namespace {

using namespace lodforge;

// Errors 0, 1 % and 4 % of a diagonal of 2 (sphere radius 1), largest side 1.5, the default screen
// (1920 x 1080, one pixel, 60 degrees, hysteresis 0.1). Level 1 may take over when 1 % of the
// diagonal is a pixel: a sphere radius of 1 / (2 * 0.01) = 50 px, diameter 100 px; level 2 at 12.5 px.
TEST(SwitchPoints, HandComputedValues) {
    const SwitchPoints s = switch_points({0, 0.01, 0.04}, 2.0, 1.5, SwitchParams{});
    ASSERT_EQ(s.levels.size(), 3u);
    const double pi = std::numbers::pi, tan30 = std::tan(pi / 6);
    EXPECT_NEAR(s.levels[0].coverage, pi * 50 * 50 / (1920.0 * 1080), 1e-12);
    EXPECT_NEAR(s.levels[1].coverage, pi * 12.5 * 12.5 / (1920.0 * 1080), 1e-12);
    EXPECT_EQ(s.levels[2].coverage, 0.0);
    EXPECT_NEAR(s.levels[0].screen_size, 100.0 / 1080, 1e-12);
    EXPECT_NEAR(s.levels[1].screen_size, 25.0 / 1080, 1e-12);
    EXPECT_EQ(s.levels[2].screen_size, 0.0);
    // Unity: LODGroup size 1.5 instead of the sphere's 2.
    EXPECT_NEAR(s.levels[0].unity_transition_height, 100.0 / 1080 * 0.75, 1e-12);
    EXPECT_NEAR(s.levels[1].unity_transition_height, 25.0 / 1080 * 0.75, 1e-12);
    EXPECT_EQ(s.levels[2].unity_transition_height, 0.0);
    // Unreal: where each level begins.
    EXPECT_EQ(s.levels[0].unreal_screen_size, 1.0);
    EXPECT_NEAR(s.levels[1].unreal_screen_size, 100.0 / 1080, 1e-12);
    EXPECT_NEAR(s.levels[2].unreal_screen_size, 25.0 / 1080, 1e-12);
    // Godot: a sphere of radius 1 spans 50 px at distance 1080 / (2 * 50 * tan 30) = 18.706...
    const double d1 = 1080 / (100 * tan30), d2 = 1080 / (25 * tan30);
    EXPECT_NEAR(d1, 18.7061, 1e-4);
    EXPECT_EQ(s.levels[0].godot.range_begin, 0.0);
    EXPECT_NEAR(s.levels[0].godot.range_end, d1, 1e-9);
    EXPECT_NEAR(s.levels[0].godot.range_end_margin, 0.1 * d1, 1e-9);
    EXPECT_NEAR(s.levels[1].godot.range_begin, d1, 1e-9);
    EXPECT_NEAR(s.levels[1].godot.range_begin_margin, 0.1 * d1, 1e-9);
    EXPECT_NEAR(s.levels[1].godot.range_end, d2, 1e-9);
    EXPECT_NEAR(s.levels[2].godot.range_begin, d2, 1e-9);
    EXPECT_EQ(s.levels[2].godot.range_end, 0.0);  // Godot's "no end": the coarsest is never culled
}

TEST(SwitchPoints, ToleranceScreenAndFieldOfView) {
    SwitchParams p;
    p.pixels = 2;
    p.width = 1280;
    p.height = 720;
    p.fov_deg = 90;
    p.hysteresis = 0;
    const SwitchPoints s = switch_points({0, 0.01, 0.04}, 2.0, 2.0, p);
    // Two pixels: the sphere may be 100 px in radius before level 1 takes over, at 720 / (2 * 100 * 1).
    EXPECT_NEAR(s.levels[0].screen_size, 200.0 / 720, 1e-12);
    EXPECT_NEAR(s.levels[0].coverage, std::numbers::pi * 100 * 100 / (1280.0 * 720), 1e-12);
    EXPECT_NEAR(s.levels[0].godot.range_end, 3.6, 1e-12);
    EXPECT_EQ(s.levels[0].godot.range_end_margin, 0.0);
    EXPECT_NEAR(s.levels[0].unity_transition_height, s.levels[0].screen_size, 1e-15);
}

// The three.js runtime turns coverage c into d(c) = r / (2 tan(fov/2)) sqrt(pi / (c aspect)); the Godot
// distances are the same switch points, so both must agree on every screen.
TEST(SwitchPoints, GodotDistancesAreTheThreeJsDistances) {
    for (const auto& [w, h, fov] : {std::tuple{1920u, 1080u, 60.0}, {800u, 600u, 45.0}, {1080u, 1920u, 75.0}}) {
        SwitchParams p;
        p.width = w;
        p.height = h;
        p.fov_deg = fov;
        const double diagonal = 3.7, radius = diagonal / 2;
        const SwitchPoints s = switch_points({0, 0.002, 0.009, 0.05}, diagonal, 2.0, p);
        for (std::size_t k = 0; k + 1 < s.levels.size(); ++k) {
            const double c = s.levels[k].coverage;
            const double three = radius / (2 * std::tan(fov * std::numbers::pi / 360)) *
                                 std::sqrt(std::numbers::pi / (c * double(w) / double(h)));
            EXPECT_NEAR(s.levels[k].godot.range_end, three, 1e-9 * three) << w << "x" << h << " level " << k;
        }
    }
}

TEST(SwitchPoints, OrderKeptWhenAFinerLevelMeasuredWorse) {
    const SwitchPoints s = switch_points({0, 0.02, 0.01, 0.05}, 1.0, 1.0, SwitchParams{});
    EXPECT_EQ(s.levels[1].coverage, s.levels[0].coverage);  // level 2's own 1 % would switch it in earlier
    EXPECT_LE(s.levels[2].coverage, s.levels[1].coverage);
    EXPECT_LE(s.levels[1].godot.range_end, s.levels[2].godot.range_end);
}

TEST(SwitchPoints, ErrorsTooSmallToShowCoverTheScreen) {
    const SwitchPoints s = switch_points({0, 1e-9}, 1.0, 1.0, SwitchParams{});
    EXPECT_EQ(s.levels[0].coverage, 1.0);
    EXPECT_NEAR(s.levels[0].screen_size, 2 * std::sqrt(1920.0 * 1080 / std::numbers::pi) / 1080, 1e-12);
    EXPECT_EQ(s.levels[0].unreal_screen_size, std::max(1.0, s.levels[1].unreal_screen_size));
    EXPECT_GE(s.levels[0].unreal_screen_size, s.levels[1].unreal_screen_size);
    EXPECT_EQ(coverage_for_error(0, SwitchParams{}), 1.0);
}

TEST(SwitchPoints, BadParametersAreRefused) {
    auto refused = [](SwitchParams p, double diagonal = 1, double side = 1) {
        try {
            switch_points({0, 0.1}, diagonal, side, p);
        } catch (const Error& e) {
            return e.kind() == Error::Kind::argument;
        }
        return false;
    };
    SwitchParams p;
    EXPECT_FALSE(refused(p));
    EXPECT_TRUE(refused(p, 0));
    EXPECT_TRUE(refused(p, 1, 2));
    p.pixels = 0;
    EXPECT_TRUE(refused(p));
    p = {};
    p.fov_deg = 180;
    EXPECT_TRUE(refused(p));
    p = {};
    p.hysteresis = 1;
    EXPECT_TRUE(refused(p));
    p = {};
    p.height = 0;
    EXPECT_TRUE(refused(p));
}

TEST(SwitchPoints, FromABoundingBox) {
    Bounds box;
    box.add({0, 0, 0});
    box.add({3, 4, 0});  // diagonal 5, largest side 4
    const SwitchPoints a = switch_points({0, 0.01}, box, SwitchParams{});
    const SwitchPoints b = switch_points({0, 0.01}, 5.0, 4.0, SwitchParams{});
    ASSERT_EQ(a.levels.size(), 2u);
    EXPECT_DOUBLE_EQ(a.levels[0].unity_transition_height, b.levels[0].unity_transition_height);
    EXPECT_DOUBLE_EQ(a.levels[0].godot.range_end, b.levels[0].godot.range_end);
    EXPECT_TRUE(switch_points({0, 0.01}, Bounds{}, SwitchParams{}).levels.empty());  // no extent
}

TEST(SwitchPoints, JsonKeysInTheirFixedOrder) {
    const SwitchPoints s = switch_points({0, 0.01}, 2.0, 1.5, SwitchParams{});
    const auto j = nlohmann::ordered_json::parse(level_switch_json(s.levels[1]));
    std::vector<std::string> keys;
    for (auto it = j.begin(); it != j.end(); ++it) keys.push_back(it.key());
    EXPECT_EQ(keys, (std::vector<std::string>{"coverage", "screen_size", "unity_transition_height",
                                              "unreal_screen_size", "godot"}));
    EXPECT_NEAR(j["godot"]["visibility_range_begin"].get<double>(), s.levels[1].godot.range_begin, 1e-12);
    EXPECT_EQ(j["godot"]["visibility_range_end"].get<double>(), 0.0);
}

}  // namespace
