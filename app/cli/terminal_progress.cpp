#include "terminal_progress.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <unistd.h>

namespace lodforge::cli {
namespace {
volatile std::sig_atomic_t g_interrupted = 0;  // the signal number, 0 when none came
extern "C" void on_interrupt(int signal_number) {
    g_interrupted = signal_number;
    // A second signal of the same kind ends the process at once (the user insists).
    std::signal(signal_number, SIG_DFL);
}
}  // namespace

// SIGTERM (kill, systemd, CI timeouts) and SIGHUP (a closed terminal) cancel like Ctrl+C: the command
// stops at its next progress check and its temporary files are removed on the way out.
void install_interrupt_handler() {
    for (int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, on_interrupt);
}
int cancelled_exit_code() { return 128 + (g_interrupted ? static_cast<int>(g_interrupted) : SIGINT); }
bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

TerminalProgress::TerminalProgress(bool enabled) : enabled_(enabled) {}
TerminalProgress::~TerminalProgress() { finish(); }

bool TerminalProgress::cancelled() const { return g_interrupted != 0; }

void TerminalProgress::report(double fraction, std::string_view stage) {
    if (!enabled_) return;
    const int percent = static_cast<int>(fraction * 100.0 + 0.5);
    const auto now = std::chrono::steady_clock::now();
    // Redraw at most ~20 times a second; terminals are slow and algorithms report often.
    if (percent == last_percent_ && stage == last_stage_) return;
    if (now - last_draw_ < std::chrono::milliseconds(50) && percent != 100 && stage == last_stage_) return;
    last_draw_ = now;
    last_percent_ = percent;
    last_stage_ = stage;
    constexpr int width = 30;
    const int filled = percent * width / 100;
    std::fprintf(stderr, "\r%-24.24s [", last_stage_.c_str());
    for (int i = 0; i < width; ++i) std::fputc(i < filled ? '#' : '.', stderr);
    std::fprintf(stderr, "] %3d%%", percent);
    std::fflush(stderr);
    drawn_ = true;
}

void TerminalProgress::finish() {
    if (drawn_) {
        std::fprintf(stderr, "\r%*s\r", 64, "");
        std::fflush(stderr);
        drawn_ = false;
    }
}

}  // namespace lodforge::cli
