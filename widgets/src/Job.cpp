#include "lodforge/widgets/Job.h"

#include "lodforge/error.h"
#include "lodforge/widgets/QueuedProgress.h"

#include <QElapsedTimer>
#include <QtConcurrent/QtConcurrentRun>

#include <exception>
#include <new>

namespace lodforge::widgets {

Job::Job(QString name, Work work, QObject* parent)
    : QObject(parent), name_(std::move(name)), work_(std::move(work)) {
    progress_ = std::make_unique<QueuedProgress>(this, [this](double fraction, const QString& stage) {
        emit progressChanged(fraction, stage);
    });
    connect(&watcher_, &QFutureWatcher<JobResult>::finished, this, [this] { emit finished(watcher_.result()); });
}

Job::~Job() {
    progress_->cancel();
    watcher_.waitForFinished();
}

void Job::start() {
    if (watcher_.isRunning()) return;
    QueuedProgress* progress = progress_.get();
    watcher_.setFuture(QtConcurrent::run([name = name_, work = work_, progress] { return run(name, work, progress); }));
}

void Job::cancel() { progress_->cancel(); }

bool Job::isCancelling() const { return progress_->cancelled(); }

bool Job::isRunning() const { return watcher_.isRunning(); }

JobResult Job::run(const QString& name, const Work& work, Progress* progress) {
    JobResult result;
    result.name = name;
    QElapsedTimer timer;
    timer.start();
    try {
        if (progress && progress->cancelled()) throw Error(Error::Kind::cancelled, "cancelled");
        work(progress);
        result.status = JobResult::Status::ok;
    } catch (const Error& e) {
        result.status = e.kind() == Error::Kind::cancelled ? JobResult::Status::cancelled : JobResult::Status::failed;
        result.error = QString::fromUtf8(e.what());
    } catch (const std::bad_alloc&) {
        result.status = JobResult::Status::failed;
        result.error = QStringLiteral("%1: not enough memory for this mesh").arg(name);
    } catch (const std::exception& e) {
        result.status = JobResult::Status::failed;
        result.error = QStringLiteral("%1: %2").arg(name, QString::fromUtf8(e.what()));
    } catch (...) {
        result.status = JobResult::Status::failed;
        result.error = QStringLiteral("%1: unknown error").arg(name);
    }
    result.elapsedMs = timer.elapsed();
    return result;
}

}  // namespace lodforge::widgets
