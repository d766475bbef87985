// Hostile input at the command line (issue 32): usage errors exit 2 everywhere, inputs that are not
// regular files are refused at once, output names near the file-name limit work, and no message says
// "internal error".
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <sys/stat.h>

namespace {
namespace fs = std::filesystem;
using lodforge::test::CliRun;
using lodforge::test::quoted;
using lodforge::test::run_cli;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;

TEST(CliHostile, UsageErrorsExitTwoWhateverCli11CallsThem) {
    ScratchDir dir("cli-usage");
    const std::string ply = quoted(shared_data("color-open3d-small/color.ply"));
    // CLI11's own codes were 105 (validation), 106 (required), 109 (extras), ...
    const char* const usage[] = {
        "strips extract --lod 2 x.lodstrips -o y.ply",  // was 105
        "info --bogus x.ply",
        "convert",
        "convert a.ply b.ply c.ply",  // was 109
        "octree build x.ply",          // -o missing
        "no-such-command",
    };
    for (const char* args : usage) {
        const CliRun r = run_cli(args);
        EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
        EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;
    }
    // Values a command checks itself are usage errors too.
    const CliRun weights = run_cli("simplify " + ply + " " + quoted(dir.file("o.ply")) + " --ratio 0.5 --weights bogus=1");
    EXPECT_EQ(weights.exit_code, 2) << weights.out;
    EXPECT_FALSE(fs::exists(dir.file("o.ply")));
    EXPECT_EQ(run_cli("--help").exit_code, 0);
    EXPECT_EQ(run_cli("strips extract --help").exit_code, 0);
}

TEST(CliHostile, FifoAndDeviceInputsAreRefusedNotReadForever) {
    ScratchDir dir("cli-fifo");
    const std::string fifo = dir.file("pipe.ply");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
    // `timeout` turns a regression (a blocked open) into exit 124 instead of a hung test.
    const std::vector<std::string> commands = {"info " + quoted(fifo),
                                               "octree build " + quoted(fifo) + " -o " + quoted(dir.file("o.lfo")),
                                               "info /dev/zero", "strips info /dev/zero", "octree info /dev/zero",
                                               "mcoctree info /dev/zero"};
    for (const std::string& args : commands) {
        const CliRun r = lodforge::test::run_command("timeout 30 " + std::string(LODFORGE_BIN_DIR) + "/lodforge --quiet " +
                                                     args + " 2>&1");
        EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.out;
        EXPECT_NE(r.out.find("not a regular file"), std::string::npos) << args << "\n" << r.out;
    }
    EXPECT_FALSE(fs::exists(dir.file("o.lfo")));
}

TEST(CliHostile, OutputNamedNearTheFileNameLimitIsWritten) {
    ScratchDir dir("cli-long-name");
    const std::string name = std::string(250, 'a') + ".ply";  // 254 bytes: the temporary's suffix used to overflow
    const CliRun r = run_cli("convert " + quoted(shared_data("color-open3d-small/color.ply")) + " " + quoted(dir.file(name)));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(fs::exists(dir.file(name)));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(CliHostile, GlbNamedWithBytesThatAreNotUtf8IsWritten) {
    ScratchDir dir("cli-utf8");
    const std::string name = dir.file("bad\xff\xfe.glb");  // the mesh name in the JSON came from it: "internal error"
    const CliRun r = run_cli("convert " + quoted(shared_data("color-open3d-small/color.ply")) + " " + quoted(name));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    ASSERT_TRUE(fs::exists(name));
    const CliRun info = run_cli("info " + quoted(name));
    EXPECT_EQ(info.exit_code, 0) << info.out;
}

// An output that cannot be written (here: under a regular file, which no user, root included, can
// create a directory in) fails before the long part with exit 1 and the user's own path; the names of
// temporaries (".NAME.tmp-PID-N", ".lodforge-tmp-PID-N") are never shown, and nothing is left.
TEST(CliHostile, UnwritableOutputsNameTheUsersPathNotATemporary) {
    ScratchDir dir("cli-unwritable");
    const std::string ply = shared_data("color-open3d-small/color.ply");
    const std::string blocker = dir.file("file.txt");
    std::ofstream(blocker) << "a file, not a directory\n";
    const std::string under = blocker + "/sub";
    const std::vector<std::string> commands = {
        "lod " + quoted(ply) + " -o " + quoted(under) + " --levels 0.5",
        "pack " + quoted(ply) + " -o " + quoted(under) + " --levels 0.5",
        "octree build " + quoted(ply) + " -o " + quoted(under + "/o.lfo"),
        "octree build " + quoted(ply) + " -o " + quoted(dir.file("o.lfo")) + " --temp-dir " + quoted(under),
        "strips " + quoted(ply) + " -o " + quoted(under + "/o.lodstrips"),
        "convert " + quoted(ply) + " " + quoted(under + "/o.ply"),
        "simplify " + quoted(ply) + " -o " + quoted(under + "/o.ply") + " --ratio 0.5",
    };
    for (const std::string& args : commands) {
        SCOPED_TRACE(args);
        const CliRun r = run_cli(args);
        EXPECT_EQ(r.exit_code, 1) << r.out;
        EXPECT_NE(r.out.find(under), std::string::npos) << r.out;
        for (const char* internal : {".tmp-", ".lodforge-tmp-", "lodforge-method-", "internal error", "bad_alloc"})
            EXPECT_EQ(r.out.find(internal), std::string::npos) << r.out;
        std::vector<std::string> left;
        for (const auto& e : fs::directory_iterator(dir.path())) left.push_back(e.path().filename().string());
        EXPECT_EQ(left, std::vector<std::string>{"file.txt"});
    }
}

// A write that fails in the octree's scratch files (here the file-size limit stands in for a full
// disk) names the user's output and the directory of the temporaries, not the scratch file.
TEST(CliHostile, FullDiskDuringTheOctreeBuildNamesTheOutput) {
    ScratchDir dir("cli-octree-efbig");
    const std::string out = dir.file("dragon.lfo");
    // SIGXFSZ ignored (inherited through exec), so the write fails with EFBIG instead of killing.
    const CliRun r = lodforge::test::run_command(
        "bash -c \"trap '' XFSZ; ulimit -f 2048; exec " + std::string(LODFORGE_BIN_DIR) + "/lodforge --quiet octree build " +
        quoted(shared_data("scan-dragon/dragon_vrip.ply")) + " -o " + quoted(out) + " --memory 4\" 2>&1");
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("lodforge: error: " + out + ": "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("write failed"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find(".lodforge-tmp-"), std::string::npos) << r.out;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 0);
}

}  // namespace
