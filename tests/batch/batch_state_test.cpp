// The state file: what makes an asset up to date (same input bytes, preset content, version, an ok
// run whose pack.json is there) and that it round-trips; a foreign file is refused by name.
#include "lodforge/batch/batch_state.h"
#include "lodforge/error.h"

#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {
namespace fs = std::filesystem;
using lodforge::BatchAsset;
using lodforge::BatchRecord;
using lodforge::BatchState;
using lodforge::test::contains;
using lodforge::test::ScratchDir;

struct StateFixture {
    ScratchDir dir{"batch-state"};
    BatchAsset asset{dir.file("in.ply"), "", dir.file("out")};
    StateFixture() {
        std::ofstream(asset.input) << "ply one";
        fs::create_directories(asset.output);
        std::ofstream(dir.file("out/pack.json")) << "{}";
    }
    BatchState state_after_ok_run() const {
        BatchRecord r = lodforge::batch_fingerprint(asset, "1.0");
        r.status = BatchRecord::Status::ok;
        r.levels = {{100, 52, 0}, {50, 27, 0.01}};
        BatchState s;
        record_outcome(s, r);
        return s;
    }
};

TEST(BatchState, UnchangedAssetIsUpToDateAndRoundTrips) {
    StateFixture f;
    const BatchState s = f.state_after_ok_run();
    lodforge::save_batch_state(f.dir.file("state.json"), s);
    const BatchState loaded = lodforge::load_batch_state(f.dir.file("state.json"));
    const BatchRecord* last = up_to_date_record(loaded, lodforge::batch_fingerprint(f.asset, "1.0"));
    ASSERT_NE(last, nullptr);
    ASSERT_EQ(last->levels.size(), 2u);
    EXPECT_EQ(last->levels[1].triangles, 50u);
    EXPECT_DOUBLE_EQ(last->levels[1].error_relative, 0.01);
}

TEST(BatchState, EachDependencyInvalidates) {
    StateFixture f;
    const BatchState s = f.state_after_ok_run();
    EXPECT_EQ(up_to_date_record(s, lodforge::batch_fingerprint(f.asset, "1.1")), nullptr);  // new version
    BatchAsset other_preset = f.asset;
    other_preset.preset = "mobile";
    EXPECT_EQ(up_to_date_record(s, lodforge::batch_fingerprint(other_preset, "1.0")), nullptr);
    std::ofstream(f.asset.input) << "ply two";  // new content
    EXPECT_EQ(up_to_date_record(s, lodforge::batch_fingerprint(f.asset, "1.0")), nullptr);
    std::ofstream(f.asset.input) << "ply one";
    ASSERT_NE(up_to_date_record(s, lodforge::batch_fingerprint(f.asset, "1.0")), nullptr);
    fs::remove(f.dir.file("out/pack.json"));  // the pack was deleted
    EXPECT_EQ(up_to_date_record(s, lodforge::batch_fingerprint(f.asset, "1.0")), nullptr);
}

TEST(BatchState, FailedRunIsRetried) {
    StateFixture f;
    BatchRecord r = lodforge::batch_fingerprint(f.asset, "1.0");
    r.status = BatchRecord::Status::failed;
    r.message = "boom";
    BatchState s;
    record_outcome(s, r);
    EXPECT_EQ(up_to_date_record(s, lodforge::batch_fingerprint(f.asset, "1.0")), nullptr);
    // A cancelled record does not replace what the state knows.
    r.status = BatchRecord::Status::cancelled;
    record_outcome(s, r);
    EXPECT_EQ(s.assets.at(f.asset.output).status, BatchRecord::Status::failed);
}

TEST(BatchState, MissingFileIsEmptyAndForeignFileIsRefused) {
    ScratchDir dir("batch-state-foreign");
    EXPECT_TRUE(lodforge::load_batch_state(dir.file("none.json")).assets.empty());
    std::ofstream(dir.file("foreign.json")) << R"({"assets": {}})";
    try {
        lodforge::load_batch_state(dir.file("foreign.json"));
        FAIL() << "a file without the state format was accepted";
    } catch (const lodforge::Error& e) {
        EXPECT_TRUE(contains(e.what(), dir.file("foreign.json"))) << e.what();
        EXPECT_TRUE(contains(e.what(), "not a LodForge batch state file")) << e.what();
    }
}

}  // namespace
