// The runner with stand-in pack commands (a shell that crashes, hangs or fails): each misbehaving
// asset fails alone with a message that says what happened, and the others still run.
#include "lodforge/batch/batch_run.h"

#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {
namespace fs = std::filesystem;
using lodforge::BatchAsset;
using lodforge::BatchRecord;
using lodforge::BatchRunParams;
using lodforge::test::contains;
using lodforge::test::ScratchDir;

// Assets over a real input file (the fingerprint hashes it); the stand-in command ignores it.
std::vector<BatchAsset> assets_for(const ScratchDir& dir, int count) {
    const std::string input = dir.file("in.ply");
    fs::copy_file(lodforge::test::shared_data("tex-ply-wedge-uv/laurana500.ply"), input,
                  fs::copy_options::overwrite_existing);
    std::vector<BatchAsset> assets;
    for (int i = 0; i < count; ++i) assets.push_back({input, "", dir.file("out" + std::to_string(i))});
    return assets;
}

BatchRunParams shell(const std::string& script, std::vector<BatchAsset> assets) {
    BatchRunParams p;
    p.assets = std::move(assets);
    p.jobs = 2;
    p.pack_command = {"/bin/sh", "-c", script, "sh"};
    p.lodforge_version = "test";
    return p;
}

TEST(BatchRun, CrashingPackFailsWithItsSignal) {
    ScratchDir dir("batch-run-crash");
    const lodforge::BatchReport r = run_batch(shell("kill -SEGV $$", assets_for(dir, 3)));
    ASSERT_EQ(r.assets.size(), 3u);
    for (const BatchRecord& a : r.assets) {
        EXPECT_EQ(a.status, BatchRecord::Status::failed);
        EXPECT_TRUE(contains(a.message, "crashed (signal 11")) << a.message;
        EXPECT_EQ(a.input_sha256.size(), 64u);
    }
    EXPECT_FALSE(r.cancelled);
}

TEST(BatchRun, HangingPackTimesOutAndTheOthersFinish) {
    ScratchDir dir("batch-run-hang");
    // The first asset hangs; the second prints a result like `pack --json` does.
    const std::string script =
        "case \"$*\" in *out0*) exec sleep 60;; esac; "
        "printf '{\"levels\":[{\"triangles\":7,\"vertices\":5,\"error_relative\":0}],\"files\":[],\"notes\":[]}'";
    BatchRunParams p = shell(script, assets_for(dir, 2));
    p.timeout_seconds = 0.5;
    const lodforge::BatchReport r = run_batch(p);
    ASSERT_EQ(r.assets.size(), 2u);
    EXPECT_EQ(r.assets[0].status, BatchRecord::Status::failed);
    EXPECT_TRUE(contains(r.assets[0].message, "timed out after 0.5 s")) << r.assets[0].message;
    EXPECT_EQ(r.assets[1].status, BatchRecord::Status::ok) << r.assets[1].message;
    ASSERT_EQ(r.assets[1].levels.size(), 1u);
    EXPECT_EQ(r.assets[1].levels[0].triangles, 7u);
}

TEST(BatchRun, FailureMessageIsThePackErrorLine) {
    ScratchDir dir("batch-run-message");
    const lodforge::BatchReport r =
        run_batch(shell("echo 'lodforge: error: x.ply: line 3: bad vertex' >&2; exit 1", assets_for(dir, 1)));
    ASSERT_EQ(r.assets.size(), 1u);
    EXPECT_EQ(r.assets[0].status, BatchRecord::Status::failed);
    EXPECT_EQ(r.assets[0].message, "x.ply: line 3: bad vertex");
}

TEST(BatchRun, MissingInputFailsBeforeAnythingRuns) {
    ScratchDir dir("batch-run-missing");
    std::vector<BatchAsset> assets = assets_for(dir, 1);
    assets.push_back({dir.file("nope.ply"), "", dir.file("out-nope")});
    // The command leaves a trace of every run: only the existing input may run.
    const lodforge::BatchReport r = run_batch(shell("echo run >> '" + dir.file("runs") + "'; exit 1", assets));
    ASSERT_EQ(r.assets.size(), 2u);
    EXPECT_TRUE(contains(r.assets[1].message, "nope.ply")) << r.assets[1].message;
    EXPECT_TRUE(contains(r.assets[1].message, "no such file")) << r.assets[1].message;
    std::ifstream runs(dir.file("runs"));
    std::string line;
    int count = 0;
    while (std::getline(runs, line)) ++count;
    EXPECT_EQ(count, 1);
}

}  // namespace
