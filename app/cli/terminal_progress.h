// The CLI's face of lodforge::Progress: a one-line bar on stderr when it is a terminal, silence when
// it is not (CI logs, pipes), and Ctrl+C turned into a clean cancellation instead of a killed process
// that would leave temporary files behind.
#pragma once

#include "lodforge/progress.h"

#include <chrono>
#include <string>

namespace lodforge::cli {

class TerminalProgress : public Progress {
public:
    explicit TerminalProgress(bool enabled);
    ~TerminalProgress() override;
    void report(double fraction, std::string_view stage) override;
    bool cancelled() const override;
    void finish();

private:
    bool enabled_;
    bool drawn_ = false;
    int last_percent_ = -1;
    std::string last_stage_;
    std::chrono::steady_clock::time_point last_draw_{};
};

// Installs SIGINT, SIGTERM and SIGHUP handlers that set the flag TerminalProgress::cancelled() reads.
void install_interrupt_handler();
// The exit code of a cancelled run: 128 + the signal that cancelled it (130 for Ctrl+C).
int cancelled_exit_code();
// Exit code of a usage error (unknown option, option value out of range).
inline constexpr int kExitUsage = 2;
bool stderr_is_terminal();

}  // namespace lodforge::cli
