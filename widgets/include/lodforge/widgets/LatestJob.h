// Interactive work on a worker where only the newest request matters (a slider's index, a camera's cut):
// the bookkeeping the docks share (docs/studio.md, "Work off the GUI thread").
//
//   latest_ = new LatestJob([this]() -> std::optional<LatestJob::Run> {
//       if (!tree_) return std::nullopt;              // nothing to do any more
//       auto out = std::make_shared<Output>();
//       return LatestJob::Run{tr("Extraction"), [out, index = index_](Progress* p) { out->mesh = cut(index, p); },
//                             [this, out](const JobResult&) { show(out->mesh); }};
//   }, this);
//   connect(slider, &QSlider::valueChanged, this, [this](int i) { index_ = i; latest_->request(i); });
//
// - One job at a time. A request made while one runs waits for it (replacing any older waiting request),
//   and the run is made (`MakeRun`) only when the worker is free, from the state of then; so the newest
//   request is the only one that waits, and the work never queues behind itself.
// - A request cancels the running job at its next progress check unless it is the same request (equal
//   keys): the running job's result would arrive superseded anyway.
// - A result reaches `Run::show` only when its job ended ok and is still the newest request. Stale
//   results (ended ok, superseded meanwhile) are dropped, cancelled ones too; each case is counted.
// - Superseded::show makes it a throttle instead (the morph heat map while playing): a newer request
//   lets the running job finish and show its result, then the newest runs; while requests go on, a
//   result shows once per job's time instead of never.
// - request() starts at the next turn of the event loop (CoalescedUpdate), so the requests of one turn
//   make one job; requestNow() starts at once when the worker is free.
// - A failure ends the requests (the waiting one too, so a failing input is not retried in a loop) and
//   comes back as failed() with the job's message.
// - cancel() drops the waiting request and lets the running job go: it is cancelled, its result never
//   shows, and it deletes itself when it ends. stop() cancels it too but waits for its end, which
//   comes back as cancelled() (for a Cancel button whose outcome is reported, as the morph's open). What it holds (a tree, a store) it captured itself, so that
//   goes with it; destroying the LatestJob cancels every job, also those let go, and waits for them.
#pragma once

#include "lodforge/widgets/Job.h"

#include <QObject>
#include <QString>

#include <cstdint>
#include <functional>
#include <optional>

namespace lodforge::widgets {

class CoalescedUpdate;

class LatestJob final : public QObject {
    Q_OBJECT

public:
    struct Run {
        QString name;
        Job::Work work;  // on the worker; writes into state it captured
        // On the GUI thread, for the newest request's job that ended ok (never a stale or cancelled one).
        std::function<void(const JobResult&)> show;
    };
    // Called on the GUI thread when the worker is free and a request waits; nullopt: nothing to do (the
    // request is dropped).
    using MakeRun = std::function<std::optional<Run>()>;
    // What a newer request does to the running job.
    enum class Superseded { cancel, show };

    LatestJob(MakeRun make, QObject* parent, Superseded superseded = Superseded::cancel);
    ~LatestJob() override;

    // A new request, started at the next turn of the event loop (the requests of one turn make one job).
    // With a key, a request equal to the running job's key is that job's request: it keeps running and
    // its result is shown. Without one every request is new.
    void request(std::optional<std::uint64_t> key = std::nullopt);
    // The same, started now when the worker is free (programmatic changes, tests).
    void requestNow(std::optional<std::uint64_t> key = std::nullopt);
    // Drops the waiting request and lets the running job go (cancelled, its result dropped).
    void cancel();
    // Drops the waiting request and cancels the running job, whose end is still waited for: cancelled()
    // (or, had it finished meanwhile, show).
    void stop();

    // A request waits or its job runs: the newest request is not shown yet.
    bool isBusy() const { return wanted_ || running_ != nullptr; }
    // The job of the newest request is on the worker now (started, its end not handled yet).
    bool isWorkerBusy() const;

    // Since construction: results shown; those that ended ok but were superseded when they arrived;
    // those stopped early (cancelled for a newer request, or stopped by their own work); running jobs let
    // go by cancel(); failures.
    int shownCount() const { return shown_; }
    int droppedCount() const { return dropped_; }
    int cancelledCount() const { return cancelled_; }
    int letGoCount() const { return letGo_; }
    int failedCount() const { return failed_; }
    // Jobs started.
    int startedCount() const { return started_; }

signals:
    // Of the job working for the newest request only.
    void progressChanged(double fraction, const QString& stage);
    void failed(const QString& error);
    // The newest request's job ended cancelled (stop(), or its work stopped by itself).
    void cancelled(const lodforge::widgets::JobResult& result);
    // isBusy() or isWorkerBusy() may have changed (a request, a start, an end, cancel()).
    void changed();

private:
    struct Ticket {
        std::uint64_t serial = 0;  // one per distinct request
        std::optional<std::uint64_t> key;
    };

    void record(std::optional<std::uint64_t> key);
    void start();
    void finish(Job* job, const Ticket& ticket, const std::function<void(const JobResult&)>& show,
                const JobResult& result);

    MakeRun make_;
    Superseded superseded_;
    CoalescedUpdate* update_ = nullptr;
    Job* running_ = nullptr;  // the job whose result is waited for; let-go ones are only children
    Ticket runningTicket_;
    Ticket newest_;
    bool wanted_ = false;  // the newest request is not shown yet
    std::uint64_t serial_ = 0;
    int shown_ = 0;
    int dropped_ = 0;
    int cancelled_ = 0;
    int letGo_ = 0;
    int failed_ = 0;
    int started_ = 0;
};

}  // namespace lodforge::widgets
