// LatestJob on its own (widgets/include/lodforge/widgets/LatestJob.h): the newest request wins, a stale
// result is dropped, a superseded job is cancelled, a request equal to the running one keeps it, Cancel
// and failures end the requests, and destroying it while jobs run waits for them. The work here is made
// in code: it blocks on a gate the test opens, so the order of events is the test's, not the scheduler's.
#include "lodforge/error.h"
#include "lodforge/widgets/LatestJob.h"

#include <QCoreApplication>
#include <QSignalSpy>
#include <QTest>

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

using lodforge::Progress;
using lodforge::widgets::JobResult;
using lodforge::widgets::LatestJob;

namespace {

// Work that holds until the test opens its gate; `pollCancel` decides whether it stops early when
// cancelled (as the docks' work does at each stage) or runs to the end regardless (a result that arrives
// superseded).
struct Gate {
    std::atomic<bool> open{false};
    std::atomic<int> running{0};   // works inside their body now
    std::atomic<int> entered{0};   // works that entered their body
    std::atomic<int> sawCancel{0};  // works that saw the cancel flag while held
};

struct Harness {
    std::shared_ptr<Gate> gate = std::make_shared<Gate>();
    int value = 0;                  // what the next job works on (the panel's state at start time)
    bool pollCancel = true;
    bool fail = false;
    std::vector<int> started;       // values of the jobs started, in order
    std::vector<int> shown;         // values whose result reached show
    std::shared_ptr<int> held;      // something the work keeps alive (a tree, a store)

    LatestJob::MakeRun make() {
        return [this]() -> std::optional<LatestJob::Run> {
            if (value < 0) return std::nullopt;
            const int v = value;
            started.push_back(v);
            auto out = std::make_shared<int>(-1);
            return LatestJob::Run{
                QStringLiteral("test job"),
                [gate = gate, v, out, poll = pollCancel, fail = fail, held = held](Progress* p) {
                    ++gate->entered;
                    ++gate->running;
                    bool saw = false;
                    while (!gate->open) {
                        if (p->cancelled() && !saw) {
                            saw = true;
                            ++gate->sawCancel;
                            if (poll) {
                                --gate->running;
                                throw lodforge::Error(lodforge::Error::Kind::cancelled, "cancelled");
                            }
                        }
                        std::this_thread::sleep_for(std::chrono::milliseconds(1));
                    }
                    p->report(0.5, "half");
                    --gate->running;
                    if (fail) throw lodforge::Error(lodforge::Error::Kind::io, "test.ply: broken");
                    *out = v;
                },
                [this, out](const JobResult&) { shown.push_back(*out); }};
        };
    }
};

bool waitRunning(const Gate& gate, int n = 1) {
    return QTest::qWaitFor([&] { return gate.running.load() == n; }, 10000);
}

// Asks for `value` now and waits until its job holds at the gate.
bool startHeld(Harness& h, LatestJob& job, int value) {
    h.value = value;
    job.requestNow();
    return waitRunning(*h.gate);
}

}  // namespace

class LatestJobTest : public QObject {
    Q_OBJECT

private slots:
    void requestsOfOneTurnMakeOneJobForTheNewest();
    void newerRequestCancelsTheRunningJobAndWins();
    void staleResultIsDropped();
    void equalKeyKeepsTheRunningJob();
    void cancelDropsTheWaitingRequestAndTheResult();
    void failureEndsTheRequestsWithItsMessage();
    void nothingToDoDropsTheRequest();
    void throttleShowsTheSupersededResultThenTheNewest();
    void stopReportsTheEndAsCancelled();
    void destructionWhileJobsRunWaitsForThem();
};

void LatestJobTest::requestsOfOneTurnMakeOneJobForTheNewest() {
    Harness h;
    h.gate->open = true;
    LatestJob job(h.make(), nullptr);
    for (int v = 1; v <= 5; ++v) {
        h.value = v;
        job.request();
    }
    QVERIFY(job.isBusy());
    QCOMPARE(job.startedCount(), 0);  // coalesced: nothing starts within the turn
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(h.started, std::vector<int>{5});
    QCOMPARE(h.shown, std::vector<int>{5});
    QCOMPARE(job.shownCount(), 1);
    QCOMPARE(job.cancelledCount() + job.droppedCount() + job.letGoCount(), 0);
}

void LatestJobTest::newerRequestCancelsTheRunningJobAndWins() {
    Harness h;
    LatestJob job(h.make(), nullptr);
    QSignalSpy progress(&job, &LatestJob::progressChanged);
    QVERIFY(startHeld(h, job, 1));
    QVERIFY(job.isWorkerBusy());
    h.value = 2;
    job.requestNow();  // the worker is busy: waits, and the running job is told to stop
    QCOMPARE(h.started, std::vector<int>{1});
    QTRY_COMPARE(h.gate->sawCancel.load(), 1);
    // Job 1 stopped; job 2 started for the newest value and holds at the gate.
    QTRY_COMPARE(h.started, (std::vector<int>{1, 2}));
    QVERIFY(waitRunning(*h.gate));
    QCOMPARE(job.cancelledCount(), 1);
    QVERIFY(h.shown.empty());
    h.gate->open = true;
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(h.shown, std::vector<int>{2});
    QCOMPARE(job.shownCount(), 1);
    QCOMPARE(job.droppedCount(), 0);
    // Progress of the job that was shown came through.
    QTRY_VERIFY(!progress.isEmpty());
    QCOMPARE(progress.last().at(1).toString(), QStringLiteral("half"));
}

void LatestJobTest::staleResultIsDropped() {
    Harness h;
    h.pollCancel = false;  // the work ignores the cancel flag and ends ok, superseded
    LatestJob job(h.make(), nullptr);
    QVERIFY(startHeld(h, job, 1));
    h.value = 2;
    job.requestNow();
    QTRY_COMPARE(h.gate->sawCancel.load(), 1);  // told to stop, but it goes on
    h.gate->open = true;
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(h.started, (std::vector<int>{1, 2}));
    QCOMPARE(h.shown, std::vector<int>{2});  // never 1: it arrived after request 2
    QCOMPARE(job.droppedCount(), 1);
    QCOMPARE(job.cancelledCount(), 0);
    QCOMPARE(job.shownCount(), 1);
}

void LatestJobTest::equalKeyKeepsTheRunningJob() {
    Harness h;
    LatestJob job(h.make(), nullptr);
    h.value = 7;
    job.requestNow(7);
    QVERIFY(waitRunning(*h.gate));
    job.requestNow(7);  // the same request: not cancelled, not started again
    job.request(7);
    QTest::qWait(50);
    QCOMPARE(h.gate->sawCancel.load(), 0);
    h.gate->open = true;
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(h.started, std::vector<int>{7});
    QCOMPARE(h.shown, std::vector<int>{7});
    // Another key does cancel.
    h.gate->open = false;
    job.requestNow(7);
    QVERIFY(waitRunning(*h.gate));
    h.value = 8;
    job.requestNow(8);
    QTRY_COMPARE(h.gate->sawCancel.load(), 1);
    h.gate->open = true;
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(h.shown, (std::vector<int>{7, 8}));
    QCOMPARE(job.cancelledCount(), 1);
}

void LatestJobTest::cancelDropsTheWaitingRequestAndTheResult() {
    Harness h;
    h.pollCancel = false;  // even a result that comes back ok must not show
    LatestJob job(h.make(), nullptr);
    QVERIFY(startHeld(h, job, 1));
    h.value = 2;
    job.request();  // waiting
    job.cancel();
    QVERIFY(!job.isBusy());
    QVERIFY(!job.isWorkerBusy());
    QCOMPARE(job.letGoCount(), 1);
    h.gate->open = true;
    QTRY_COMPARE(h.gate->running.load(), 0);
    QTest::qWait(100);  // the let-go job's end and a coalesced start would both have come by now
    QVERIFY(h.shown.empty());
    QCOMPARE(h.started, std::vector<int>{1});
    QCOMPARE(job.shownCount() + job.droppedCount(), 0);
    // Usable again afterwards.
    h.value = 3;
    job.request();
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(h.shown, std::vector<int>{3});
}

void LatestJobTest::failureEndsTheRequestsWithItsMessage() {
    Harness h;
    h.fail = true;
    h.gate->open = true;
    LatestJob job(h.make(), nullptr);
    QSignalSpy failed(&job, &LatestJob::failed);
    h.value = 1;
    job.request();
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(failed.size(), 1);
    QVERIFY2(failed.at(0).at(0).toString().contains(QStringLiteral("test.ply: broken")),
             qPrintable(failed.at(0).at(0).toString()));
    QCOMPARE(job.failedCount(), 1);
    QVERIFY(h.shown.empty());

    // A failure while a newer request waits: that request is dropped, nothing retries it.
    h.gate->open = false;
    h.pollCancel = false;  // the running one ends (failing) in spite of the newer request
    job.requestNow();
    QVERIFY(waitRunning(*h.gate));
    h.value = 2;
    job.requestNow();
    h.gate->open = true;
    QTRY_COMPARE(failed.size(), 2);
    QVERIFY(!job.isBusy());
    QTest::qWait(50);
    QCOMPARE(h.started, (std::vector<int>{1, 1}));
    QCOMPARE(job.startedCount(), 2);
}

void LatestJobTest::nothingToDoDropsTheRequest() {
    Harness h;
    LatestJob job(h.make(), nullptr);
    QSignalSpy changed(&job, &LatestJob::changed);
    h.value = -1;  // the state is gone (no tree any more)
    job.request();
    QVERIFY(job.isBusy());
    QTRY_VERIFY(!job.isBusy());
    QVERIFY(h.started.empty());
    QCOMPARE(job.startedCount(), 0);
    QVERIFY(changed.size() >= 2);  // the request, and its end
}

void LatestJobTest::throttleShowsTheSupersededResultThenTheNewest() {
    Harness h;
    LatestJob job(h.make(), nullptr, LatestJob::Superseded::show);
    QVERIFY(startHeld(h, job, 1));
    for (int v = 2; v <= 4; ++v) {
        h.value = v;
        job.requestNow();  // not cancelled: it runs on, and only the newest waits
    }
    QTest::qWait(50);
    QCOMPARE(h.gate->sawCancel.load(), 0);
    QVERIFY(h.shown.empty());
    h.gate->open = true;
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(h.shown, (std::vector<int>{1, 4}));
    QCOMPARE(h.started, (std::vector<int>{1, 4}));
    QCOMPARE(job.cancelledCount() + job.droppedCount(), 0);
    // Cancel still lets the running one go without showing it.
    h.gate->open = false;
    QVERIFY(startHeld(h, job, 5));
    job.cancel();
    h.gate->open = true;
    QTRY_COMPARE(h.gate->running.load(), 0);
    QTest::qWait(50);
    QCOMPARE(h.shown, (std::vector<int>{1, 4}));
}

void LatestJobTest::stopReportsTheEndAsCancelled() {
    Harness h;
    LatestJob job(h.make(), nullptr);
    QSignalSpy cancelled(&job, &LatestJob::cancelled);
    QVERIFY(startHeld(h, job, 1));
    h.value = 2;
    job.request();  // waiting: stop() drops it
    job.stop();
    QVERIFY(job.isBusy());  // the stopped job's end is still waited for
    QVERIFY(cancelled.wait(10000));
    QCOMPARE(cancelled.size(), 1);
    QCOMPARE(cancelled.at(0).at(0).value<JobResult>().name, QStringLiteral("test job"));
    QVERIFY(!job.isBusy());
    QTest::qWait(50);
    QCOMPARE(h.started, std::vector<int>{1});
    QVERIFY(h.shown.empty());
    QCOMPARE(job.letGoCount(), 0);
    // A job superseded by a newer request ends cancelled too, but silently: it is not the newest.
    h.gate->open = false;
    job.requestNow();
    QVERIFY(waitRunning(*h.gate));
    job.requestNow();
    h.gate->open = true;
    QTRY_VERIFY(!job.isBusy());
    QCOMPARE(cancelled.size(), 1);
    QCOMPARE(h.shown, std::vector<int>{2});
}

void LatestJobTest::destructionWhileJobsRunWaitsForThem() {
    Harness h;
    h.held = std::make_shared<int>(42);
    const std::weak_ptr<int> held = h.held;
    auto* job = new LatestJob(h.make(), nullptr);
    QVERIFY(startHeld(h, *job, 1));
    job->cancel();  // let go: still running, cancelled
    h.pollCancel = false;  // the next one does not stop by itself
    h.value = 2;
    job->requestNow();
    // Job 1 has stopped and job 2 holds at the gate.
    QVERIFY(QTest::qWaitFor([&] { return h.gate->entered.load() == 2 && h.gate->running.load() == 1; }, 10000));
    h.held.reset();
    // Job 2 ignores the flag: the destructor must wait until it ends; open the gate a little later.
    std::thread opener([gate = h.gate] {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        gate->open = true;
    });
    delete job;
    // Nothing of the work runs any more once the destructor returned.
    QCOMPARE(h.gate->running.load(), 0);
    opener.join();
    QVERIFY(h.shown.empty());
    QCOMPARE(h.gate->sawCancel.load(), 2);  // both were told to stop
    // The pool thread drops its copy of the work (and what it held) just after the job ends.
    QTRY_VERIFY_WITH_TIMEOUT(held.expired(), 5000);
}

QTEST_GUILESS_MAIN(LatestJobTest)
#include "latest_job_test.moc"
