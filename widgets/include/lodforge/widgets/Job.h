// Long work off the GUI thread (LOD chains, heat maps, exports): progress, Cancel, and a result that says
// what happened instead of an exception crossing the thread.
//
//   auto out = std::make_shared<Output>();
//   auto* job = new Job(tr("LOD chain"), [out, input](Progress* p) { out->levels = build(input, p); }, this);
//   connect(job, &Job::finished, this, [out](const JobResult& r) { if (r.ok()) show(out->levels); });
//   job->start();
//
// The work writes its output into state it captured; the job only reports how it ended. Whatever the work
// throws is caught on the worker and comes back as a failed (or, for Error(cancelled), cancelled) result.
#pragma once

#include "lodforge/progress.h"

#include <QFutureWatcher>
#include <QObject>
#include <QString>

#include <functional>
#include <memory>

namespace lodforge::widgets {

class QueuedProgress;

struct JobResult {
    enum class Status { ok, failed, cancelled };
    Status status = Status::failed;
    QString name;          // what ran, as given to the job
    QString error;         // for failed: the problem (lodforge::Error messages name the file)
    qint64 elapsedMs = 0;  // wall time of the work

    bool ok() const { return status == Status::ok; }
};

class Job : public QObject {
    Q_OBJECT

public:
    using Work = std::function<void(lodforge::Progress*)>;

    Job(QString name, Work work, QObject* parent = nullptr);
    // Cancels and waits for the worker: the work reports to this object.
    ~Job() override;

    void start();
    // Asks the work to stop at its next progress check; finished() then reports Status::cancelled.
    void cancel();
    bool isCancelling() const;
    bool isRunning() const;
    const QString& name() const { return name_; }

    // Runs `work` here and now, catching everything. Never throws.
    static JobResult run(const QString& name, const Work& work, lodforge::Progress* progress);

signals:
    void progressChanged(double fraction, const QString& stage);
    void finished(const lodforge::widgets::JobResult& result);

private:
    QString name_;
    Work work_;
    std::unique_ptr<QueuedProgress> progress_;
    QFutureWatcher<JobResult> watcher_;
};

}  // namespace lodforge::widgets
