// One pending run of an interactive update (a slider drag, a camera move): requests made while one is
// pending merge into it. By the last run's time: fast work runs on the next turn of the event loop (the
// view follows the drag); slower work runs at most once per its own duration while requests go on
// (half the time left to the event loop); slow work runs only after the requests pause (debounce), so
// it never queues behind itself.
#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

#include <functional>
#include <utility>

namespace lodforge::widgets {

class CoalescedUpdate final : public QObject {
public:
    static constexpr double fastMs = 30;   // faster: at once
    static constexpr double slowMs = 150;  // slower: after a pause
    static constexpr int pauseMs = 150;

    CoalescedUpdate(std::function<void()> work, QObject* parent) : QObject(parent), work_(std::move(work)) {
        timer_.setSingleShot(true);
        connect(&timer_, &QTimer::timeout, this, [this] { run(); });
    }

    void request() {
        if (lastMs_ > slowMs) {
            timer_.start(pauseMs);  // restarted by every request: runs once they pause
        } else if (!timer_.isActive()) {
            timer_.start(lastMs_ > fastMs ? int(lastMs_) : 0);
        }
    }
    // Runs now (tests, programmatic changes), dropping a pending request.
    void run() {
        timer_.stop();
        QElapsedTimer clock;
        clock.start();
        work_();
        lastMs_ = double(clock.nsecsElapsed()) / 1e6;
    }
    void cancel() { timer_.stop(); }
    bool pending() const { return timer_.isActive(); }
    double lastMs() const { return lastMs_; }

private:
    std::function<void()> work_;
    QTimer timer_;
    double lastMs_ = 0;
};

}  // namespace lodforge::widgets
