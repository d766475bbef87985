// The steps the in-process studio tests share: a non-interactive main window, loading a file, building
// a preset's levels, and grabbing a freshly rendered frame.
#pragma once

#include "MainWindow.h"

#include "lodforge/pack/preset.h"
#include "lodforge/widgets/McoPriorityPanel.h"
#include "lodforge/widgets/OctreeTuningPanel.h"
#include "lodforge/widgets/VtkView.h"

#include <QImage>
#include <QSignalSpy>
#include <QString>
#include <QTest>

#include <memory>

namespace lodforge::testing {

// Shown and exposed, or null.
inline std::unique_ptr<studio::MainWindow> openStudioWindow() {
    auto window = std::make_unique<studio::MainWindow>();
    window->setInteractive(false);
    window->resize(1200, 860);
    window->show();
    if (!QTest::qWaitForWindowExposed(window.get())) return nullptr;
    return window;
}

inline bool loadInStudio(studio::MainWindow& window, const QString& path) {
    QSignalSpy finished(&window, &studio::MainWindow::loadFinished);
    window.openFile(path);
    return finished.wait(120000) && finished.at(0).at(0).toBool();
}

// Shown, active (so the window's keys reach it) and with `path` loaded, or null.
inline std::unique_ptr<studio::MainWindow> openStudioWith(const QString& path) {
    auto window = openStudioWindow();
    if (!window) return nullptr;
    window->activateWindow();
    if (!QTest::qWaitForWindowActive(window.get()) || !loadInStudio(*window, path)) return nullptr;
    return window;
}

// The levels' measure (started by every built chain) has ended.
inline bool measuredInStudio(const studio::MainWindow& window, int timeoutMs = 120000) {
    return QTest::qWaitFor([&] { return !window.isMeasuring(); }, timeoutMs);
}

// Builds `preset`'s levels and waits for their measure; false with the job's message (or why it never
// finished) in `message`.
inline bool buildInStudio(studio::MainWindow& window, const Preset& preset, QString* message) {
    window.setPreset(preset);
    QSignalSpy finished(&window, &studio::MainWindow::jobFinished);
    window.buildLodChain();
    if (finished.isEmpty() && !finished.wait(60000)) {
        *message = QStringLiteral("no jobFinished in time");
        return false;
    }
    *message = finished.at(0).at(2).toString();
    if (finished.at(0).at(1).toBool() && !measuredInStudio(window)) {
        *message = QStringLiteral("the levels' measure never ended");
        return false;
    }
    return finished.at(0).at(1).toBool();
}

// Renders a fresh frame of `view` and grabs it.
inline QImage freshFrame(widgets::VtkView* view) {
    const quint64 before = view->frameCount();
    view->update();
    if (!QTest::qWaitFor([&] { return view->frameCount() > before; }, 5000)) qWarning("no new frame");
    return view->grabFramebuffer().convertToFormat(QImage::Format_RGB32);
}

// The MC octree dock's extraction (on its worker) has caught up with the last request.
inline bool mcoSettled(const widgets::McoPriorityPanel* panel, int timeoutMs = 60000) {
    return QTest::qWaitFor([&] { return !panel->isExtracting(); }, timeoutMs) &&
           panel->priority() == panel->requestedPriority();
}

// The Octree dock's view-dependent cut (made on its worker) has caught up with the last request.
inline bool cutSettled(const widgets::OctreeTuningPanel* panel, int timeoutMs = 60000) {
    return QTest::qWaitFor([&] { return !panel->isCutting(); }, timeoutMs);
}

}  // namespace lodforge::testing
