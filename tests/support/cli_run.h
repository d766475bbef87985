// Runs the real `lodforge` executable the way users and scripts do: a shell command line, exit code
// and output captured.
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

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

// Single-quoted for the shell (the test paths contain no quotes).
inline std::string quoted(const std::string& s) { return "'" + s + "'"; }

}  // namespace lodforge::test
