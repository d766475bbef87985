// The bridge between the core's Progress interface and the GUI thread.
#pragma once

#include "lodforge/progress.h"

#include <QObject>
#include <QString>

#include <functional>
#include <string>

namespace lodforge::widgets {

// A cancellable Progress for work running on another thread. report() runs on the worker: it posts a
// queued call of `sink` to `receiver`'s thread, only when the stage changes or the fraction moves by at
// least 0.1%, so it stays cheap when algorithms call it per element. cancel() may be called from any
// thread. `receiver` must outlive the work (LoadJob waits for its worker before it is destroyed).
class QueuedProgress final : public lodforge::CancelFlagProgress {
public:
    using Sink = std::function<void(double fraction, const QString& stage)>;

    QueuedProgress(QObject* receiver, Sink sink);

    void report(double fraction, std::string_view stage) override;

private:
    QObject* receiver_;
    Sink sink_;
    // Touched by the reporting thread only.
    int lastPermille_ = -1;
    std::string lastStage_;
};

}  // namespace lodforge::widgets
