// Long work of the studio's docks runs on workers, in process under Xvfb (docs/studio.md, "Work off the
// GUI thread"): the event loop keeps turning while it runs, requests made meanwhile coalesce into the
// newest one, a result that is no longer wanted never reaches the view, and closing the window or loading
// another file while the work runs ends it cleanly (the data it held is freed).
//  - MC octree dock on frag_115 (a coloured RGB-D scan, resolution 64): a fast drag of the priority slider through many
//    indices; the final frame is the last index's (the core's extraction count, real pixels).
//  - Octree dock's view-dependent cut on the dragon (202 k triangles): a burst of camera moves; the cut
//    shown is the last camera's, equal to the core's select_cut and extract_mesh for it.
//  - LODStrips slider: the full-detail strips' scene is made on the chain's worker, and the slider's first
//    move shows it (its triangles replaced) instead of making one on the GUI thread.
//  - A dock's job that fails (the octree build of a PLY that vanished after loading, a morph that cannot
//    be opened) opens the window's error dialog with the message naming the file.
#include "MainWindow.h"
#include "PixelStats.h"
#include "StudioSession.h"

#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/octree/octree_select.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/pack/preset.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LodLevels.h"
#include "lodforge/widgets/LandmarkPicker.h"
#include "lodforge/widgets/McoPriorityPanel.h"
#include "lodforge/widgets/MorphPanel.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/OctreeTuningPanel.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

#include <QApplication>
#include <QElapsedTimer>
#include <QFile>
#include <QLabel>
#include <QLocale>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSlider>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

using lodforge::studio::MainWindow;
using lodforge::testing::differingFraction;
using lodforge::testing::freshFrame;
using lodforge::widgets::McoPriorityPanel;
using lodforge::widgets::OctreeTuningPanel;
using lodforge::widgets::VtkView;
using lodforge::widgets::viewBackgroundColor;

namespace {

const QString fragPath = QStringLiteral(LODFORGE_SHARED_DATA "/color-open3d-frag115/frag_115.ply");
const QString dragonRes3Path = QStringLiteral(LODFORGE_SHARED_DATA "/scan-dragon/dragon_vrip_res3.ply");
const QString dragonRes2Path = QStringLiteral(LODFORGE_SHARED_DATA "/scan-dragon/dragon_vrip_res2.ply");
const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");

// Counts the turns of the event loop while `busy()` holds: a timer that cannot fire while the GUI thread
// is blocked. How many ticks there are depends on the machine's load (the GUI thread must be scheduled);
// that there are any at all while the work runs shows the work is not on the GUI thread.
class LoopProbe {
public:
    explicit LoopProbe(std::function<bool()> busy) : busy_(std::move(busy)) {
        timer_.setTimerType(Qt::PreciseTimer);
        timer_.setInterval(2);
        QObject::connect(&timer_, &QTimer::timeout, [this] {
            const qint64 now = clock_.elapsed();
            if (busy_()) {
                ++busyTicks_;
                if (wasBusy_) longestGapMs_ = std::max(longestGapMs_, now - lastMs_);
            }
            wasBusy_ = busy_();
            lastMs_ = now;
        });
        clock_.start();
        timer_.start();
    }
    int busyTicks() const { return busyTicks_; }
    // Turns the event loop until `done()`, without the sleeps of QTest::qWaitFor: every tick that falls
    // due is delivered as soon as this thread runs. False on timeout.
    bool waitUntil(const std::function<bool()>& done, int timeoutMs = 60000) {
        QElapsedTimer clock;
        clock.start();
        while (!done()) {
            if (clock.elapsed() > timeoutMs) return false;
            QCoreApplication::processEvents(QEventLoop::WaitForMoreEvents);
        }
        return true;
    }
    qint64 longestGapMs() const { return longestGapMs_; }

private:
    std::function<bool()> busy_;
    QTimer timer_;
    QElapsedTimer clock_;
    int busyTicks_ = 0;
    bool wasBusy_ = false;
    qint64 lastMs_ = 0;
    qint64 longestGapMs_ = 0;
};

}  // namespace

class StudioWorkersTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase();
    void init();
    void cleanup();

    void mcoDragStaysResponsiveAndShowsTheLastIndex();
    void mcoCancelAndCloseDuringExtraction();
    void octreeCutFollowsACameraBurstOffTheGuiThread();
    void lodstripsFirstMoveUsesTheWorkersScene();
    void dockFailuresOpenADialogNamingTheFile();
    void landmarkMeshLoadShowsProgressAndCancels();

private:
    McoPriorityPanel* buildMco(const QString& path, std::size_t resolution);
    std::unique_ptr<MainWindow> window_;
};

void StudioWorkersTest::initTestCase() {
    for (const QString& path : {fragPath, dragonRes2Path, dragonRes3Path, spotPath}) QVERIFY2(QFile::exists(path), qPrintable(path));
    QSettings().clear();
}

void StudioWorkersTest::init() {
    window_ = lodforge::testing::openStudioWindow();
    QVERIFY(window_);
}

void StudioWorkersTest::cleanup() {
    while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
    window_.reset();
}

// Loads `path`, builds its MC octree at `resolution` and waits for the first (full-detail) mesh; null on
// failure (the test has failed then).
McoPriorityPanel* StudioWorkersTest::buildMco(const QString& path, std::size_t resolution) {
    if (!lodforge::testing::loadInStudio(*window_, path)) return nullptr;
    lodforge::Preset preset = window_->preset();
    preset.mcoctree.resolution = resolution;
    window_->setPreset(preset);
    McoPriorityPanel* panel = window_->mcoPriorityPanel();
    QSignalSpy built(panel, &McoPriorityPanel::built);
    panel->build();
    if (!built.wait(120000) || !built.at(0).at(0).toBool()) return nullptr;
    if (!lodforge::testing::mcoSettled(panel)) return nullptr;
    return panel;
}

void StudioWorkersTest::mcoDragStaysResponsiveAndShowsTheLastIndex() {
    McoPriorityPanel* panel = buildMco(fragPath, 64);
    QVERIFY(panel);
    const lodforge::McOctree* tree = panel->tree();
    QVERIFY(tree && tree->max_priority() > 1000);
    const std::size_t top = tree->max_priority();
    QCOMPARE(panel->priority(), top);

    // Every result that reaches the view is the newest request at that moment (stale ones are dropped).
    std::vector<std::size_t> shown;
    int staleShown = 0;
    connect(panel, &McoPriorityPanel::extracted, this, [&](std::size_t priority, std::uint64_t) {
        shown.push_back(priority);
        if (priority != panel->requestedPriority()) ++staleShown;
    });
    // Ticks while an extraction job is on the worker: impossible if it blocked the GUI thread.
    LoopProbe probe([panel] { return panel->isWorkerBusy(); });
    const int runsBefore = panel->extractionsRun(), droppedBefore = panel->resultsDropped();
    const int cancelledBefore = panel->extractionsCancelled();

    // A fast drag: 120 indices up and down the fine half (the slow end), four moves per turn of the event
    // loop (as a mouse faster than the repaint delivers them), turns a few milliseconds apart.
    const int moves = 120;
    std::size_t last = 0;
    for (int i = 0; i < moves; ++i) {
        const double phase = double(i % 40) / 39.0;
        last = top / 2 + std::size_t(double(top / 2) * (i / 40 % 2 ? 1.0 - phase : phase));
        if (i % 30 == 29) last = top / 3;  // a jump back
        panel->slider()->setValue(int(last));
        QCOMPARE(panel->requestedPriority(), last);
        if (i % 4 == 3) QTest::qWait(3);
    }
    // The label follows the slider at once with the count of the index asked for (the tree's table).
    QVERIFY(panel->isExtracting());
    const QString lastCount = QLocale().toString(qulonglong(lodforge::mc_triangles_at(*tree, last)));
    QVERIFY2(panel->label()->text().contains(QStringLiteral("extracting priority %1").arg(QLocale().toString(qulonglong(last)))),
             qPrintable(panel->label()->text()));
    QVERIFY(lodforge::testing::mcoSettled(panel));
    const int runs = panel->extractionsRun() - runsBefore, dropped = panel->resultsDropped() - droppedBefore;
    const int cancelled = panel->extractionsCancelled() - cancelledBefore;
    qInfo("drag: %d moves, %d extractions shown, %d dropped, %d cancelled early; event loop ticked %d times "
          "while the worker extracted, longest gap %lld ms; last update: %s",
          moves, runs, dropped, cancelled, probe.busyTicks(), qlonglong(probe.longestGapMs()),
          qPrintable(panel->timing()));
    // Coalesced: the moves of one turn make one request, and a request made while the worker is busy
    // waits for it (replacing any older waiting one), so at most about one extraction starts per turn.
    QVERIFY2(runs + dropped + cancelled <= moves / 2, "the moves did not coalesce");
    QCOMPARE(staleShown, 0);
    QVERIFY(!shown.empty() && shown.back() == last);

    // The final state is the last index's: the count of the core's own extraction, in both labels.
    QCOMPARE(panel->priority(), last);
    const std::uint64_t expected = lodforge::extract_mc_octree(*tree, last).mesh.triangle_count();
    QCOMPARE(panel->triangles(), expected);
    QCOMPARE(expected, lodforge::mc_triangles_at(*tree, last));
    QVERIFY(panel->label()->text().contains(lastCount + QStringLiteral(" triangles")));
    QCOMPARE(window_->levelViews()->singleLabel()->text(), panel->labelText());

    // Full-detail extractions with the cut's cells (the cells scene of 120 k boxes is most of the
    // worker's time) from the coarse end: the event loop turns while the worker has them. Each coarse
    // frame is drawn before the fine request (drawing is the GUI thread's), and a busy machine may leave
    // the GUI thread few turns, so over two.
    {
        lodforge::widgets::ViewOptions options = window_->viewOptions();
        options.cells = true;
        window_->setViewOptions(options);
        LoopProbe single([panel] { return panel->isWorkerBusy(); });
        for (int i = 0; i < 2; ++i) {
            panel->setPriority(top / 40);
            QVERIFY(lodforge::testing::mcoSettled(panel));
            freshFrame(window_->view());
            panel->setPriority(top);
            QVERIFY(single.waitUntil([panel] { return !panel->isExtracting(); }));
            QVERIFY(panel->cutCells() > 0);
        }
        qInfo("two full-detail extractions with cells: the event loop ticked %d times while the worker "
              "extracted; %s", single.busyTicks(), qPrintable(panel->timing()));
        QVERIFY2(single.busyTicks() >= 1, "the event loop did not turn while the worker extracted");
        options.cells = false;
        window_->setViewOptions(options);
    }
    QCOMPARE(panel->triangles(), lodforge::mc_triangles_at(*tree, top));

    // Two indices, two pictures: the frame is the one of the index shown.
    panel->setPriority(last);
    QVERIFY(lodforge::testing::mcoSettled(panel));
    const QImage atLast = freshFrame(window_->view());
    panel->setPriority(top / 40);
    QVERIFY(lodforge::testing::mcoSettled(panel));
    QCOMPARE(panel->triangles(), lodforge::extract_mc_octree(*tree, top / 40).mesh.triangle_count());
    const QImage coarse = freshFrame(window_->view());
    const double differ = differingFraction(atLast, coarse, viewBackgroundColor());
    qInfo("priority %zu (%llu triangles) against %zu (%llu): %.3f of the model pixels differ", last,
          qulonglong(expected), top / 40, qulonglong(panel->triangles()), differ);
    QVERIFY(differ > 0.05);

    // Another file opened while extractions run: they end, their results never show, the tree is freed.
    const std::weak_ptr<const lodforge::McOctree> handle = panel->treeHandle();
    QVERIFY(!handle.expired());
    int flips = 0;
    QTimer flipper;
    connect(&flipper, &QTimer::timeout, this, [&] { panel->slider()->setValue(int(++flips % 2 ? top : top / 2)); });
    flipper.start(5);
    QVERIFY(QTest::qWaitFor([panel] { return panel->isWorkerBusy(); }, 10000));
    QSignalSpy loaded(window_.get(), &MainWindow::loadFinished);
    QSignalSpy extracted(panel, &McoPriorityPanel::extracted);
    window_->openFile(spotPath);
    QVERIFY(loaded.wait(60000) && loaded.at(0).at(0).toBool());
    const int extractedAtLoad = int(extracted.size());
    qInfo("%d slider moves while Spot loaded, %d extractions shown", flips, extractedAtLoad);
    QTest::qWait(200);
    flipper.stop();
    QVERIFY(!panel->hasTree() && !panel->isExtracting());
    QCOMPARE(int(extracted.size()), extractedAtLoad);
    QTRY_VERIFY_WITH_TIMEOUT(handle.expired(), 10000);
    QVERIFY(window_->levelViews()->inspectionOwner() == nullptr);
    QVERIFY(window_->levelViews()->singleLabel()->text().startsWith(QStringLiteral("Original")));
}

void StudioWorkersTest::mcoCancelAndCloseDuringExtraction() {
    McoPriorityPanel* panel = buildMco(dragonRes3Path, 128);
    QVERIFY(panel);
    const std::size_t top = panel->tree()->max_priority();
    QVERIFY(top > 100);

    // Cancel while extracting: the view keeps the mesh it shows and the slider comes back to it.
    panel->slider()->setValue(int(top / 3));
    QVERIFY(panel->isExtracting() && panel->cancelButton()->isEnabled());
    QTest::mouseClick(panel->cancelButton(), Qt::LeftButton);
    QVERIFY(!panel->isExtracting());
    QCOMPARE(panel->priority(), top);
    QCOMPARE(std::size_t(panel->slider()->value()), top);
    QTest::qWait(300);
    QCOMPARE(panel->priority(), top);
    QCOMPARE(window_->levelViews()->singleLabel()->text(), panel->labelText());

    // The window closed while extractions run: no crash, no wait for a result, nothing left behind.
    const std::weak_ptr<const lodforge::McOctree> handle = panel->treeHandle();
    for (int i = 0; i < 5; ++i) {
        panel->slider()->setValue(int(i % 2 ? top : top / 4));
        QTest::qWait(2);
    }
    QVERIFY(panel->isExtracting());
    window_->close();
    window_.reset();
    // The pool thread drops its copy of the work just after the job ends.
    QTRY_VERIFY_WITH_TIMEOUT(handle.expired(), 5000);
}

void StudioWorkersTest::octreeCutFollowsACameraBurstOffTheGuiThread() {
    QVERIFY(lodforge::testing::loadInStudio(*window_, dragonRes2Path));
    lodforge::Preset preset = window_->preset();
    preset.octree.max_triangles_per_node = 5000;
    window_->setPreset(preset);
    OctreeTuningPanel* panel = window_->octreeTuningPanel();
    {
        QSignalSpy built(panel, &OctreeTuningPanel::built);
        panel->build();
        QVERIFY(built.wait(120000));
        QVERIFY2(built.at(0).at(0).toBool(), qPrintable(built.at(0).at(1).toString()));
    }
    VtkView* view = window_->view();
    window_->levelViews()->resetView();
    panel->setFrustumCulling(false);
    panel->setScreenError(1);
    panel->setViewDependent(true);
    QVERIFY(lodforge::testing::cutSettled(panel));
    QCOMPARE(panel->cutsShown(), 1);
    const VtkView::ViewCamera start = view->viewCamera();

    // A burst of camera moves (a dolly in and out, as a wheel does), three per turn of the event loop.
    const int shownBefore = panel->cutsShown(), droppedBefore = panel->cutsDropped();
    const int moves = 60;
    std::vector<std::uint64_t> shownCounts;
    connect(panel, &OctreeTuningPanel::cutUpdated, this, [&] { shownCounts.push_back(panel->cutTriangles()); });
    for (int i = 0; i < moves; ++i) {
        const double factor = 0.35 + 0.6 * std::abs(double(i % 20) - 10.0) / 10.0;
        VtkView::ViewCamera c = start;
        for (int k = 0; k < 3; ++k) c.position[k] = c.focalPoint[k] + (start.position[k] - c.focalPoint[k]) * factor;
        view->setViewCamera(c);
        if (i % 3 == 2) QTest::qWait(4);
    }
    QVERIFY(lodforge::testing::cutSettled(panel));
    const int shown = panel->cutsShown() - shownBefore, dropped = panel->cutsDropped() - droppedBefore;
    qInfo("camera burst: %d moves, %d cuts shown, %d dropped (superseded or cancelled); %s", moves, shown,
          dropped, qPrintable(panel->cutLabel()->text()));
    QVERIFY2(shown + dropped <= moves / 2, "the camera moves did not coalesce");
    QCOMPARE(shown, int(shownCounts.size()));
    QVERIFY(shown >= 1);

    // Cuts of the whole model at full resolution, one after the other: the event loop turns while the
    // worker makes them. A cut takes 15-150 ms here, and a busy machine may leave the GUI thread no turn
    // during one: with ctest -j2 beside a CPU-bound test, ten cuts of 16 ms each once went by without a
    // tick. So at least ten cuts, and more (up to 60) until a tick is seen; a cut made on the GUI thread
    // would never show one. Each result is drawn before the next cut is asked for: drawing is the GUI
    // thread's (OpenGL), and on llvmpipe 200 k triangles take a while.
    // The octree's levels are coarse enough that a 1 px cut from afar is a few ms: the finest error with
    // the camera close in keeps every cut near full resolution.
    panel->setScreenError(0.5);
    {
        VtkView::ViewCamera close = start;
        for (int k = 0; k < 3; ++k) close.position[k] = close.focalPoint[k] + (start.position[k] - close.focalPoint[k]) * 0.3;
        view->setViewCamera(close);
    }
    QVERIFY(lodforge::testing::cutSettled(panel));
    {
        LoopProbe probe([panel] { return panel->isCutWorkerBusy(); });
        for (int i = 0; i < 10 || (probe.busyTicks() < 1 && i < 60); ++i) {
            panel->updateCut();
            QVERIFY(probe.waitUntil([panel] { return !panel->isCutting(); }));
            freshFrame(view);
        }
        qInfo("cuts: the event loop ticked %d times while the worker ran; %s; %s", probe.busyTicks(),
              qPrintable(panel->cutLabel()->text()),
              qPrintable(panel->findChild<QLabel*>(QStringLiteral("octreeStatus"))->text()));
        QVERIFY2(probe.busyTicks() >= 1, "the event loop did not turn while the cut was made");
    }

    // The cut shown is the last camera's: the core's own cut for that camera, and its mesh.
    const VtkView::ViewCamera c = view->viewCamera();
    lodforge::Camera camera;
    camera.eye = {float(c.position[0]), float(c.position[1]), float(c.position[2])};
    camera.target = {float(c.focalPoint[0]), float(c.focalPoint[1]), float(c.focalPoint[2])};
    camera.up = {float(c.viewUp[0]), float(c.viewUp[1]), float(c.viewUp[2])};
    camera.fov_y_degrees = float(c.viewAngle);
    camera.viewport_width = std::max(1, int(view->width() * view->devicePixelRatioF()));
    camera.viewport_height = std::max(1, int(view->height() * view->devicePixelRatioF()));
    lodforge::SelectParams select;
    select.screen_error_pixels = panel->screenError();
    select.frustum_culling = false;
    lodforge::OctreeStore& store = *panel->store();
    const lodforge::Cut reference = lodforge::select_cut(store, camera, select).cut;
    QCOMPARE(panel->cut().size(), reference.size());
    for (std::size_t i = 0; i < reference.size(); ++i) {
        QCOMPARE(panel->cut()[i].node, reference[i].node);
        QCOMPARE(panel->cut()[i].raw, reference[i].raw);
    }
    QCOMPARE(panel->cutTriangles(), lodforge::extract_mesh(store, reference).triangle_count());
    QCOMPARE(shownCounts.back(), panel->cutTriangles());
    QVERIFY(window_->levelViews()->singleLabel()->text().contains(
        QLocale().toString(qulonglong(panel->cutTriangles())) + QStringLiteral(" triangles")));

    // Closed while a cut is being made: no crash, the worker ends and lets the store go.
    const std::weak_ptr<const lodforge::OctreeStore> handle = panel->storeHandle();
    QVERIFY(!handle.expired());
    view->setViewCamera(start);
    QTest::qWait(1);
    QVERIFY(panel->isCutting());
    window_->close();
    window_.reset();
    // The pool thread drops its copy of the work just after the job ends.
    QTRY_VERIFY_WITH_TIMEOUT(handle.expired(), 5000);
}

void StudioWorkersTest::lodstripsFirstMoveUsesTheWorkersScene() {
    QVERIFY(lodforge::testing::loadInStudio(*window_, dragonRes3Path));
    lodforge::Preset preset = window_->preset();
    preset.method = lodforge::LodMethod::lodstrips;
    preset.levels = {{lodforge::LodTarget::Kind::ratio, 0.5}, {lodforge::LodTarget::Kind::ratio, 0.05}};
    QString message;
    QVERIFY2(lodforge::testing::buildInStudio(*window_, preset, &message), qPrintable(message));
    auto* levels = window_->levelViews();
    QVERIFY(levels->hasContinuousLod());
    const auto& data = levels->levels().front().continuous;
    QVERIFY(data && data->fullScene);

    // The chain's worker made the full-detail strips: every triangle and vertex of the runtime's level 0.
    lodstrips::LodStrips reference;
    std::string error;
    QVERIFY2(reference.load_memory(data->lodstripsFile.data(), data->lodstripsFile.size(), &error), error.c_str());
    std::size_t triangles = 0;
    for (const auto& part : lodforge::widgets::describe(*data->fullScene).parts) triangles += part.triangles;
    QCOMPARE(triangles, std::size_t(reference.triangle_count()));

    // The slider's first move shows that scene (its triangles replaced), not one made on the GUI thread.
    VtkView* view = window_->view();
    const QImage full = freshFrame(view);
    levels->continuousSlider()->setValue(300);
    QVERIFY(levels->continuousActive());
    QVERIFY(view->scene() == data->fullScene);
    reference.go_to_lod(0.3);
    QCOMPARE(levels->continuousTriangles(), std::size_t(reference.triangle_count()));
    const QImage coarse = freshFrame(view);
    const double differ = differingFraction(full, coarse, viewBackgroundColor());
    qInfo("LODStrips on dragon res3: %zu triangles at full detail, %zu at 0.3; %.3f of the pixels differ", triangles,
          levels->continuousTriangles(), differ);
    QVERIFY(differ > 0.02);
}

namespace {

// Waits for the error dialog (window-modal, not blocking), checks that it is a critical one naming
// `file`, and closes it. Empty when so, else what was wrong.
QString closeErrorDialogNaming(const QString& file) {
    QMessageBox* box = nullptr;
    if (!QTest::qWaitFor(
            [&] { return (box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) != nullptr; }, 5000))
        return QStringLiteral("no error dialog");
    QString problem;
    if (box->icon() != QMessageBox::Critical) problem = QStringLiteral("not a critical message box; ");
    if (!box->informativeText().contains(file))
        problem += QStringLiteral("does not name %1: %2").arg(file, box->informativeText());
    box->close();
    if (!QTest::qWaitFor([] { return QApplication::activeModalWidget() == nullptr; }, 5000))
        problem += QStringLiteral(" (it did not close)");
    return problem;
}

// Asks a dock for its build (`built(bool, QString)` reports its end) and returns the failure's message;
// empty when it did not fail within a minute.
template <class Panel>
QString failedBuildMessage(Panel* panel) {
    QSignalSpy built(panel, &Panel::built);
    panel->build();
    if (!built.wait(60000) || built.at(0).at(0).toBool()) return {};
    return built.at(0).at(1).toString();
}

}  // namespace

void StudioWorkersTest::dockFailuresOpenADialogNamingTheFile() {
    // A PLY loaded, then deleted: the octree streams its input from the file, so the build fails on it.
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString vanishing = dir.filePath(QStringLiteral("vanishing_scan.ply"));
    QVERIFY(QFile::copy(QStringLiteral(LODFORGE_SHARED_DATA "/color-open3d-small/color.ply"), vanishing));
    QVERIFY(lodforge::testing::loadInStudio(*window_, vanishing));
    QVERIFY(QFile::remove(vanishing));
    window_->setInteractive(true);
    OctreeTuningPanel* octree = window_->octreeTuningPanel();
    const QString message = failedBuildMessage(octree);
    QVERIFY2(message.contains(QStringLiteral("vanishing_scan.ply")), qPrintable(message));
    {
        const QString problem = closeErrorDialogNaming(QStringLiteral("vanishing_scan.ply"));
        QVERIFY2(problem.isEmpty(), qPrintable(problem));
    }
    QVERIFY(!octree->hasAsset() && !octree->isBuilding());

    // The MC octree of a mesh whose one triangle is degenerate (no usable normal): the core's message,
    // with the file named as the CLI names it.
    const QString flat = dir.filePath(QStringLiteral("flat_line.ply"));
    {
        QFile file(flat);
        QVERIFY(file.open(QIODevice::WriteOnly));
        file.write("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n");
    }
    QVERIFY(lodforge::testing::loadInStudio(*window_, flat));
    McoPriorityPanel* mco = window_->mcoPriorityPanel();
    const QString mcoMessage = failedBuildMessage(mco);
    QVERIFY2(mcoMessage.contains(QStringLiteral("flat_line.ply: no point has a usable normal")), qPrintable(mcoMessage));
    {
        const QString problem = closeErrorDialogNaming(QStringLiteral("flat_line.ply"));
        QVERIFY2(problem.isEmpty(), qPrintable(problem));
    }
    QVERIFY(!mco->hasTree());

    // A morph sequence directory that does not exist: the same dialog, naming it.
    lodforge::widgets::MorphPanel* morph = window_->morphPanel();
    QSignalSpy loaded(morph, &lodforge::widgets::MorphPanel::morphLoaded);
    morph->openMorph(dir.filePath(QStringLiteral("no-such-sequence")));
    QVERIFY(loaded.wait(30000));
    QVERIFY(!loaded.at(0).at(0).toBool());
    {
        const QString problem = closeErrorDialogNaming(QStringLiteral("no-such-sequence"));
        QVERIFY2(problem.isEmpty(), qPrintable(problem));
    }

    // Cancel is not an error: no dialog.
    QSignalSpy built(octree, &OctreeTuningPanel::built);
    octree->build();
    QVERIFY(octree->isBuilding());
    octree->cancel();
    QTest::qWait(300);
    QVERIFY(QApplication::activeModalWidget() == nullptr);
    QVERIFY(built.isEmpty());
}

// The landmark picker reads A and B on workers: a progress bar and Cancel while one loads, Cancel drops
// it (the side keeps its mesh), and a file that cannot be read opens the error dialog naming it.
void StudioWorkersTest::landmarkMeshLoadShowsProgressAndCancels() {
    using lodforge::widgets::LandmarkPicker;
    lodforge::widgets::MorphPanel* morph = window_->morphPanel();
    LandmarkPicker* picker = morph->landmarkPicker();
    QVERIFY(picker->loadProgressBar()->isHidden() && picker->cancelLoadButton()->isHidden());
    QSignalSpy loaded(picker, &LandmarkPicker::meshLoaded);
    picker->openMesh(LandmarkPicker::Side::a, spotPath);
    QVERIFY(loaded.wait(30000));
    QVERIFY(loaded.at(0).at(1).toBool());
    const auto spot = picker->mesh(LandmarkPicker::Side::a);
    QVERIFY(spot);
    QVERIFY(picker->loadProgressBar()->isHidden());

    // The full dragon (34 MB of ASCII PLY) as A: the bar and Cancel show while it loads, the bar moves.
    QSignalSpy progress(picker->loadProgressBar(), &QProgressBar::valueChanged);
    picker->openMesh(LandmarkPicker::Side::a, QStringLiteral(LODFORGE_SHARED_DATA "/scan-dragon/dragon_vrip.ply"));
    QVERIFY(picker->isLoading());
    QVERIFY(!picker->loadProgressBar()->isHidden() && !picker->cancelLoadButton()->isHidden());
    QVERIFY(QTest::qWaitFor([&] { return picker->loadProgressBar()->value() > 0; }, 20000));
    QVERIFY(picker->isLoading());
    QTest::mouseClick(picker->cancelLoadButton(), Qt::LeftButton);
    QVERIFY(!picker->isLoading());
    QVERIFY(picker->loadProgressBar()->isHidden() && picker->cancelLoadButton()->isHidden());
    QTest::qWait(300);
    QCOMPARE(int(loaded.size()), 1);  // a cancelled load reports nothing
    QCOMPARE(picker->mesh(LandmarkPicker::Side::a), spot);
    QVERIFY(!progress.isEmpty());

    // A missing file: meshLoaded fails naming it, and the window's error dialog says so.
    window_->setInteractive(true);
    QTemporaryDir dir;
    const QString missing = dir.filePath(QStringLiteral("no_such_mesh_b.obj"));
    picker->openMesh(LandmarkPicker::Side::b, missing);
    QVERIFY(loaded.wait(30000));
    QVERIFY(!loaded.at(1).at(1).toBool());
    QVERIFY2(loaded.at(1).at(2).toString().contains(QStringLiteral("no_such_mesh_b.obj")),
             qPrintable(loaded.at(1).at(2).toString()));
    {
        const QString problem = closeErrorDialogNaming(QStringLiteral("no_such_mesh_b.obj"));
        QVERIFY2(problem.isEmpty(), qPrintable(problem));
    }
    QVERIFY(!picker->mesh(LandmarkPicker::Side::b));
}

QTEST_MAIN(StudioWorkersTest)
#include "studio_workers_test.moc"
