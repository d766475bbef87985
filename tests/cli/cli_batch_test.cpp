// `lodforge batch` end to end (docs/batch.md): packs of a directory and of a manifest, skipping on a
// re-run, retry of a failed asset, one bad asset not stopping the others, a signal leaving no partial
// pack, and malformed manifests refused with the file's name.
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>
#include <thread>

namespace {
namespace fs = std::filesystem;
using lodforge::test::contains;
using lodforge::test::quoted;
using lodforge::test::run_cli;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;

nlohmann::json read_json_file(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

// Three small meshes of three formats in two folders.
void make_small_tree(const fs::path& in) {
    fs::create_directories(in / "scans");
    fs::copy_file(shared_data("scan-dragon/dragon_vrip_res4.ply"), in / "scans/dragon.ply");
    fs::copy_file(shared_data("color-open3d-small/color.ply"), in / "color.ply");
    fs::copy_file(shared_data("skin-rigged-simple/RiggedSimple.glb"), in / "scans/rigged.glb");
}

const nlohmann::json& asset_named(const nlohmann::json& report, const std::string& output_suffix) {
    for (const auto& a : report["assets"])
        if (a["output"].get<std::string>().ends_with(output_suffix)) return a;
    static const nlohmann::json none;
    ADD_FAILURE() << "no asset with output " << output_suffix;
    return none;
}

// A successful batch run whose summary line says `summary`; its report.
nlohmann::json run_expecting(const std::string& cmd, const std::string& summary, const fs::path& root) {
    const auto r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, summary)) << r.out;
    return read_json_file(root / "batch-report.json");
}

fs::file_time_type pack_time(const fs::path& pack) { return fs::last_write_time(pack / "pack.json"); }

TEST(CliBatch, DirectoryPacksEveryMeshThenSkipsUnchangedAndRebuildsChanged) {
    ScratchDir dir("cli-batch-dir");
    make_small_tree(dir.path() / "in");
    const std::string cmd = "batch " + quoted(dir.file("in")) + " -o " + quoted(dir.file("packs")) + " --jobs 2";
    const auto first = run_cli(cmd);
    ASSERT_EQ(first.exit_code, 0) << first.out;
    EXPECT_TRUE(contains(first.out, "3 assets: 3 ok, 0 failed, 0 skipped")) << first.out;
    const nlohmann::json report = read_json_file(dir.path() / "packs/batch-report.json");
    EXPECT_EQ(report["summary"]["ok"], 3);
    for (const auto& a : report["assets"]) {
        SCOPED_TRACE(a["input"].get<std::string>());
        ASSERT_EQ(a["status"], "ok");
        ASSERT_GE(a["levels"].size(), 2u);
        EXPECT_LT(a["levels"][1]["triangles"].get<std::size_t>(), a["levels"][0]["triangles"].get<std::size_t>());
        std::uintmax_t bytes = 0;
        for (const auto& f : a["files"]) bytes += fs::file_size(fs::path(a["output"].get<std::string>()) / f.get<std::string>());
        EXPECT_EQ(a["bytes"].get<std::uintmax_t>(), bytes);
        EXPECT_GT(bytes, 0u);
    }
    EXPECT_EQ(asset_named(report, "/packs/scans/dragon")["levels"][0]["triangles"], 11102);
    ASSERT_TRUE(fs::exists(dir.path() / "packs/scans/rigged/pack.json"));
    ASSERT_TRUE(fs::exists(dir.path() / "packs/color/pack.json"));
    const auto dragon_time = pack_time(dir.path() / "packs/scans/dragon");
    const auto color_time = pack_time(dir.path() / "packs/color");

    // Nothing changed: nothing runs, and the report still lists every asset's levels.
    const nlohmann::json again = run_expecting(cmd, "3 assets: 0 ok, 0 failed, 3 skipped", dir.path() / "packs");
    EXPECT_EQ(asset_named(again, "/packs/scans/dragon")["levels"][0]["triangles"], 11102);
    EXPECT_EQ(pack_time(dir.path() / "packs/scans/dragon"), dragon_time);

    // New content for one input: that asset alone is packed again.
    fs::copy_file(shared_data("scan-dragon/dragon_vrip_res3.ply"), dir.path() / "in/scans/dragon.ply",
                  fs::copy_options::overwrite_existing);
    const nlohmann::json rebuilt = run_expecting(cmd, "3 assets: 1 ok, 0 failed, 2 skipped", dir.path() / "packs");
    EXPECT_EQ(asset_named(rebuilt, "/packs/scans/dragon")["levels"][0]["triangles"], 47794);
    EXPECT_EQ(pack_time(dir.path() / "packs/color"), color_time);

    // Another preset: every asset is packed again.
    run_expecting(cmd + " --preset mobile", "3 assets: 3 ok, 0 failed, 0 skipped", dir.path() / "packs");
}

TEST(CliBatch, BadAssetIsReportedTheOthersFinishAndARerunRetriesIt) {
    ScratchDir dir("cli-batch-bad");
    fs::copy_file(shared_data("scan-dragon/dragon_vrip_res4.ply"), dir.path() / "good.ply");
    std::ofstream(dir.file("bad.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n";
    std::ofstream(dir.file("assets.csv")) << "input,output\ngood.ply,out/good\nbad.ply,out/bad\n";
    const std::string cmd = "batch " + quoted(dir.file("assets.csv")) + " --jobs 2";
    const auto first = run_cli(cmd);
    EXPECT_EQ(first.exit_code, 1) << first.out;
    EXPECT_TRUE(contains(first.out, "1 of 2 assets failed")) << first.out;
    EXPECT_TRUE(contains(first.out, "lodforge: failed: " + dir.file("bad.ply"))) << first.out;
    nlohmann::json report = read_json_file(dir.path() / "batch-report.json");
    EXPECT_EQ(asset_named(report, "/out/good")["status"], "ok");
    const auto& bad = asset_named(report, "/out/bad");
    EXPECT_EQ(bad["status"], "failed");
    EXPECT_TRUE(contains(bad["message"].get<std::string>(), "bad.ply")) << bad["message"];
    EXPECT_FALSE(fs::exists(dir.path() / "out/bad"));

    // The failure is retried (and fails again); the good asset is not packed again.
    const auto second = run_cli(cmd);
    EXPECT_EQ(second.exit_code, 1) << second.out;
    EXPECT_TRUE(contains(second.out, "2 assets: 0 ok, 1 failed, 1 skipped")) << second.out;
    // Fixed, it is packed.
    fs::copy_file(shared_data("scan-dragon/dragon_vrip_res4.ply"), dir.path() / "bad.ply",
                  fs::copy_options::overwrite_existing);
    const auto third = run_cli(cmd);
    EXPECT_EQ(third.exit_code, 0) << third.out;
    EXPECT_TRUE(contains(third.out, "2 assets: 1 ok, 0 failed, 1 skipped")) << third.out;
    EXPECT_TRUE(fs::exists(dir.path() / "out/bad/pack.json"));
}

TEST(CliBatch, ReportOnStdoutWithOnlyAndNoState) {
    ScratchDir dir("cli-batch-only");
    make_small_tree(dir.path() / "in");
    const auto r = run_cli("batch " + quoted(dir.file("in")) + " -o " + quoted(dir.file("packs")) + " --only " +
                               quoted(dir.file("packs/color")) + " --no-state --report -",
                           false);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const nlohmann::json report = nlohmann::json::parse(r.out);
    ASSERT_EQ(report["assets"].size(), 1u);
    EXPECT_EQ(report["assets"][0]["status"], "ok");
    EXPECT_EQ(report["assets"][0]["levels"][0]["triangles"], 5537);
    EXPECT_FALSE(fs::exists(dir.path() / "packs/batch-state.json"));
    EXPECT_FALSE(fs::exists(dir.path() / "packs/scans"));
}

TEST(CliBatch, MalformedManifestsAndUsageErrors) {
    ScratchDir dir("cli-batch-usage");
    std::ofstream(dir.file("broken.json")) << "[{\"input\": \"a.ply\",";
    auto r = run_cli("batch " + quoted(dir.file("broken.json")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_TRUE(contains(r.out, dir.file("broken.json") + ": not valid JSON")) << r.out;
    std::ofstream(dir.file("typo.json")) << "[{\"input\": \"a.ply\", \"ouput\": \"x\"}]";
    r = run_cli("batch " + quoted(dir.file("typo.json")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_TRUE(contains(r.out, "entry 1: unknown key \"ouput\"")) << r.out;
    r = run_cli("batch " + quoted(dir.file("missing-dir")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_TRUE(contains(r.out, dir.file("missing-dir") + ": no such file or directory")) << r.out;
    std::ofstream(dir.file("ok.json")) << "[{\"input\": \"a.ply\"}]";
    r = run_cli("batch " + quoted(dir.file("ok.json")) + " --only nothing");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_TRUE(contains(r.out, "--only nothing: no asset")) << r.out;
    r = run_cli("batch " + quoted(dir.file("ok.json")) + " --jobs 0");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    std::ofstream(dir.file("state.json")) << "{\"not\": \"a state\"}";
    r = run_cli("batch " + quoted(dir.file("ok.json")) + " --state " + quoted(dir.file("state.json")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_TRUE(contains(r.out, dir.file("state.json") + ": not a LodForge batch state file")) << r.out;
}

// SIGINT while the full dragon is being packed: the batch stops its children, exits 130, leaves no
// pack directory and no temporaries for the stopped asset, and records what finished.
TEST(CliBatch, SignalLeavesNoPartialPack) {
    for (const int signal_number : {SIGINT, SIGTERM}) {
        SCOPED_TRACE(signal_number);
        ScratchDir dir("cli-batch-signal");
        fs::create_directories(dir.path() / "packs");
        std::ofstream(dir.file("assets.json"))
            << nlohmann::json::array({{{"input", shared_data("scan-dragon/dragon_vrip_res4.ply")}, {"output", "packs/small"}},
                                      {{"input", shared_data("scan-dragon/dragon_vrip.ply")}, {"output", "packs/big"}}})
                   .dump();
        const pid_t pid = lodforge::test::spawn_cli({"batch", dir.file("assets.json"), "--jobs", "1"});
        // The big pack's staging directory appears beside packs/big once its input is read.
        bool signalled = false;
        for (int i = 0; i < 60000 && !signalled; ++i) {
            for (const auto& e : fs::directory_iterator(dir.path() / "packs"))
                if (e.path().filename().string().starts_with(".big")) signalled = ::kill(pid, signal_number) == 0;
            if (!signalled) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        if (!signalled) ::kill(pid, SIGKILL);
        const int exit_code = lodforge::test::wait_cli(pid).exit_code;
        ASSERT_TRUE(signalled) << "the big asset's staging directory never appeared; exit " << exit_code;
        EXPECT_EQ(exit_code, 128 + signal_number);
        std::vector<std::string> left;
        for (const auto& e : fs::directory_iterator(dir.path() / "packs")) left.push_back(e.path().filename().string());
        std::sort(left.begin(), left.end());
        EXPECT_EQ(left, (std::vector<std::string>{"small"}));
        const nlohmann::json report = read_json_file(dir.path() / "batch-report.json");
        EXPECT_TRUE(report["cancelled"].get<bool>());
        EXPECT_EQ(asset_named(report, "/packs/small")["status"], "ok");
        EXPECT_EQ(asset_named(report, "/packs/big")["status"], "cancelled");
        // The state knows the finished asset: a re-run would skip it and pack the big one (--plan says so).
        const auto plan = run_cli("batch " + quoted(dir.file("assets.json")) + " --plan", false);
        ASSERT_EQ(plan.exit_code, 0) << plan.out;
        const nlohmann::json p = nlohmann::json::parse(plan.out);
        EXPECT_TRUE(p["assets"][0]["up_to_date"].get<bool>());
        EXPECT_FALSE(p["assets"][1]["up_to_date"].get<bool>());
    }
}

}  // namespace
