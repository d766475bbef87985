#include "lodforge/widgets/QueuedProgress.h"

#include <QMetaObject>

#include <algorithm>
#include <cmath>
#include <utility>

namespace lodforge::widgets {

QueuedProgress::QueuedProgress(QObject* receiver, Sink sink) : receiver_(receiver), sink_(std::move(sink)) {}

void QueuedProgress::report(double fraction, std::string_view stage) {
    if (!(fraction >= 0.0)) fraction = 0.0;  // also NaN
    fraction = std::min(fraction, 1.0);
    const int permille = static_cast<int>(std::lround(fraction * 1000.0));
    if (permille == lastPermille_ && stage == lastStage_) return;
    lastPermille_ = permille;
    if (stage != lastStage_) lastStage_.assign(stage);

    QString text = QString::fromUtf8(stage.data(), static_cast<qsizetype>(stage.size()));
    // Runs on the receiver's thread; a copy of the sink travels with the call, so nothing here is shared.
    QMetaObject::invokeMethod(
        receiver_, [sink = sink_, fraction, text = std::move(text)] { sink(fraction, text); },
        Qt::QueuedConnection);
}

}  // namespace lodforge::widgets
