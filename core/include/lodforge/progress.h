// Progress reporting and cancellation for long operations. One small interface passed by pointer into
// every long algorithm (nullptr = nobody is listening); the CLI draws a terminal bar from it and the
// studio a progress bar with Cancel.
#pragma once

#include <atomic>
#include <string_view>

namespace lodforge {

class Progress {
public:
    virtual ~Progress() = default;
    // fraction in [0, 1] of the current stage; called often, so implementations must be cheap.
    virtual void report(double fraction, std::string_view stage) = 0;
    // Polled by algorithms; when true they throw Error(Kind::cancelled) at the next safe point.
    virtual bool cancelled() const { return false; }
};

// Convenience for algorithms: report and throw if cancelled. Safe to call with nullptr.
void check_progress(Progress* progress, double fraction, std::string_view stage);

// A Progress whose cancel flag can be set from another thread (GUI Cancel button, SIGINT).
class CancelFlagProgress : public Progress {
public:
    void report(double, std::string_view) override {}
    void cancel() { cancel_.store(true, std::memory_order_relaxed); }
    bool cancelled() const override { return cancel_.load(std::memory_order_relaxed); }

private:
    std::atomic<bool> cancel_{false};
};

}  // namespace lodforge
