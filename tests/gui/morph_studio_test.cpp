// The Morph dock, in process under Xvfb with real pixels: six keyframes of the horse gallop are opened
// and their LOD built in the background; t and F move the picture and the labels independently (the
// counts are extract_morph's, as `lodforge morph extract` writes them); Play advances t; the heat map of
// a coarse frame shows viridis and is exactly zero at full detail; a .lfmorph file opens the same; a
// broken one fails with its name; Cancel stops a build. Landmark picking: a simulated click on mesh A
// picks the vertex under the cursor, pairs are numbered markers in both views, undo/clear work, and the
// saved file round-trips through the core reader; Build supermesh on an open mesh fails naming it, and on
// Spot and a sphere builds the two-shape morph, whose t = 0 and t = 1 frames differ.
#include "MainWindow.h"
#include "PixelStats.h"
#include "StudioSession.h"
#include "support/icosphere.h"

#include "lodforge/error.h"
#include "lodforge/morph/landmarks.h"
#include "lodforge/morph/morph_file.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/morph/morph_lod.h"
#include "lodforge/widgets/LandmarkPicker.h"
#include "lodforge/widgets/MorphPanel.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

#include <QApplication>
#include <QDir>
#include <QDockWidget>
#include <QElapsedTimer>
#include <QFile>
#include <QLabel>
#include <QMenuBar>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSlider>
#include <QTemporaryDir>

#include <cmath>
#include <memory>

using lodforge::studio::MainWindow;
using lodforge::testing::differingFraction;
using lodforge::testing::freshFrame;
using lodforge::testing::hueClusters;
using lodforge::testing::measure;
using lodforge::testing::nearColor;
using lodforge::widgets::LandmarkPicker;
using lodforge::widgets::MorphPanel;
using lodforge::widgets::viewBackgroundColor;
using lodforge::widgets::VtkView;
using Side = LandmarkPicker::Side;

namespace {

const QString horseDir = QStringLiteral(LODFORGE_SHARED_DATA "/seq-horse-gallop");
const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");

// "F 0.200 · 1,234 triangles" -> 1234: the number before "triangles".
long long trianglesIn(const QString& text) {
    const qsizetype end = text.indexOf(QStringLiteral(" triangles"));
    if (end < 0) return -1;
    qsizetype begin = end;
    while (begin > 0 && !text.at(begin - 1).isSpace()) --begin;
    QString digits;
    for (QChar c : text.mid(begin, end - begin))
        if (c.isDigit()) digits += c;
    return digits.isEmpty() ? -1 : digits.toLongLong();
}

// Pixels of the landmark markers' yellow (labels and spheres, lit or not).
int yellowPixels(const QImage& image) {
    int n = 0;
    for (int y = 0; y < image.height(); ++y) {
        const auto* line = reinterpret_cast<const QRgb*>(image.constScanLine(y));
        for (int x = 0; x < image.width(); ++x) {
            const QColor c = QColor::fromRgb(line[x]);
            if (c.hsvHue() >= 40 && c.hsvHue() <= 60 && c.hsvSaturation() > 150 && c.value() > 120) ++n;
        }
    }
    return n;
}

}  // namespace

class MorphStudioTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase();
    void init();
    void cleanup();

    void timeAndLodMoveIndependently();
    void heatmapShowsTheFramesError();
    void lfmorphFileBrokenFileAndCancel();
    void gltfMorphTargetsPlay();
    void landmarkPickingRoundTrips();
    void supermeshOfSpotAndASpherePlays();

private:
    bool openMorph(const QString& path, QString* message = nullptr);

    QTemporaryDir tmp_;
    QString sequence_;  // six horse keyframes
    std::unique_ptr<MainWindow> window_;
    MorphPanel* panel_ = nullptr;
};

void MorphStudioTest::initTestCase() {
    QVERIFY(tmp_.isValid());
    QVERIFY2(QDir(horseDir).exists(), qPrintable(horseDir));
    QSettings().clear();
    // Six of the 48 keyframes spread over the gallop: the same loader and LOD build, a fraction of the time.
    sequence_ = tmp_.filePath(QStringLiteral("horse6"));
    QVERIFY(QDir().mkpath(sequence_));
    for (int frame : {1, 9, 17, 25, 33, 41}) {
        const QString name = QStringLiteral("%1.obj").arg(frame, 4, 10, QLatin1Char('0'));
        QVERIFY(QFile::copy(horseDir + QLatin1Char('/') + name, sequence_ + QLatin1Char('/') + name));
    }
}

void MorphStudioTest::init() {
    window_ = lodforge::testing::openStudioWindow();
    QVERIFY(window_);
    panel_ = window_->morphPanel();
    QVERIFY(panel_);
    // The Morph menu opens the dock; floated and sized so that the views have room.
    QMenu* menu = window_->findChild<QMenu*>(QStringLiteral("menuMorph"));
    QVERIFY(menu && window_->menuBar()->actions().contains(menu->menuAction()));
    QVERIFY(window_->findChild<QAction*>(QStringLiteral("actionOpenMorph")));
    window_->findChild<QAction*>(QStringLiteral("actionLandmarks"))->trigger();
    QVERIFY(window_->morphDock()->isVisible());
    panel_->showAnimation();
    window_->morphDock()->setFloating(true);
    window_->morphDock()->resize(960, 760);
    QVERIFY(QTest::qWaitForWindowExposed(window_->morphDock()));
}

void MorphStudioTest::cleanup() {
    while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
    panel_ = nullptr;
    window_.reset();
}

bool MorphStudioTest::openMorph(const QString& path, QString* message) {
    QSignalSpy loaded(panel_, &MorphPanel::morphLoaded);
    panel_->openMorph(path);
    if (!loaded.wait(120000)) return false;
    if (message) *message = loaded.at(0).at(1).toString();
    return loaded.at(0).at(0).toBool();
}

void MorphStudioTest::timeAndLodMoveIndependently() {
    QVERIFY(openMorph(sequence_));
    const auto data = panel_->data();
    QVERIFY(data);
    QCOMPARE(data->morph.frame_count(), std::size_t(6));
    VtkView* view = panel_->view();
    auto* timeLabel = panel_->findChild<QLabel*>(QStringLiteral("morphTimeLabel"));
    auto* lodLabel = panel_->findChild<QLabel*>(QStringLiteral("morphLodLabel"));
    QVERIFY(timeLabel && lodLabel);

    // t = 0 and t = 0.5 at full detail: different poses, same triangle count.
    QCOMPARE(panel_->time(), 0.0);
    QCOMPARE(panel_->lodFactor(), 1.0);
    QCOMPARE(panel_->triangleCount(), lodforge::extract_morph(data->morph, data->lod, 0, 1).triangle_count());
    QCOMPARE(trianglesIn(lodLabel->text()), static_cast<long long>(panel_->triangleCount()));
    const QImage t0 = freshFrame(view);
    QVERIFY2(measure(t0, viewBackgroundColor()).modelFraction() > 0.03, "no horse in the view");
    panel_->setTime(0.5);
    QVERIFY2(timeLabel->text().contains(QStringLiteral("t 0.500")) && timeLabel->text().contains(QStringLiteral("frame 2.50")),
             qPrintable(timeLabel->text()));
    const QImage t5 = freshFrame(view);
    const double poseChange = differingFraction(t0, t5, viewBackgroundColor());
    qInfo("t 0 -> 0.5 changes %.1f%% of the drawn pixels", 100 * poseChange);
    QVERIFY2(poseChange > 0.05, qPrintable(QString::number(poseChange)));
    QCOMPARE(trianglesIn(lodLabel->text()), static_cast<long long>(data->lod.triangles));

    // Lower F: fewer triangles (extract_morph's count), a different picture, t unchanged.
    panel_->setLodFactor(0.2);
    QCOMPARE(panel_->time(), 0.5);
    const long long coarse = trianglesIn(lodLabel->text());
    qInfo("%s / %s", qPrintable(timeLabel->text()), qPrintable(lodLabel->text()));
    QCOMPARE(coarse, static_cast<long long>(lodforge::extract_morph(data->morph, data->lod, 0.5, 0.2).triangle_count()));
    QVERIFY2(coarse < static_cast<long long>(data->lod.triangles) / 2, qPrintable(lodLabel->text()));
    QVERIFY(lodLabel->text().startsWith(QStringLiteral("F 0.200")));
    const QImage f2 = freshFrame(view);
    const double lodChange = differingFraction(t5, f2, viewBackgroundColor(), {}, 8);
    qInfo("F 1 -> 0.2 changes %.1f%% of the drawn pixels", 100 * lodChange);
    QVERIFY2(lodChange > 0.02, qPrintable(QString::number(lodChange)));
    // The View menu's wireframe toggle reaches the morph view.
    window_->findChild<QAction*>(QStringLiteral("actionWireframe"))->trigger();
    QVERIFY(view->viewOptions().wireframe);
    const double wire = differingFraction(f2, freshFrame(view), viewBackgroundColor());
    QVERIFY2(wire > 0.2, qPrintable(QString::number(wire)));
    window_->findChild<QAction*>(QStringLiteral("actionWireframe"))->trigger();
    QVERIFY(!view->viewOptions().wireframe);

    // The sliders drive the same state.
    panel_->findChild<QSlider*>(QStringLiteral("morphLod"))->setValue(500);
    QCOMPARE(panel_->lodFactor(), 0.5);
    QCOMPARE(panel_->triangleCount(), lodforge::extract_morph(data->morph, data->lod, 0.5, 0.5).triangle_count());

    // What a frame change costs on the GUI thread (extract_morph + the drawable scene): logged, not asserted.
    QElapsedTimer timer;
    timer.start();
    for (int i = 1; i <= 20; ++i) panel_->setTime(0.5 + i / 100.0);
    qInfo("frame change at F 0.5: %.1f ms each", timer.elapsed() / 20.0);

    // Play advances t (and loops); Pause stops it.
    panel_->setTime(0.9);
    QSignalSpy ticks(panel_, &MorphPanel::timeChanged);
    panel_->setPlaying(true);
    QVERIFY(panel_->isPlaying());
    QVERIFY(QTest::qWaitFor([&] { return ticks.size() >= 5; }, 5000));
    QVERIFY2(panel_->time() != 0.9, "t did not move");
    QVERIFY(QTest::qWaitFor([&] { return panel_->time() < 0.5; }, 5000));  // looped past 1
    panel_->setPlaying(false);
    // Space in the dock toggles it too.
    window_->morphDock()->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window_->morphDock()));
    view->setFocus();
    QTest::keyClick(view, Qt::Key_Space);
    QVERIFY(panel_->isPlaying());
    QTest::keyClick(view, Qt::Key_Space);
    QVERIFY(!panel_->isPlaying());
    const double stopped = panel_->time();
    QTest::qWait(3 * MorphPanel::playIntervalMs);
    QCOMPARE(panel_->time(), stopped);
}

void MorphStudioTest::heatmapShowsTheFramesError() {
    QVERIFY(openMorph(sequence_));
    VtkView* view = panel_->view();
    panel_->setTime(0.3);
    panel_->setLodFactor(0.0);
    const QImage plain = freshFrame(view);
    QSignalSpy shown(panel_, &MorphPanel::heatmapShown);
    panel_->setHeatmapVisible(true);
    QVERIFY(shown.wait(30000));
    QVERIFY(panel_->heatmapCurrent());
    const double coarseError = panel_->heatmapMaxError();
    qInfo("largest error at t 0.3, F 0: %g", coarseError);
    QVERIFY(coarseError > 0);
    const QImage heat = freshFrame(view);
    const int clusters = hueClusters(heat, viewBackgroundColor());
    qInfo("heat map: %d hue clusters", clusters);
    QVERIFY2(clusters >= 2, qPrintable(QString::number(clusters)));
    QVERIFY(differingFraction(plain, heat, viewBackgroundColor()) > 0.3);
    QVERIFY(panel_->findChild<QLabel*>(QStringLiteral("morphHeatLabel"))->text().contains(QStringLiteral("largest error")));

    // A new t recomputes it for that frame.
    shown.clear();
    QElapsedTimer timer;
    timer.start();
    panel_->setTime(0.7);
    QVERIFY(!panel_->heatmapCurrent());
    QVERIFY(shown.wait(30000));
    qInfo("heat map of a new t after %lld ms", static_cast<long long>(timer.elapsed()));
    QVERIFY(panel_->heatmapCurrent());
    QVERIFY(panel_->heatmapMaxError() > 0);

    // While playing, the heat map follows t (computed in the background, one at a time).
    QSignalSpy updated(panel_, &MorphPanel::timeChanged);
    const double firstT = panel_->heatmapTime();
    panel_->setPlaying(true);
    QVERIFY(QTest::qWaitFor([&] { return panel_->heatmapTime() != firstT; }, 20000));
    const double secondT = panel_->heatmapTime();
    QVERIFY(QTest::qWaitFor([&] { return panel_->heatmapTime() != secondT; }, 20000));
    panel_->setPlaying(false);
    QVERIFY(updated.size() >= 2);

    // Full detail: the LOD is the mesh, the error is zero everywhere.
    shown.clear();
    panel_->setLodFactor(1.0);
    QVERIFY(shown.wait(30000));
    QCOMPARE(panel_->heatmapMaxError(), 0.0);
    const QImage zero = freshFrame(view);
    QVERIFY(measure(zero, viewBackgroundColor()).modelFraction() > 0.03);

    // Off: the plain LOD mesh again.
    QSignalSpy frames(panel_, &MorphPanel::frameShown);
    panel_->setHeatmapVisible(false);
    QCOMPARE(frames.size(), 1);
    QVERIFY(differingFraction(zero, freshFrame(view), viewBackgroundColor()) > 0.3);
}

void MorphStudioTest::lfmorphFileBrokenFileAndCancel() {
    QVERIFY(openMorph(sequence_));
    const auto built = panel_->data();
    const QString file = tmp_.filePath(QStringLiteral("horse6.lfmorph"));
    lodforge::write_morph_lod(file.toStdString(), built->morph, built->lod);
    const lodforge::MorphLodFile reference = lodforge::read_morph_lod(file.toStdString());

    QVERIFY(openMorph(file));
    QVERIFY(panel_->data() != built);
    panel_->setTime(0.3);
    panel_->setLodFactor(0.4);
    QCOMPARE(panel_->triangleCount(), lodforge::extract_morph(reference.morph, reference.lod, 0.3, 0.4).triangle_count());

    // A truncated file: an error naming it, and the morph shown stays.
    const auto shown = panel_->data();
    const QString broken = tmp_.filePath(QStringLiteral("broken.lfmorph"));
    {
        QFile in(file), out(broken);
        QVERIFY(in.open(QIODevice::ReadOnly) && out.open(QIODevice::WriteOnly));
        out.write(in.read(in.size() / 2));
    }
    QString message;
    QVERIFY(!openMorph(broken, &message));
    QVERIFY2(message.contains(QStringLiteral("broken.lfmorph")), qPrintable(message));
    QCOMPARE(panel_->data(), shown);

    QVERIFY(!openMorph(tmp_.filePath(QStringLiteral("missing-sequence")), &message));
    QVERIFY2(message.contains(QStringLiteral("missing-sequence")), qPrintable(message));
    QCOMPARE(panel_->data(), shown);

    // Cancel a build of the whole gallop: cancelled (no message), nothing replaced.
    QSignalSpy loaded(panel_, &MorphPanel::morphLoaded);
    panel_->openMorph(horseDir);
    QVERIFY(panel_->isBusy());
    QVERIFY(panel_->findChild<QPushButton*>(QStringLiteral("morphCancel"))->isVisible());
    QTest::qWait(200);
    panel_->cancel();
    QVERIFY(loaded.wait(30000));
    QCOMPARE(loaded.at(0).at(0).toBool(), false);
    QCOMPARE(loaded.at(0).at(1).toString(), QString());
    QCOMPARE(panel_->data(), shown);
    QVERIFY(!panel_->isBusy());

    // Another open while the gallop's build runs: that build is cancelled (the GUI thread does not wait
    // for it) and reports nothing; only the newest open ends, with its morph.
    QSignalSpy superseded(panel_, &MorphPanel::morphLoaded);
    panel_->openMorph(horseDir);
    QTest::qWait(200);
    QVERIFY(panel_->isBusy());
    panel_->openMorph(sequence_);
    QVERIFY(panel_->isBusy());
    QVERIFY(superseded.wait(120000));
    QVERIFY2(superseded.at(0).at(0).toBool(), qPrintable(superseded.at(0).at(1).toString()));
    QCOMPARE(panel_->data()->morph.frame_count(), std::size_t(6));
    QTest::qWait(200);
    QCOMPARE(int(superseded.size()), 1);
    QVERIFY(!panel_->isBusy());
}

void MorphStudioTest::gltfMorphTargetsPlay() {
    // The glTF sample is flat shaded (every edge a normal seam): like the CLI, it simplifies only with
    // --close-seams.
    const QString sphere = QStringLiteral(LODFORGE_SHARED_DATA "/morph-animated-morph-sphere/AnimatedMorphSphere.gltf");
    QVERIFY(openMorph(sphere));
    panel_->setLodFactor(0.0);
    QCOMPARE(panel_->triangleCount(), panel_->data()->lod.triangles);
    QVERIFY2(window_->logView()->toPlainText().contains(QStringLiteral("Close seams")),
             qPrintable(window_->logView()->toPlainText()));
    panel_->setLodFactor(1.0);
    panel_->setCloseSeams(true);
    QVERIFY(openMorph(sphere));
    const auto data = panel_->data();
    QVERIFY(data->morph.frame_count() > 2);
    VtkView* view = panel_->view();
    const QImage start = freshFrame(view);
    panel_->setTime(0.5);
    const QImage middle = freshFrame(view);
    const double change = differingFraction(start, middle, viewBackgroundColor());
    qInfo("sphere: %zu keyframes, t 0 -> 0.5 changes %.1f%% of the drawn pixels", data->morph.frame_count(), 100 * change);
    QVERIFY2(change > 0.05, qPrintable(QString::number(change)));
    const std::size_t full = panel_->triangleCount();
    panel_->setLodFactor(0.0);
    qInfo("sphere: %zu triangles at F 1, %zu at F 0", full, panel_->triangleCount());
    QVERIFY(panel_->triangleCount() < full);
    QCOMPARE(panel_->triangleCount(), data->lod.sequences.front().level_triangles.back());
}

void MorphStudioTest::landmarkPickingRoundTrips() {
    panel_->showLandmarks();
    LandmarkPicker* picker = panel_->landmarkPicker();
    QVERIFY(picker->isVisible());
    // The supermesh action waits for two meshes and a pair.
    QPushButton* build = picker->buildSupermeshButton();
    QVERIFY(MorphPanel::supermeshBuilderConnected());
    QVERIFY(!build->isEnabled());

    QSignalSpy loaded(picker, &LandmarkPicker::meshLoaded);
    picker->openMesh(Side::a, spotPath);
    picker->openMesh(Side::b, horseDir + QStringLiteral("/0001.obj"));
    QVERIFY(QTest::qWaitFor([&] { return loaded.size() == 2; }, 60000));
    QVERIFY2(loaded.at(0).at(1).toBool() && loaded.at(1).at(1).toBool(), qPrintable(loaded.at(0).at(2).toString()));
    const auto a = picker->mesh(Side::a);
    const auto b = picker->mesh(Side::b);
    QVERIFY(a && b);

    // A click in the middle of view A picks the vertex nearest to the surface point there.
    VtkView* viewA = picker->view(Side::a);
    const QImage before = freshFrame(viewA);
    const QPoint centre = viewA->rect().center();
    const auto surface = viewA->surfacePointAt(centre);
    QVERIFY2(surface, "no surface under the centre of view A");
    QTest::mouseClick(viewA, Qt::LeftButton, Qt::NoModifier, centre);
    QVERIFY(picker->pendingPick(Side::a).has_value());
    const std::uint32_t clicked = *picker->pendingPick(Side::a);
    QCOMPARE(clicked, LandmarkPicker::nearestVertex(*a, *surface));
    const lodforge::Vec3f p = a->positions[clicked];
    const double offset = std::hypot(p.x - (*surface)[0], p.y - (*surface)[1], p.z - (*surface)[2]);
    qInfo("clicked vertex %u, %.4g from the surface point", clicked, offset);
    QVERIFY(offset < 0.05);  // Spot is about 2 units across; its edges are ~0.03
    QVERIFY(picker->landmarks().pairs.empty());
    QCOMPARE(viewA->markerCount(), std::size_t(1));  // the waiting pick

    // The picking slot on B completes pair 1; two more pairs, a refused repeat, an undo.
    QVERIFY(picker->pickVertex(Side::b, 10));
    QVERIFY(!picker->pendingPick(Side::a) && !picker->pendingPick(Side::b));
    QVERIFY(picker->pickVertex(Side::a, 20));
    QVERIFY(picker->pickVertex(Side::b, 30));
    QString why;
    QVERIFY(!picker->pickVertex(Side::a, 20, &why));
    QVERIFY2(why.contains(QStringLiteral("pair 2")), qPrintable(why));
    QVERIFY(!picker->pickVertex(Side::b, static_cast<std::uint32_t>(b->vertex_count()), &why));
    QCOMPARE(picker->landmarks().pairs.size(), std::size_t(2));
    picker->undoLastPair();
    QCOMPARE(picker->landmarks().pairs.size(), std::size_t(1));
    QVERIFY(picker->pickVertex(Side::b, 50));  // B first this time
    QVERIFY(picker->pickVertex(Side::a, 40));
    QCOMPARE(picker->landmarks().pairs.size(), std::size_t(2));
    QCOMPARE(viewA->markerCount(), std::size_t(2));
    QCOMPARE(picker->view(Side::b)->markerCount(), std::size_t(2));
    const int yellowBefore = yellowPixels(before), yellowAfter = yellowPixels(freshFrame(viewA));
    qInfo("marker pixels: %d before, %d after", yellowBefore, yellowAfter);
    QVERIFY(yellowAfter > yellowBefore + 30);
    // B (a horse keyframe) is open: Build supermesh runs and fails with the file's name and the reason;
    // the horse on screen stays.
    QVERIFY(build->isEnabled());
    QSignalSpy built(panel_, &MorphPanel::morphLoaded);
    build->click();
    QVERIFY(built.wait(60000));
    QVERIFY(!built.at(0).at(0).toBool());
    const QString error = built.at(0).at(1).toString();
    qInfo("supermesh of Spot and a horse frame: %s", qPrintable(error));
    QVERIFY2(error.contains(QStringLiteral("0001.obj")) && error.contains(QStringLiteral("border")), qPrintable(error));
    try {
        (void)MorphPanel::build_supermesh(*a, *b, picker->landmarks(), "spot.obj", "0001.obj", nullptr);
        QFAIL("build_supermesh accepted an open mesh");
    } catch (const lodforge::Error& e) {
        QVERIFY2(std::string(e.what()).find("0001.obj") != std::string::npos, e.what());
    }

    // Saved through the core writer, read back by the core reader: the pairs as picked.
    const QString file = tmp_.filePath(QStringLiteral("L.json"));
    QVERIFY2(picker->saveLandmarks(file, &why), qPrintable(why));
    const lodforge::Landmarks read = lodforge::read_landmarks(file.toStdString());
    const std::vector<lodforge::LandmarkPair> expected{{clicked, 10}, {40, 50}};
    QVERIFY(read.pairs == expected);
    picker->clearPairs();
    QVERIFY(picker->landmarks().pairs.empty());
    QCOMPARE(viewA->markerCount(), std::size_t(0));
    QVERIFY2(picker->loadLandmarks(file, &why), qPrintable(why));
    QVERIFY(picker->landmarks().pairs == expected);
    QCOMPARE(viewA->markerCount(), std::size_t(2));

    // A file naming a vertex B does not have is refused with its name; the pairs stay.
    lodforge::Landmarks bad;
    bad.pairs = {{1, static_cast<std::uint32_t>(b->vertex_count() + 5)}};
    const QString badFile = tmp_.filePath(QStringLiteral("bad.json"));
    lodforge::write_landmarks(bad, badFile.toStdString());
    QVERIFY(!picker->loadLandmarks(badFile, &why));
    QVERIFY2(why.contains(QStringLiteral("bad.json")), qPrintable(why));
    QVERIFY(picker->landmarks().pairs == expected);
    QVERIFY(!picker->loadLandmarks(tmp_.filePath(QStringLiteral("missing.json")), &why));
}

void MorphStudioTest::supermeshOfSpotAndASpherePlays() {
    panel_->showLandmarks();
    LandmarkPicker* picker = panel_->landmarkPicker();
    // B: a sphere around Spot, written as a PLY the picker opens like any file.
    const auto spot = std::make_shared<lodforge::Mesh>(lodforge::read_mesh(spotPath.toStdString()));
    const lodforge::Vec3f centre = spot->bounds().center();
    const QString ball = tmp_.filePath(QStringLiteral("ball.ply"));
    lodforge::write_mesh(lodforge::test::icosphere(3, 0.5f, centre), ball.toStdString());
    QSignalSpy loaded(picker, &LandmarkPicker::meshLoaded);
    picker->openMesh(Side::a, spotPath);
    picker->openMesh(Side::b, ball);
    QVERIFY(QTest::qWaitFor([&] { return loaded.size() == 2; }, 60000));
    const auto a = picker->mesh(Side::a);
    const auto b = picker->mesh(Side::b);
    QVERIFY(a && b);
    // One pair: Spot's vertex furthest along +x and the sphere vertex in the same direction.
    std::uint32_t va = 0, vb = 0;
    for (std::uint32_t v = 0; v < a->vertex_count(); ++v)
        if (a->positions[v].x > a->positions[va].x) va = v;
    for (std::uint32_t v = 0; v < b->vertex_count(); ++v)
        if (b->positions[v].x > b->positions[vb].x) vb = v;
    QVERIFY(picker->pickVertex(Side::a, va));
    QVERIFY(picker->pickVertex(Side::b, vb));
    QPushButton* build = picker->buildSupermeshButton();
    QVERIFY(build->isEnabled());
    QSignalSpy built(panel_, &MorphPanel::morphLoaded);
    build->click();
    QVERIFY(built.wait(120000));
    QVERIFY2(built.at(0).at(0).toBool(), qPrintable(built.at(0).at(1).toString()));
    const auto data = panel_->data();
    QVERIFY(data);
    QCOMPARE(data->morph.frame_count(), std::size_t(2));
    // Every point of both meshes is a vertex of the supermesh (plus the crossings).
    QVERIFY(data->morph.vertex_count() > a->vertex_count() / 2 + b->vertex_count());
    qInfo("supermesh: %zu vertices, %zu triangles", data->morph.vertex_count(), data->lod.triangles);

    // The animation shows A at t = 0 and B at t = 1; F still lowers the triangle count.
    QVERIFY(QTest::qWaitFor([&] { return !panel_->isBusy(); }, 5000));
    panel_->setLodFactor(1.0);
    panel_->setTime(0.0);
    VtkView* view = panel_->view();
    const QImage cow = freshFrame(view);
    panel_->setTime(1.0);
    const QImage sphere = freshFrame(view);
    const double change = differingFraction(cow, sphere, viewBackgroundColor());
    qInfo("supermesh: t 0 -> 1 changes %.1f%% of the drawn pixels", 100 * change);
    QVERIFY2(change > 0.05, qPrintable(QString::number(change)));
    const std::size_t full = panel_->triangleCount();
    panel_->setLodFactor(0.0);
    QVERIFY(panel_->triangleCount() < full);
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("LodForgeTests"));
    QApplication::setApplicationName(QStringLiteral("gui_morph_studio_test"));
    MorphStudioTest test;
    return QTest::qExec(&test, argc, argv);
}
#include "morph_studio_test.moc"
