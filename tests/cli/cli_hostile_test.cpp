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

}  // namespace
