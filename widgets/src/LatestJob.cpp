#include "lodforge/widgets/LatestJob.h"

#include "CoalescedUpdate.h"

#include <utility>

namespace lodforge::widgets {

LatestJob::LatestJob(MakeRun make, QObject* parent, Superseded superseded)
    : QObject(parent), make_(std::move(make)), superseded_(superseded) {
    update_ = new CoalescedUpdate([this] { start(); }, this);
}

LatestJob::~LatestJob() {
    // Every job, also those let go that have not ended: all are cancelled first so that they stop side
    // by side, then each is waited for (its work reports to it).
    const QList<Job*> jobs = findChildren<Job*>(Qt::FindDirectChildrenOnly);
    for (Job* job : jobs) job->cancel();
    for (Job* job : jobs) delete job;
}

bool LatestJob::isWorkerBusy() const { return running_ != nullptr && running_->isRunning(); }

void LatestJob::record(std::optional<std::uint64_t> key) {
    const bool sameAsRunning = running_ && key && runningTicket_.key == key;
    newest_ = sameAsRunning ? runningTicket_ : Ticket{++serial_, key};
    wanted_ = true;
    if (running_ && runningTicket_.serial != newest_.serial && superseded_ == Superseded::cancel) running_->cancel();
}

void LatestJob::request(std::optional<std::uint64_t> key) {
    record(key);
    update_->request();
    emit changed();
}

void LatestJob::requestNow(std::optional<std::uint64_t> key) {
    record(key);
    update_->cancel();
    start();
    emit changed();
}

void LatestJob::cancel() {
    update_->cancel();
    wanted_ = false;
    if (running_) {
        running_->cancel();
        running_ = nullptr;  // its result is dropped; it deletes itself when it ends
        ++letGo_;
    }
    emit changed();
}

void LatestJob::stop() {
    update_->cancel();
    if (running_) {
        newest_ = runningTicket_;  // its end is the answer to the newest request
        running_->cancel();
    } else {
        wanted_ = false;
    }
    emit changed();
}

void LatestJob::start() {
    if (!wanted_ || running_) return;  // a running job starts the newest request when it ends
    std::optional<Run> run = make_();
    if (!run) {
        wanted_ = false;
        emit changed();
        return;
    }
    const Ticket ticket = newest_;
    runningTicket_ = ticket;
    Job* job = new Job(run->name, std::move(run->work), this);
    running_ = job;
    ++started_;
    connect(job, &Job::progressChanged, this, [this, job](double fraction, const QString& stage) {
        if (job == running_) emit progressChanged(fraction, stage);
    });
    connect(job, &Job::finished, this, [this, job, ticket, show = std::move(run->show)](const JobResult& r) {
        finish(job, ticket, show, r);
    });
    job->start();
    emit changed();
}

void LatestJob::finish(Job* job, const Ticket& ticket, const std::function<void(const JobResult&)>& show,
                       const JobResult& result) {
    job->deleteLater();
    if (job != running_) return;  // let go
    running_ = nullptr;
    if (result.status == JobResult::Status::failed) {
        wanted_ = false;
        ++failed_;
        emit failed(result.error);
    } else if (result.ok() && wanted_ && (ticket.serial == newest_.serial || superseded_ == Superseded::show)) {
        if (ticket.serial == newest_.serial) wanted_ = false;
        ++shown_;
        if (show) show(result);
    } else if (result.ok()) {
        ++dropped_;  // arrived after a newer request
    } else {
        ++cancelled_;  // stopped for a newer request, or by stop()
        if (wanted_ && ticket.serial == newest_.serial) {
            wanted_ = false;
            emit cancelled(result);
        }
    }
    start();  // the newest request, if one waits
    emit changed();
}

}  // namespace lodforge::widgets
