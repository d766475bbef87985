// Manifests and directories into assets: paths relative to the manifest, default outputs, and the
// messages of malformed manifests (each names the file and the entry or line).
#include "lodforge/batch/batch_manifest.h"
#include "lodforge/error.h"

#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {
namespace fs = std::filesystem;
using lodforge::BatchAsset;
using lodforge::batch_assets;
using lodforge::test::contains;
using lodforge::test::ScratchDir;

void write_manifest_file(const std::string& path, const std::string& text) {
    fs::create_directories(fs::path(path).parent_path());
    std::ofstream(path) << text;
}

std::string manifest_error(const std::string& path) {
    try {
        batch_assets({path, "", ""});
    } catch (const lodforge::Error& e) {
        return e.what();
    }
    return "";
}

TEST(BatchManifest, JsonPathsAreRelativeToTheManifest) {
    ScratchDir dir("batch-manifest-json");
    const std::string m = dir.file("m/assets.json");
    write_manifest_file(m, R"({"assets": [{"input": "a/x.ply", "preset": "mobile", "output": "../packs/x"},
                                          {"input": "/abs/y.obj", "preset": "p/my.json"}]})");
    const std::vector<BatchAsset> a = batch_assets({m, "", ""});
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a[0].input, (dir.path() / "m/a/x.ply").string());
    EXPECT_EQ(a[0].preset, "mobile");
    EXPECT_EQ(a[0].output, (dir.path() / "packs/x").string());
    EXPECT_EQ(a[1].input, "/abs/y.obj");
    EXPECT_EQ(a[1].preset, (dir.path() / "m/p/my.json").string());
    EXPECT_EQ(a[1].output, (dir.path() / "m/y").string());  // default: the manifest's folder / stem
}

TEST(BatchManifest, CsvWithQuotesAndDefaultPreset) {
    ScratchDir dir("batch-manifest-csv");
    const std::string m = dir.file("assets.csv");
    write_manifest_file(m, "output,input\r\n\"out/a, b\",\"in/a \"\"b\"\".ply\"\r\n\r\nout/c,c.glb\r\n");
    const std::vector<BatchAsset> a = batch_assets({m, "web", ""});
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a[0].input, (dir.path() / "in/a \"b\".ply").string());
    EXPECT_EQ(a[0].output, (dir.path() / "out/a, b").string());
    EXPECT_EQ(a[0].preset, "web");
    EXPECT_EQ(a[1].input, (dir.path() / "c.glb").string());
}

TEST(BatchManifest, MalformedManifestsNameFileAndPlace) {
    ScratchDir dir("batch-manifest-bad");
    const struct {
        const char* name;
        const char* text;
        const char* expected;
    } cases[] = {
        {"a.json", "{\"assets\": [", "not valid JSON"},
        {"b.json", "[{\"input\": \"x.ply\", \"lod\": 3}]", "entry 1: unknown key \"lod\""},
        {"c.json", "[{\"preset\": \"web\"}]", "entry 1: no input"},
        {"d.json", "[{\"input\": \"x.ply\"}, {\"input\": \"sub/x.obj\"}]", "entry 2: output"},
        {"e.csv", "path,preset\nx.ply,web\n", "line 1: unknown column \"path\""},
        {"f.csv", "input,preset\nx.ply\n", "line 2: 1 fields, the header has 2"},
        {"g.csv", "input\n\"x.ply\n", "line 2: a quoted field is not closed"},
        {"h.csv", "", "empty manifest"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        write_manifest_file(dir.file(c.name), c.text);
        const std::string message = manifest_error(dir.file(c.name));
        EXPECT_TRUE(contains(message, dir.file(c.name))) << message;
        EXPECT_TRUE(contains(message, c.expected)) << message;
    }
    EXPECT_TRUE(contains(manifest_error(dir.file("missing.json")), "no such file")) << manifest_error(dir.file("missing.json"));
    write_manifest_file(dir.file("list.txt"), "x.ply\n");
    EXPECT_TRUE(contains(manifest_error(dir.file("list.txt")), "not a directory or a manifest"));
}

TEST(BatchManifest, DirectoryFindsMeshesAndLeavesTheOutputRootOut) {
    ScratchDir dir("batch-manifest-dir");
    for (const char* f : {"in/a.ply", "in/sub/b.obj", "in/sub/b.ply", "in/notes.txt", "in/packs/old/old.glb",
                          "in/.hidden/c.ply"})
        write_manifest_file(dir.file(f), "x");
    const std::vector<BatchAsset> a = batch_assets({dir.file("in"), "mobile", dir.file("in/packs")});
    ASSERT_EQ(a.size(), 3u);
    EXPECT_EQ(a[0].input, dir.file("in/a.ply"));
    EXPECT_EQ(a[0].output, dir.file("in/packs/a"));
    EXPECT_EQ(a[0].preset, "mobile");
    // One stem twice in one folder: the extension tells the packs apart.
    EXPECT_EQ(a[1].output, dir.file("in/packs/sub/b-obj"));
    EXPECT_EQ(a[2].output, dir.file("in/packs/sub/b-ply"));
    // Without -o: a sibling "<dir>-packs".
    EXPECT_EQ(lodforge::batch_output_root({dir.file("in/"), "", ""}), dir.file("in-packs"));
}

}  // namespace
