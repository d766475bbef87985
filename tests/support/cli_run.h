// Runs the real `lodforge` executable the way users and scripts do: a shell command line, exit code
// and output captured.
#pragma once

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <utility>
#include <vector>

namespace lodforge::test {

struct CliRun {
    int exit_code = -1;
    std::string out;  // stdout, plus stderr when merged
};

// Any shell command line (the validator, coreutils), its exit code and stdout.
inline CliRun run_command(const std::string& cmd) {
    CliRun r;
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buf{};
    while (std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) r.out.append(buf.data(), n);
    const int status = pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

inline CliRun run_cli(const std::string& args, bool merge_stderr = true) {
    return run_command(std::string(LODFORGE_BIN_DIR) + "/lodforge --quiet " + args +
                       (merge_stderr ? " 2>&1" : " 2>/dev/null"));
}

// `lodforge --quiet ARGS...` as a child process with its output discarded, for tests that signal it or
// measure it while it runs; `env` is set in the child only (TMPDIR=...).
inline pid_t spawn_cli(const std::vector<std::string>& args,
                       const std::vector<std::pair<std::string, std::string>>& env = {}) {
    const std::string bin = std::string(LODFORGE_BIN_DIR) + "/lodforge";
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, 1);
        ::dup2(null, 2);
        for (const auto& [name, value] : env) ::setenv(name.c_str(), value.c_str(), 1);
        std::vector<char*> argv{const_cast<char*>(bin.c_str()), const_cast<char*>("--quiet")};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(bin.c_str(), argv.data());
        ::_exit(127);
    }
    return pid;
}

struct Waited {
    int exit_code = -1;  // 128 + the signal when a signal ended it, as a shell reports it
    long peak_kb = 0;    // peak resident memory (wait4's ru_maxrss)
};

inline Waited wait_cli(pid_t pid) {
    Waited w;
    int status = 0;
    rusage usage{};
    if (::wait4(pid, &status, 0, &usage) != pid) return w;
    w.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    w.peak_kb = usage.ru_maxrss;  // kilobytes on Linux
    return w;
}

// Single-quoted for the shell (the test paths contain no quotes).
inline std::string quoted(const std::string& s) { return "'" + s + "'"; }

// Whether a command's output mentions `part`.
inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace lodforge::test
