// Interrupted work (issue 32): a command ended by SIGINT (Ctrl+C), SIGTERM (kill, CI timeouts) or SIGHUP
// (a closed terminal) while its temporary files exist exits 128 + the signal, as a shell reports it, and
// leaves neither temporaries nor partial output. `octree build` has its own test in tests/octree.
#include "support/cli_run.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

namespace {
namespace fs = std::filesystem;
using lodforge::test::ScratchDir;
using lodforge::test::shared_data;
using lodforge::test::spawn_cli;
using lodforge::test::wait_cli;

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

std::vector<std::string> names_in(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    return names;
}

// LodForge's temporaries are hidden siblings: ".NAME.tmp-PID-N" files (AtomicFile) and
// ".NAME.lodforge-tmp-PID-N" / ".lodforge-tmp-PID-N" directories (staged outputs, octree scratch).
bool has_temporary(const fs::path& dir) {
    for (const std::string& name : names_in(dir))
        if (name.starts_with('.') && (name.find(".tmp-") != std::string::npos || name.find(".lodforge-tmp-") != std::string::npos))
            return true;
    return false;
}

struct Interrupted {
    bool signalled = false;  // a temporary was seen and the signal sent
    int exit_code = -1;
};

// Runs the command, polls `watched` (every 2 ms, for at most a minute) until a temporary appears there,
// then sends the signal. When the command ends first, no signal is sent.
Interrupted interrupt_at_temporary(const std::vector<std::string>& args, const fs::path& watched, int signal_number,
                                   const std::vector<std::pair<std::string, std::string>>& env = {}) {
    Interrupted r;
    const pid_t pid = spawn_cli(args, env);
    for (int i = 0; i < 30000; ++i) {
        if (has_temporary(watched)) {
            r.signalled = ::kill(pid, signal_number) == 0;
            break;
        }
        int status = 0;
        if (::waitpid(pid, &status, WNOHANG) == pid) {
            r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            return r;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (!r.signalled) ::kill(pid, SIGKILL);  // the bound ran out: the test fails below, without a stray process
    r.exit_code = wait_cli(pid).exit_code;
    return r;
}

// The staging directory of `lod` and `pack` exists from after the input is read to the end: the
// dragon's simplification keeps it there for seconds, so the signal always lands while it exists.
TEST(CliSignal, LodAndPackLeaveNoStagingDirectoryAndNoOutput) {
    for (const char* command : {"lod", "pack"}) {
        for (const int signal_number : kSignals) {
            SCOPED_TRACE(std::string(command) + " " + std::to_string(signal_number));
            ScratchDir dir("cli-signal-staged");
            const Interrupted r = interrupt_at_temporary(
                {command, shared_data("scan-dragon/dragon_vrip.ply"), "-o", dir.file("out"), "--levels", "0.5,0.1"},
                dir.path(), signal_number);
            ASSERT_TRUE(r.signalled) << "no staging directory appeared; exit " << r.exit_code;
            EXPECT_EQ(r.exit_code, 128 + signal_number);
            EXPECT_TRUE(names_in(dir.path()).empty()) << names_in(dir.path()).front();
        }
    }
}

// `pack --method octree` builds its octree in the system temporary directory (TMPDIR), besides the
// staging directory beside the output: both go.
TEST(CliSignal, PackOctreeLeavesNothingInTmpdir) {
    for (const int signal_number : kSignals) {
        SCOPED_TRACE(signal_number);
        ScratchDir dir("cli-signal-pack-octree");
        const fs::path tmp = dir.path() / "tmp";
        fs::create_directory(tmp);
        const Interrupted r = interrupt_at_temporary(
            {"pack", shared_data("scan-dragon/dragon_vrip.ply"), "-o", dir.file("out"), "--method", "octree"}, tmp,
            signal_number, {{"TMPDIR", tmp.string()}});
        ASSERT_TRUE(r.signalled) << "no octree scratch directory appeared in TMPDIR; exit " << r.exit_code;
        EXPECT_EQ(r.exit_code, 128 + signal_number);
        EXPECT_TRUE(names_in(tmp).empty()) << names_in(tmp).front();
        EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"tmp"});
    }
}

// Single-file outputs go through a temporary beside the target (AtomicFile) that exists only while
// the file is written, so a signal can come too late to cancel: then the run ends normally with the
// whole output. Either way nothing else may remain; a few tries make sure the cancelled path is taken.
TEST(CliSignal, ConvertLeavesNoTemporaryFile) {
    for (const int signal_number : kSignals) {
        SCOPED_TRACE(signal_number);
        bool cancelled = false;
        for (int attempt = 0; attempt < 5 && !cancelled; ++attempt) {
            ScratchDir dir("cli-signal-convert");
            const std::string out = dir.file("out.ply");
            const Interrupted r = interrupt_at_temporary(
                {"convert", shared_data("scan-dragon/dragon_vrip.ply"), out, "--encoding", "ascii"}, dir.path(),
                signal_number);
            ASSERT_TRUE(r.signalled || r.exit_code == 0) << "exit " << r.exit_code;
            if (r.exit_code == 128 + signal_number) {
                cancelled = true;
                EXPECT_TRUE(names_in(dir.path()).empty()) << names_in(dir.path()).front();
            } else {
                EXPECT_EQ(r.exit_code, 0);
                EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"out.ply"});
            }
        }
        EXPECT_TRUE(cancelled) << "the signal never landed while the output was being written";
    }
}

// The single-output commands spend their time computing, before any file exists: a signal then must
// still end them promptly with 128 + the signal and no output. Each input keeps its command busy for
// seconds, so a signal sent 300 ms after the start lands while it works.
TEST(CliSignal, ComputingCommandsStopAndWriteNothing) {
    struct Case {
        std::vector<std::string> args;  // the output is appended as "-o DIR/out.EXT"
        std::string extension;
    };
    const std::string dragon = shared_data("scan-dragon/dragon_vrip.ply");
    const std::vector<Case> cases = {
        {{"simplify", dragon, "--ratio", "0.1"}, ".ply"},
        {{"strips", dragon}, ".lodstrips"},
        {{"mcoctree", "build", dragon, "--resolution", "256"}, ".mco"},
        {{"morph", "build", shared_data("seq-horse-gallop")}, ".lfmorph"},
    };
    for (const Case& c : cases) {
        for (const int signal_number : {SIGINT, SIGTERM}) {
            SCOPED_TRACE(c.args.front() + " " + std::to_string(signal_number));
            ScratchDir dir("cli-signal-compute");
            std::vector<std::string> args = c.args;
            args.insert(args.end(), {"-o", dir.file("out" + c.extension)});
            const pid_t pid = spawn_cli(args);
            std::this_thread::sleep_for(std::chrono::milliseconds(300));
            int status = 0;
            ASSERT_EQ(::waitpid(pid, &status, WNOHANG), 0) << "the command ended within 300 ms";
            ASSERT_EQ(::kill(pid, signal_number), 0);
            EXPECT_EQ(wait_cli(pid).exit_code, 128 + signal_number);
            EXPECT_TRUE(names_in(dir.path()).empty()) << names_in(dir.path()).front();
        }
    }
}

}  // namespace
