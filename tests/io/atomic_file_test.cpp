#include "lodforge/io/atomic_file.h"
#include "lodforge/error.h"
#include "support/test_paths.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sys/resource.h>
#include <sys/stat.h>
#include <thread>
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

// A user who points an output at a full device (`ln -s /dev/full out.ply`) must get an error: the
// temporary-and-rename used to replace the link with a regular file and report success.
TEST(AtomicFile, LinkToAFullDeviceIsAWriteErrorAndTheLinkSurvives) {
    test::ScratchDir dir("atomic-devfull");
    const std::string link = dir.file("out.ply");
    fs::create_symlink("/dev/full", link);
    try {
        AtomicFile f(link);
        f.stream() << std::string(1 << 16, 'x');
        f.commit();
        FAIL() << "writing to /dev/full succeeded";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), Error::Kind::io);
        EXPECT_NE(std::string(e.what()).find(link), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("write failed"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_symlink(link)) << "the link was replaced";
    EXPECT_EQ(entries(dir.path()), 1u) << "no temporary may be left";
}

TEST(AtomicFile, SymbolicLinkIsWrittenThrough) {
    test::ScratchDir dir("atomic-symlink");
    const std::string real = dir.file("real.txt"), link = dir.file("link.txt");
    { std::ofstream(real) << "old"; }
    fs::create_symlink(real, link);
    {
        AtomicFile f(link);
        f.stream() << "new";
        f.commit();
    }
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(slurp(real), "new");
    EXPECT_EQ(entries(dir.path()), 2u);
}

TEST(AtomicFile, FifoIsWrittenInPlace) {
    test::ScratchDir dir("atomic-fifo");
    const std::string fifo = dir.file("pipe.ply");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] { received = slurp(fifo); });
    {
        AtomicFile f(fifo);
        f.stream() << "through the pipe";
        f.commit();
    }
    reader.join();
    EXPECT_EQ(received, "through the pipe");
    EXPECT_EQ(fs::status(fifo).type(), fs::file_type::fifo) << "the FIFO was replaced by a file";
    EXPECT_EQ(entries(dir.path()), 1u);
}
