// The shipped presets (resources/presets, found under the program's prefix) and the one function that
// builds a preset's levels for every method (preset_levels.h).
#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/pack/preset_levels.h"
#include "lodforge/pack/preset_library.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

using namespace lodforge;

TEST(PresetLibrary, TheFourShippedPresetsAreFoundAndParse) {
    const std::vector<std::string> names = shipped_preset_names();
    EXPECT_EQ(names, (std::vector<std::string>{"console", "mobile", "scan-archive", "web"}));
    for (const std::string& n : names) {
        const Preset p = load_shipped_preset(n);
        EXPECT_EQ(p.name, n);
        EXPECT_FALSE(p.levels.empty()) << n;
        EXPECT_NE(p, Preset{}) << n;
    }
    // Each target gets its own trade-off: fewer, coarser levels for mobile and web than for console.
    EXPECT_LT(load_shipped_preset("web").levels.size(), load_shipped_preset("console").levels.size());
    EXPECT_LT(load_shipped_preset("mobile").levels.back().value, load_shipped_preset("console").levels.back().value);
    EXPECT_EQ(load_shipped_preset("scan-archive").levels.front().kind, LodTarget::Kind::error);
}

TEST(PresetLibrary, NamesAndFilesResolveByOneRule) {
    lodforge::test::ScratchDir dir("preset-library");
    const std::string file = dir.file("mine.json");
    std::ofstream(file) << R"({"name": "mine", "method": "cluster"})";
    EXPECT_EQ(resolve_preset(file).name, "mine");
    EXPECT_EQ(resolve_preset("web").name, "web");
    try {
        resolve_preset("mobil");
        FAIL() << "an unknown name must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::argument);
        EXPECT_NE(std::string(e.what()).find("console, mobile, scan-archive, web"), std::string::npos) << e.what();
    }
    EXPECT_THROW(resolve_preset(dir.file("missing.json")), Error);
    // $LODFORGE_PRESETS_DIR comes first: a preset there shadows the shipped one of the same name.
    std::ofstream(dir.file("web.json")) << R"({"name": "own web", "levels": [{"ratio": 0.4}]})";
    ::setenv("LODFORGE_PRESETS_DIR", dir.path().c_str(), 1);
    const Preset shadowed = load_shipped_preset("web");
    const std::vector<std::string> names = shipped_preset_names();
    ::unsetenv("LODFORGE_PRESETS_DIR");
    EXPECT_EQ(shadowed.name, "own web");
    EXPECT_EQ(names, (std::vector<std::string>{"console", "mine", "mobile", "scan-archive", "web"}));  // each once
    EXPECT_EQ(load_shipped_preset("web").name, "web");
}

// Every method through the one function: one level per preset level, each measured, with its target
// and stop, and what the method adds (the chain, the .lodstrips bytes, the structure's cells).
TEST(PresetLevels, EveryMethodGivesOneMeasuredLevelPerTarget) {
    const Mesh mesh = read_mesh(lodforge::test::shared_data("tex-spot/spot_triangulated.obj"));
    Preset preset;
    preset.levels = {{LodTarget::Kind::ratio, 0.5}, {LodTarget::Kind::triangles, 600}};
    preset.octree.max_triangles_per_node = 300;
    preset.mcoctree.resolution = 32;
    PresetLevelsParams params;
    params.source_path = "spot.obj";
    for (LodMethod m : {LodMethod::collapse, LodMethod::cluster, LodMethod::lodstrips, LodMethod::mcoctree,
                        LodMethod::octree}) {
        preset.method = m;
        PresetLevelsStats stats;
        const PresetLevels r = build_preset_levels(mesh, preset, params, nullptr, &stats);
        const std::string name(to_string(m));
        ASSERT_EQ(r.levels.size(), 2u) << name;
        ASSERT_EQ(r.distance.size(), 2u) << name;
        ASSERT_EQ(r.stops.size(), 2u) << name;
        ASSERT_EQ(stats.level_seconds.size(), 2u) << name;
        EXPECT_EQ(r.target_triangles[0], 2928u) << name;
        EXPECT_EQ(r.target_triangles[1], 600u) << name;
        EXPECT_LT(r.levels[1].triangle_count(), r.levels[0].triangle_count()) << name;
        EXPECT_LT(r.levels[0].triangle_count(), mesh.triangle_count()) << name;
        EXPECT_GT(r.distance[1].hausdorff, 0) << name;
        EXPECT_EQ(r.chain.has_value(), m == LodMethod::collapse) << name;
        // The default optimal placement moves the collapse chain's vertices; lodstrips always keeps them.
        EXPECT_EQ(r.vertices_on_input, m == LodMethod::lodstrips) << name;
        EXPECT_TRUE(!r.chain || r.chain->shared.levels.empty()) << name;  // no shared buffer to write
        EXPECT_EQ(r.lodstrips_file.empty(), m != LodMethod::lodstrips) << name;
        EXPECT_EQ(r.cells.empty(), m != LodMethod::mcoctree && m != LodMethod::octree) << name;
    }
    // Without measuring, no distances; error targets only for the collapse chain.
    PresetLevelsParams unmeasured;
    unmeasured.measure = false;
    preset.method = LodMethod::collapse;
    EXPECT_TRUE(build_preset_levels(mesh, preset, unmeasured).distance.empty());
    preset.levels = {{LodTarget::Kind::error, 0.01}};
    EXPECT_EQ(build_preset_levels(mesh, preset, unmeasured).levels.size(), 1u);
    for (LodMethod m : {LodMethod::cluster, LodMethod::lodstrips, LodMethod::mcoctree, LodMethod::octree}) {
        preset.method = m;
        try {
            build_preset_levels(mesh, preset, params);
            ADD_FAILURE() << to_string(m) << " must refuse an error target";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), Error::Kind::argument);
            EXPECT_NE(std::string(e.what()).find("spot.obj"), std::string::npos) << e.what();
        }
    }
}
