// Progress callbacks and errors across the Python boundary.
//
// A Python callable `progress(fraction, stage)` becomes a lodforge::Progress. The core's work runs
// with the GIL released; each report takes the GIL back to call the callable (from whichever thread
// reports), throttled so a tight loop does not spend its time in Python. The callable returning False
// or raising sets the cancel flag the core polls, so the work stops at its next safe point with
// Error(cancelled); a Python exception from the callable is then re-raised in its place.
#pragma once

#include "lodforge/progress.h"

#include <pybind11/pybind11.h>

#include <atomic>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

namespace lodforge::python {

class CallbackProgress final : public Progress {
public:
    explicit CallbackProgress(pybind11::object callback) : callback_(std::move(callback)) {}
    ~CallbackProgress() override;
    void report(double fraction, std::string_view stage) override;
    bool cancelled() const override { return cancelled_.load(std::memory_order_relaxed); }
    // Re-raises the callable's exception, if it raised one (GIL held).
    void rethrow_callback_error();

private:
    pybind11::object callback_;
    std::atomic<bool> cancelled_{false};
    std::mutex mutex_;  // the throttle state below
    double last_fraction_ = -1;
    std::string last_stage_;
    std::optional<pybind11::error_already_set> error_;
};

// Runs `work(Progress*)` with the GIL released; `callback` None passes nullptr.
template <class Work>
auto run_with_progress(const pybind11::object& callback, Work&& work) {
    if (callback.is_none()) {
        pybind11::gil_scoped_release release;
        return work(nullptr);
    }
    CallbackProgress progress(callback);
    auto result = [&] {
        try {
            pybind11::gil_scoped_release release;
            return work(&progress);
        } catch (...) {
            progress.rethrow_callback_error();
            throw;
        }
    }();
    progress.rethrow_callback_error();  // the callable raised where the work no longer polled
    return result;
}

// Registers lodforge.Error (and lodforge.Cancelled, its subclass for Error(cancelled)) and the
// translation of lodforge::Error into them: the message is the core's, `kind` its Error::Kind name.
void bind_errors(pybind11::module_& m);

}  // namespace lodforge::python
