#include "lodforge/atomic_file.h"
#include "lodforge/error.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace lodforge;
namespace fs = std::filesystem;

namespace {
std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}
std::size_t entries(const fs::path& dir) {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}
}  // namespace

TEST(AtomicFile, CommitReplacesTheTargetAndLeavesNoTemporary) {
    test::ScratchDir dir("atomic-commit");
    const std::string target = dir.file("out.txt");
    { std::ofstream(target) << "old"; }
    {
        AtomicFile f(target);
        f.stream() << "new content";
        EXPECT_EQ(slurp(target), "old") << "the target must not change before commit";
        f.commit();
    }
    EXPECT_EQ(slurp(target), "new content");
    EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(AtomicFile, AbandonedWriteKeepsTheOldFileAndRemovesTheTemporary) {
    test::ScratchDir dir("atomic-abandon");
    const std::string target = dir.file("out.txt");
    { std::ofstream(target) << "old"; }
    {
        AtomicFile f(target);
        f.stream() << "half written";
    }
    EXPECT_EQ(slurp(target), "old");
    EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(AtomicFile, MissingDirectoryAndFileAsDirectoryAreIoErrorsNamingTheTarget) {
    test::ScratchDir dir("atomic-missing");
    const std::string in_missing = dir.file("nope/out.ply");
    try {
        AtomicFile f(in_missing);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::io);
        EXPECT_NE(std::string(e.what()).find(in_missing), std::string::npos) << e.what();
    }
    // A regular file in the parent position: fails the same way for root, unlike permission bits.
    const std::string blocker = dir.file("blocker");
    { std::ofstream(blocker) << "x"; }
    EXPECT_THROW(AtomicFile(blocker + "/out.ply"), Error);
    EXPECT_THROW(AtomicFile(dir.path().string()), Error);
}

TEST(AtomicFile, FullDiskIsReportedAndLeavesNothingBehind) {
    // RLIMIT_FSIZE makes write() fail with EFBIG exactly like a full file system would (ENOSPC)
    // from the writer's point of view; it needs no privileges, so it works on any test machine.
    test::ScratchDir dir("atomic-full");
    const std::string target = dir.file("big.bin");
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        std::signal(SIGXFSZ, SIG_IGN);
        rlimit limit{4096, 4096};
        setrlimit(RLIMIT_FSIZE, &limit);
        int code = 10;
        try {
            AtomicFile f(target);
            const std::string block(1 << 16, 'x');
            for (int i = 0; i < 64; ++i) f.stream() << block;
            f.commit();
            code = 11;  // must not get here
        } catch (const Error& e) {
            const bool names_file = std::string(e.what()).find(target) != std::string::npos;
            code = (e.kind() == Error::Kind::io && names_file) ? 0 : 12;
        }
        _exit(code);
    }
    int status = 0;
    waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "10 = no exception, 11 = commit succeeded, 12 = wrong error";
    EXPECT_FALSE(fs::exists(target));
    EXPECT_EQ(entries(dir.path()), 0u) << "the temporary file must be removed";
}
