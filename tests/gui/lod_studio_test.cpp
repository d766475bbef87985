// The studio's LOD workflow in process, under Xvfb: LOD chains on the textured Spot sample, the level
// slider, side-by-side views in one camera, heat maps, appearance toggles and the split compare, the
// parameters panel with undo and presets, the report export, and cancelling a long job on the dragon.
// What is shown is checked on real pixels, with tolerances.
#include "MainWindow.h"
#include "PixelStats.h"
#include "StudioSession.h"

#include "lodforge/pack/preset.h"
#include "lodforge/pack/preset_library.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/ParametersPanel.h"
#include "lodforge/widgets/ReportPanel.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFile>
#include <QLabel>
#include <QLocale>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QProcess>
#include <QDir>
#include <QDirIterator>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSlider>
#include <QStatusBar>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <QUndoStack>

#include <algorithm>
#include <cmath>
#include <memory>

using lodforge::studio::MainWindow;
using lodforge::testing::differingFraction;
using lodforge::testing::hueClusters;
using lodforge::testing::measure;
using lodforge::testing::PixelStats;
using lodforge::widgets::viewBackgroundColor;
using lodforge::widgets::ViewOptions;
using lodforge::widgets::VtkView;

namespace {

const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");
const QString dragonPath = QStringLiteral(LODFORGE_SHARED_DATA "/scan-dragon/dragon_vrip.ply");

QImage frameOf(VtkView* view) { return view->grabFramebuffer().convertToFormat(QImage::Format_RGB32); }

QString triangles(std::size_t n) { return QLocale().toString(qulonglong(n)); }

}  // namespace

class LodStudioTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase();
    void init();
    void cleanup();

    void sideBySideShowsDistinctLevelsInOneCamera();
    void sliderShowsTheChosenLevel();
    void heatmapShowsTheErrorField();
    void appearanceTogglesAndSplitCompare();
    void parameterChangesUndoAndRedo();
    void presetSavesAndReloads();
    void structureMethodsBuildLevels();
    void clusterMethodBuildsLevels();
    void reportExportsHtmlAndPdf();
    void reportShowsImageErrorsComputedInTheBackground();
    void exportedPackMatchesTheCli();
    void cancelStopsALongJobOnTheDragon();
    void shortcutsSettingsAndErrorDialogs();

private:
    bool load(const QString& path);
    // Runs buildLodChain (or computeHeatmaps) and waits; returns jobFinished's ok, message in `message`.
    bool runJob(bool heatmap, QString* message = nullptr, int timeoutMs = 60000);
    bool buildSpotChain(const std::vector<double>& ratios);

    std::unique_ptr<MainWindow> window_;
};

void LodStudioTest::initTestCase() {
    QVERIFY2(QFile::exists(spotPath), qPrintable(spotPath));
    QSettings().clear();
}

void LodStudioTest::init() {
    window_ = std::make_unique<MainWindow>();
    window_->setInteractive(false);
    window_->resize(1200, 860);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
}

void LodStudioTest::cleanup() {
    while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
    window_.reset();
}

bool LodStudioTest::load(const QString& path) {
    QSignalSpy finished(window_.get(), &MainWindow::loadFinished);
    window_->openFile(path);
    return finished.wait(120000) && finished.at(0).at(0).toBool();
}

bool LodStudioTest::runJob(bool heatmap, QString* message, int timeoutMs) {
    QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
    if (heatmap) {
        window_->computeHeatmaps();
    } else {
        window_->buildLodChain();
    }
    if (finished.isEmpty() && !finished.wait(timeoutMs)) {
        if (message) *message = QStringLiteral("no jobFinished in time");
        return false;
    }
    if (message) *message = finished.at(0).at(2).toString();
    // A chain's levels are measured after it ends: the tests read their errors.
    if (!heatmap && finished.at(0).at(1).toBool() && !lodforge::testing::measuredInStudio(*window_)) {
        if (message) *message = QStringLiteral("the levels' measure never ended");
        return false;
    }
    return finished.at(0).at(1).toBool();
}

bool LodStudioTest::buildSpotChain(const std::vector<double>& ratios) {
    if (!load(spotPath)) return false;
    lodforge::Preset preset = window_->preset();
    preset.levels = lodforge::lod_targets_from_ratios(ratios);
    window_->setPreset(preset);
    QString message;
    const bool ok = runJob(false, &message);
    if (!ok) qWarning("LOD chain failed: %s", qPrintable(message));
    return ok;
}

void LodStudioTest::sideBySideShowsDistinctLevelsInOneCamera() {
    QVERIFY(buildSpotChain({0.5, 0.1, 0.02}));
    auto* levels = window_->levelViews();
    QCOMPARE(levels->levelCount(), 4);
    // Level counts fall with the targets; the original is level 0.
    const auto& data = levels->levels();
    QCOMPARE(data[0].triangles, std::size_t(5856));
    for (int i = 1; i < 4; ++i) {
        QVERIFY2(data[i].triangles < data[i - 1].triangles, qPrintable(QString::number(data[i].triangles)));
        QVERIFY(data[i].errorRelative > 0 && data[i].errorRelative >= data[i - 1].errorRelative);
    }
    QVERIFY(std::abs(double(data[1].triangles) - 2928.0) < 60);

    window_->setSideBySide(true);
    ViewOptions options = window_->viewOptions();
    options.wireframe = true;
    window_->setViewOptions(options);
    const QList<VtkView*> tiles = levels->tileViews();
    const QList<QLabel*> labels = levels->tileLabels();
    QCOMPARE(tiles.size(), 4);
    QTRY_VERIFY_WITH_TIMEOUT(tiles[3]->isVisible() && tiles[3]->frameCount() > 0, 10000);

    // Each label names its level's triangle count and error.
    for (int i = 0; i < 4; ++i) {
        const QString text = labels[i]->text();
        qInfo("tile %d: %s", i, qPrintable(text));
        // Reached against the target (ratios resolved to counts).
        const QString target = i > 0 ? QStringLiteral(" / ") + triangles(data[i].targetTriangles) : QString();
        QVERIFY2(text.contains(triangles(data[i].triangles) + target + QStringLiteral(" triangles")), qPrintable(text));
        if (i > 0) QVERIFY2(text.contains(QStringLiteral("error")), qPrintable(text));
    }
    // In wireframe, fewer triangles leave more background between the edges.
    QList<QImage> frames;
    QList<PixelStats> stats;
    for (VtkView* tile : tiles) {
        frames << frameOf(tile);
        stats << measure(frames.back(), viewBackgroundColor());
        qInfo("wire pixels %lld (%.1f%%)", stats.back().modelPixels, 100.0 * stats.back().modelFraction());
    }
    for (int i = 1; i < 4; ++i)
        QVERIFY2(stats[i].modelPixels < stats[i - 1].modelPixels, qPrintable(QString::number(i)));
    QVERIFY2(stats[3].modelPixels < 0.6 * stats[0].modelPixels, "the coarsest level must be clearly sparser");
    QVERIFY2(stats[3].modelPixels > 0, "the coarsest level must be on screen");

    // One camera: dragging in the first tile turns the mesh in the last one too.
    const QPoint from = tiles[0]->rect().center();
    QTest::mousePress(tiles[0], Qt::LeftButton, Qt::NoModifier, from);
    for (int step = 1; step <= 8; ++step) {
        QMouseEvent move(QEvent::MouseMove, QPointF(from + QPoint(12 * step, 0)), tiles[0]->mapToGlobal(QPointF(from + QPoint(12 * step, 0))),
                         Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
        QApplication::sendEvent(tiles[0], &move);
    }
    QTest::mouseRelease(tiles[0], Qt::LeftButton, Qt::NoModifier, from + QPoint(96, 0));
    const QImage turnedFirst = frameOf(tiles[0]);
    const QImage turnedLast = frameOf(tiles[3]);
    const double firstChanged = differingFraction(frames[0], turnedFirst, viewBackgroundColor());
    const double lastChanged = differingFraction(frames[3], turnedLast, viewBackgroundColor());
    qInfo("drag changed %.1f%% of the first tile and %.1f%% of the last", 100 * firstChanged, 100 * lastChanged);
    QVERIFY2(firstChanged > 0.2, qPrintable(QString::number(firstChanged)));
    QVERIFY2(lastChanged > 0.2, qPrintable(QString::number(lastChanged)));

    // The window grab holds every tile.
    const QImage shot = window_->grabWindowImage();
    const QRect tileRect(tiles[3]->mapTo(window_.get(), QPoint(0, 0)), tiles[3]->size());
    QVERIFY(measure(shot.copy(tileRect), viewBackgroundColor()).modelPixels > 0);
}

void LodStudioTest::sliderShowsTheChosenLevel() {
    QVERIFY(buildSpotChain({0.5, 0.1, 0.02}));
    auto* levels = window_->levelViews();
    QSlider* slider = levels->levelSlider();
    QVERIFY(slider->isEnabled());
    QCOMPARE(slider->maximum(), 3);
    ViewOptions options = window_->viewOptions();
    options.wireframe = true;
    window_->setViewOptions(options);

    slider->setValue(0);
    QCOMPARE(levels->currentLevel(), 0);
    const QImage original = frameOf(window_->view());
    QVERIFY2(levels->singleLabel()->text().contains(triangles(5856)), qPrintable(levels->singleLabel()->text()));

    // Moving the slider (as a user would, by keyboard) shows the coarsest level.
    slider->setFocus();
    for (int i = 0; i < 3; ++i) QTest::keyClick(slider, Qt::Key_Right);
    QCOMPARE(levels->currentLevel(), 3);
    const QString label = levels->singleLabel()->text();
    qInfo("label: %s", qPrintable(label));
    QVERIFY2(label.contains(triangles(levels->levels()[3].triangles) + QStringLiteral(" / ") +
                            triangles(levels->levels()[3].targetTriangles) + QStringLiteral(" triangles")),
             qPrintable(label));
    const QImage coarse = frameOf(window_->view());
    const double changed = differingFraction(original, coarse, viewBackgroundColor());
    qInfo("level 0 -> 3 changes %.1f%% of the model pixels", 100 * changed);
    QVERIFY2(changed > 0.3, qPrintable(QString::number(changed)));
    QVERIFY(measure(coarse, viewBackgroundColor()).modelPixels < 0.6 * measure(original, viewBackgroundColor()).modelPixels);

    // Page Up goes back one level (the window's shortcut).
    auto* previous = window_->findChild<QAction*>(QStringLiteral("actionPreviousLevel"));
    QVERIFY(previous && previous->isEnabled());
    previous->trigger();
    QCOMPARE(levels->currentLevel(), 2);
    QCOMPARE(slider->value(), 2);
}

void LodStudioTest::heatmapShowsTheErrorField() {
    QVERIFY(buildSpotChain({0.5, 0.1, 0.02}));
    auto* levels = window_->levelViews();
    levels->setCurrentLevel(3);
    const QImage textured = frameOf(window_->view());
    const int texturedHues = hueClusters(textured, viewBackgroundColor());

    QString message;
    QVERIFY2(runJob(true, &message), qPrintable(message));
    QVERIFY(levels->hasHeatmaps() && levels->heatmapVisible());
    auto* action = window_->findChild<QAction*>(QStringLiteral("actionHeatmap"));
    QVERIFY(action && action->isChecked());
    QCOMPARE(int(levels->heatmaps().scenes.size()), 4);
    QCOMPARE(levels->heatmaps().levelMax[0], 0.f);
    QVERIFY(levels->heatmaps().levelMax[3] > levels->heatmaps().levelMax[1]);
    // The automatic range: a high percentile of the used vertices' values, at most the largest.
    QVERIFY(levels->heatmaps().autoRange > 0 && levels->heatmaps().autoRange <= levels->heatmaps().maxError);
    QCOMPARE(window_->view()->scalarRange(), levels->heatmaps().autoRange);

    const QImage heat = frameOf(window_->view());
    const int heatHues = hueClusters(heat, viewBackgroundColor());
    qInfo("hue clusters: textured %d, heat map %d", texturedHues, heatHues);
    QVERIFY2(heatHues > 2, qPrintable(QString::number(heatHues)));
    QVERIFY(differingFraction(textured, heat, viewBackgroundColor()) > 0.3);

    // The value under the cursor: on the surface it lies in [0, largest]; shown in the status bar.
    VtkView* view = window_->view();
    const PixelStats s = measure(heat, viewBackgroundColor());
    QPoint onModel;
    for (int y = heat.height() / 3; y < 2 * heat.height() / 3 && onModel.isNull(); y += 4)
        for (int x = heat.width() / 3; x < 2 * heat.width() / 3; x += 4)
            if (!lodforge::testing::nearColor(heat.pixel(x, y), viewBackgroundColor(), 8) && x < heat.width() * 0.8) {
                onModel = QPoint(x, y) / view->devicePixelRatio();
                break;
            }
    QVERIFY2(!onModel.isNull(), qPrintable(QString::number(s.modelPixels)));
    const std::optional<double> value = view->scalarAt(onModel);
    QVERIFY(value.has_value());
    QVERIFY2(*value >= 0 && *value <= levels->heatmaps().levelMax[3] * 1.0001, qPrintable(QString::number(*value)));
    QVERIFY(!view->scalarAt(QPoint(2, 2)).has_value());  // the background corner
    QTest::mouseMove(view, onModel);
    QTRY_VERIFY_WITH_TIMEOUT(window_->statusBar()->currentMessage().contains(QStringLiteral("Distance to the original")),
                             5000);
    qInfo("hover: %s", qPrintable(window_->statusBar()->currentMessage()));

    // The range control: a smaller range pushes the colours up the map.
    auto* range = window_->findChild<QDoubleSpinBox*>(QStringLiteral("heatmapRange"));
    QVERIFY(range);
    range->setValue(levels->heatmaps().levelMax[3] * 0.1);
    QVERIFY(std::abs(range->value() - levels->heatmaps().levelMax[3] * 0.1) < 1e-6);
    QVERIFY(std::abs(view->scalarRange() - range->value()) < 1e-9);
    const QImage saturated = frameOf(view);
    const double changed = differingFraction(heat, saturated, viewBackgroundColor());
    qInfo("range / 10 changes %.1f%% of the model pixels", 100 * changed);
    QVERIFY2(changed > 0.2, qPrintable(QString::number(changed)));

    // Off again: the texture is back.
    action->trigger();
    QVERIFY(!levels->heatmapVisible());
    QVERIFY(differingFraction(textured, frameOf(view), viewBackgroundColor()) < 0.02);
}

void LodStudioTest::appearanceTogglesAndSplitCompare() {
    QVERIFY(buildSpotChain({0.02}));
    auto* levels = window_->levelViews();
    VtkView* view = window_->view();
    levels->setCurrentLevel(0);
    const QImage textured = frameOf(view);

    auto toggled = [this, view](const char* action) {
        auto* a = window_->findChild<QAction*>(QString::fromLatin1(action));
        if (!a) return QImage();
        a->trigger();
        const QImage image = frameOf(view);
        a->trigger();
        return image;
    };
    const QImage normals = toggled("actionNormalColors");
    const QImage checker = toggled("actionUvChecker");
    const QImage edges = toggled("actionEdges");
    QVERIFY(!normals.isNull() && !checker.isNull() && !edges.isNull());
    const PixelStats n = measure(normals, viewBackgroundColor());
    qInfo("normals as colours: %.1f%% chromatic; checker changes %.1f%%, edges change %.1f%%",
          100 * n.chromaticFraction, 100 * differingFraction(textured, checker, viewBackgroundColor()),
          100 * differingFraction(textured, edges, viewBackgroundColor()));
    QVERIFY2(n.chromaticFraction > 0.5, "normals as colours are strongly coloured");
    QVERIFY(hueClusters(normals, viewBackgroundColor()) > 2);
    QVERIFY(differingFraction(textured, checker, viewBackgroundColor()) > 0.3);
    QVERIFY(differingFraction(textured, edges, viewBackgroundColor()) > 0.1);
    QVERIFY(differingFraction(textured, frameOf(view), viewBackgroundColor()) < 0.01);  // all back off

    // Split compare: the original left of the split, the level right of it.
    ViewOptions options = window_->viewOptions();
    options.wireframe = true;
    window_->setViewOptions(options);
    const QImage original = frameOf(view);
    levels->setCurrentLevel(1);
    const QImage level = frameOf(view);
    window_->setCompareVisible(true);
    auto* split = window_->findChild<QSlider*>(QStringLiteral("splitSlider"));
    QVERIFY(split);
    split->setValue(500);
    const QImage both = frameOf(view);
    const QRect left(0, 0, both.width() / 2 - 3, both.height());
    const QRect right(both.width() / 2 + 3, 0, both.width() / 2 - 3, both.height());
    const double leftVsOriginal = differingFraction(both, original, viewBackgroundColor(), left);
    const double rightVsLevel = differingFraction(both, level, viewBackgroundColor(), right);
    const double rightVsOriginal = differingFraction(both, original, viewBackgroundColor(), right);
    qInfo("split: left vs original %.1f%%, right vs level %.1f%%, right vs original %.1f%%", 100 * leftVsOriginal,
          100 * rightVsLevel, 100 * rightVsOriginal);
    QVERIFY(leftVsOriginal < 0.05);
    QVERIFY(rightVsLevel < 0.05);
    QVERIFY(rightVsOriginal > 0.2);
    // Dragging the split to the right shows more of the original.
    split->setValue(900);
    const QImage moved = frameOf(view);
    const QRect middle(both.width() * 6 / 10, 0, both.width() / 5, both.height());
    QVERIFY(differingFraction(moved, original, viewBackgroundColor(), middle) < 0.05);
}

void LodStudioTest::parameterChangesUndoAndRedo() {
    auto* panel = window_->parametersPanel();
    QUndoStack* undo = window_->undoStack();
    QCOMPARE(undo->count(), 0);
    const lodforge::Preset original = window_->preset();

    auto* normal = panel->findChild<QDoubleSpinBox*>(QStringLiteral("normalWeight"));
    auto* lock = panel->findChild<QCheckBox*>(QStringLiteral("lockBorder"));
    QVERIFY(normal && lock);
    normal->setValue(0.5);
    QCOMPARE(window_->preset().weights.normal, 0.5f);
    QCOMPARE(undo->count(), 1);
    lock->click();
    QVERIFY(window_->preset().lock_border);
    panel->addLevel();
    QCOMPARE(window_->preset().levels.size(), original.levels.size() + 1);
    QCOMPARE(undo->count(), 3);
    QVERIFY(window_->isWindowModified());

    // Ctrl+Z three times brings back the defaults, widgets included; Ctrl+Shift+Z redoes.
    auto* undoAction = window_->findChild<QAction*>(QStringLiteral("actionUndo"));
    auto* redoAction = window_->findChild<QAction*>(QStringLiteral("actionRedo"));
    QVERIFY(undoAction && redoAction);
    undoAction->trigger();
    QCOMPARE(window_->preset().levels.size(), original.levels.size());
    undoAction->trigger();
    QVERIFY(!window_->preset().lock_border);
    QVERIFY(!lock->isChecked());
    undoAction->trigger();
    QCOMPARE(window_->preset(), original);
    QVERIFY(std::abs(normal->value() - double(original.weights.normal)) < 1e-6);
    QVERIFY(!window_->isWindowModified());
    redoAction->trigger();
    QCOMPARE(window_->preset().weights.normal, 0.5f);
    QCOMPARE(normal->value(), 0.5);
    QVERIFY(!undoAction->text().isEmpty());
}

void LodStudioTest::presetSavesAndReloads() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    lodforge::Preset preset;
    preset.name = "studio test";
    preset.method = lodforge::LodMethod::cluster;
    preset.levels = {{lodforge::LodTarget::Kind::triangles, 2000}, {lodforge::LodTarget::Kind::triangles, 300}};
    preset.weights.color = 0.25f;
    preset.lock_border = true;
    preset.octree.max_depth = 11;
    preset.mcoctree.resolution = 96;
    window_->setPreset(preset);
    const QString path = dir.filePath(QStringLiteral("game.json"));
    QString error;
    QVERIFY2(window_->savePreset(path, &error), qPrintable(error));
    QVERIFY(!window_->isWindowModified());

    // The file is the CLI's preset format, read back by the same function.
    QCOMPARE(lodforge::load_preset(QFile::encodeName(path).toStdString()), preset);
    QFile file(path);
    QVERIFY(file.open(QIODevice::ReadOnly));
    const QByteArray json = file.readAll();
    QVERIFY(json.contains("\"cluster\"") && json.contains("\"triangles\": 2000") && json.contains("\"max_depth\": 11"));

    window_->setPreset(lodforge::Preset{});
    QCOMPARE(window_->preset(), lodforge::Preset{});
    QVERIFY(window_->loadPreset(path, &error));
    QCOMPARE(window_->preset(), preset);
    auto* method = window_->parametersPanel()->findChild<QComboBox*>(QStringLiteral("method"));
    QVERIFY(method && method->currentData().toString() == QStringLiteral("cluster"));
    // Loading is one undo step.
    window_->undoStack()->undo();
    QCOMPARE(window_->preset(), lodforge::Preset{});

    // A broken preset is refused with a message naming the file; the parameters stay.
    const QString broken = dir.filePath(QStringLiteral("broken.json"));
    QFile out(broken);
    QVERIFY(out.open(QIODevice::WriteOnly));
    out.write("{\"version\": 1, \"max_dept\": 4}");
    out.close();
    QVERIFY(!window_->loadPreset(broken, &error));
    QVERIFY2(error.contains(QStringLiteral("broken.json")) && error.contains(QStringLiteral("max_dept")),
             qPrintable(error));
    QCOMPARE(window_->preset(), lodforge::Preset{});

    // A shipped preset loads by name (as `--preset console` does); it is not a file to save back to.
    QVERIFY2(window_->loadPreset(QStringLiteral("console"), &error), qPrintable(error));
    QCOMPARE(window_->preset(), lodforge::load_shipped_preset("console"));
    QVERIFY(!window_->loadPreset(QStringLiteral("consol"), &error));
    QVERIFY2(error.contains(QStringLiteral("not a shipped preset")), qPrintable(error));

    // The last preset file comes back in the next session.
    window_->close();
    window_ = std::make_unique<MainWindow>();
    QCOMPARE(window_->preset(), preset);
}

// LODStrips, the MC octree and the out-of-core octree build their levels in the studio like the chain
// methods; a target they cannot take is refused with the reason in the log.
void LodStudioTest::structureMethodsBuildLevels() {
    QVERIFY(load(spotPath));
    auto* method = window_->parametersPanel()->findChild<QComboBox*>(QStringLiteral("method"));
    QVERIFY(method);
    for (const char* name : {"lodstrips", "mcoctree", "octree"}) {
        method->setCurrentIndex(method->findData(QString::fromLatin1(name)));
        QCOMPARE(QString::fromLatin1(lodforge::to_string(window_->preset().method)), QString::fromLatin1(name));
        lodforge::Preset preset = window_->preset();
        preset.levels = {{lodforge::LodTarget::Kind::ratio, 0.5}, {lodforge::LodTarget::Kind::ratio, 0.2}};
        preset.octree.max_triangles_per_node = 300;
        preset.mcoctree.resolution = 48;
        window_->setPreset(preset);
        QString message;
        QVERIFY2(runJob(false, &message), qPrintable(QString::fromLatin1(name) + QStringLiteral(": ") + message));
        const auto& levels = window_->levelViews()->levels();
        QCOMPARE(int(levels.size()), 3);
        QVERIFY2(levels[1].triangles < 5856 && levels[2].triangles < levels[1].triangles, name);
        QVERIFY2(levels[2].errorRelative > 0, name);
    }
    lodforge::Preset preset = window_->preset();
    preset.levels = {{lodforge::LodTarget::Kind::error, 0.01}};
    window_->setPreset(preset);
    QString message;
    QVERIFY(!runJob(false, &message));
    QVERIFY2(message.contains(QStringLiteral("error targets")), qPrintable(message));
    QVERIFY(window_->logView()->toPlainText().contains(QStringLiteral("error targets")));
    QVERIFY(!window_->isBusy());
}

void LodStudioTest::clusterMethodBuildsLevels() {
    QVERIFY(load(spotPath));
    lodforge::Preset preset = window_->preset();
    preset.method = lodforge::LodMethod::cluster;
    preset.levels = {{lodforge::LodTarget::Kind::ratio, 0.3}, {lodforge::LodTarget::Kind::triangles, 400}};
    window_->setPreset(preset);
    QString message;
    QVERIFY2(runJob(false, &message), qPrintable(message));
    const auto& levels = window_->levelViews()->levels();
    QCOMPARE(int(levels.size()), 3);
    QVERIFY(levels[1].triangles < 5856 && levels[2].triangles < levels[1].triangles);
    QVERIFY(!levels[1].verticesOnOriginal && levels[2].errorRelative > 0);
    // Its heat map is drawn on the level itself.
    QVERIFY2(runJob(true, &message), qPrintable(message));
    QVERIFY(window_->levelViews()->heatmaps().levelMax[2] > 0);
}

void LodStudioTest::reportShowsImageErrorsComputedInTheBackground() {
    QVERIFY(buildSpotChain({0.3, 0.02}));
    auto* report = window_->reportPanel();
    QTableWidget* table = report->table();
    const int column = table->columnCount() - 1;
    QVERIFY(table->horizontalHeaderItem(column)->text().startsWith(QStringLiteral("Image error")));
    QCOMPARE(table->item(0, column)->text(), QStringLiteral("—"));
    // The chain's job is over while the images are still rendered: the window takes new work.
    QVERIFY(!window_->isBusy());
    QTRY_VERIFY_WITH_TIMEOUT(report->rows().size() == 3 && report->rows()[2].imageError.has_value(), 120000);
    const auto& rows = report->rows();
    QVERIFY(!rows[0].imageError.has_value());
    QVERIFY(rows[1].imageError.has_value());
    qInfo("image error: level 1 %.3f (silhouette %.4f), level 2 %.3f (silhouette %.4f)", *rows[1].imageError,
          *rows[1].imageSilhouette, *rows[2].imageError, *rows[2].imageSilhouette);
    QVERIFY(*rows[1].imageError > 0);
    QVERIFY(*rows[2].imageError > *rows[1].imageError);
    QVERIFY(*rows[2].imageSilhouette > *rows[1].imageSilhouette);
    // The table shows them, and the exported report carries the column.
    QVERIFY2(table->item(2, column)->text().startsWith(QString::number(*rows[2].imageError, 'f', 2)),
             qPrintable(table->item(2, column)->text()));
    QVERIFY(window_->logView()->toPlainText().contains(QStringLiteral("image error per level")));
    QTemporaryDir dir;
    QString error;
    const QString html = dir.filePath(QStringLiteral("r.html"));
    QVERIFY2(window_->exportReport(html, &error), qPrintable(error));
    QFile h(html);
    QVERIFY(h.open(QIODevice::ReadOnly));
    const QString text = QString::fromUtf8(h.readAll());
    QVERIFY(text.contains(QStringLiteral("Image error")));
    QVERIFY(text.contains(table->item(1, column)->text()));
}

void LodStudioTest::reportExportsHtmlAndPdf() {
    // Enough levels for the PDF's table to go over a page, with heat maps (a second picture per level).
    const std::vector<double> ratios = {0.7, 0.5, 0.35, 0.25, 0.15, 0.1, 0.05, 0.02};
    QVERIFY(buildSpotChain(ratios));
    QString message;
    QVERIFY2(runJob(true, &message), qPrintable(message));
    auto* report = window_->reportPanel();
    const int rows = int(ratios.size()) + 1;
    QCOMPARE(report->table()->rowCount(), rows);
    QCOMPARE(report->table()->item(0, 1)->text(), triangles(5856));
    QTemporaryDir dir;
    const QString html = dir.filePath(QStringLiteral("spot_report.html"));
    const QString pdf = dir.filePath(QStringLiteral("spot_report.pdf"));
    QString error;
    QVERIFY2(window_->exportReport(html, &error), qPrintable(error));
    QVERIFY2(window_->exportReport(pdf, &error), qPrintable(error));
    QVERIFY(window_->levelViews()->heatmapVisible());  // the view is as it was

    QFile h(html);
    QVERIFY(h.open(QIODevice::ReadOnly));
    const QString text = QString::fromUtf8(h.readAll());
    QCOMPARE(text.count(QStringLiteral("<tr class=\"level\">")), rows);
    for (const auto& level : window_->levelViews()->levels())
        QVERIFY2(text.contains(QStringLiteral(">%1<").arg(triangles(level.triangles))), qPrintable(triangles(level.triangles)));
    // Per level the shaded level and its heat map, plus the chart, embedded; the parameters listed.
    QCOMPARE(text.count(QStringLiteral("data:image/png;base64,")), 2 * rows + 1);
    QVERIFY(text.contains(QStringLiteral("<td>weights.normal</td>")));

    QFile p(pdf);
    QVERIFY(p.open(QIODevice::ReadOnly));
    QVERIFY(p.readAll().startsWith("%PDF-"));
    auto run = [](const QString& program, const QStringList& arguments) {
        QProcess process;
        process.start(program, arguments);
        if (!process.waitForFinished(60000) || process.exitCode() != 0) return QString();
        return QString::fromUtf8(process.readAllStandardOutput());
    };
    // Read back as text with its layout (poppler): every row of the table on one line, its numbers whole.
    const QStringList pages = run(QStringLiteral(LODFORGE_PDFTOTEXT), {QStringLiteral("-layout"), pdf, QStringLiteral("-")})
                                  .split(QLatin1Char('\f'));
    QVERIFY2(pages.size() >= 3, qPrintable(QString::number(pages.size())));  // at least two pages and the end
    QVERIFY(pages[0].contains(QStringLiteral("weights.normal")));
    std::vector<int> rowsOnPage(std::size_t(pages.size()), 0);
    for (int r = 0; r < rows; ++r) {
        QStringList tokens;
        for (int c = 0; c <= 5; ++c)
            tokens += report->table()->item(r, c)->text().remove(QStringLiteral("≈")).split(QLatin1Char(' '), Qt::SkipEmptyParts);
        int found = -1;
        for (int page = 0; page < int(pages.size()) && found < 0; ++page)
            for (const QString& line : pages[page].split(QLatin1Char('\n'))) {
                const QStringList words = line.split(QLatin1Char(' '), Qt::SkipEmptyParts);
                if (!words.isEmpty() && words.front() == tokens.front() &&
                    std::all_of(tokens.begin(), tokens.end(), [&](const QString& t) { return words.contains(t); })) {
                    found = page;
                    break;
                }
            }
        QVERIFY2(found >= 0, qPrintable(tokens.join(QLatin1Char(' '))));
        ++rowsOnPage[std::size_t(found)];
        // The header is repeated on every page that has rows.
        QVERIFY2(pages[found].contains(QStringLiteral("Triangles")), qPrintable(pages[found]));
    }
    // Pictures (poppler's image list): a row's two pictures on its own page, the chart last.
    const QStringList images = run(QStringLiteral(LODFORGE_PDFIMAGES), {QStringLiteral("-list"), pdf}).split(QLatin1Char('\n'));
    std::vector<int> imagesOnPage(std::size_t(pages.size()), 0);
    int total = 0;
    for (const QString& line : images.mid(2)) {
        bool ok = false;
        const int page = line.section(QLatin1Char(' '), 0, 0, QString::SectionSkipEmpty).toInt(&ok);
        if (!ok || page < 1 || page > int(pages.size())) continue;
        ++imagesOnPage[std::size_t(page - 1)];
        ++total;
    }
    QCOMPARE(total, 2 * rows + 1);
    // Rendered (poppler's pdftoppm): the first page shows its pictures, not only text and rules.
    const QString prefix = dir.filePath(QStringLiteral("page"));
    run(QStringLiteral(LODFORGE_PDFTOPPM), {QStringLiteral("-r"), QStringLiteral("40"), QStringLiteral("-f"),
                                             QStringLiteral("1"), QStringLiteral("-l"), QStringLiteral("1"),
                                             QStringLiteral("-png"), pdf, prefix});
    const QImage firstPage(prefix + QStringLiteral("-1.png"));
    QVERIFY2(!firstPage.isNull(), qPrintable(prefix));
    long coloured = 0;
    for (int y = 0; y < firstPage.height(); ++y)
        for (int x = 0; x < firstPage.width(); ++x) {
            const QColor c = firstPage.pixelColor(x, y);
            if (c.saturation() > 60 || c.value() < 90) ++coloured;  // the views' dark background, heat colours
        }
    QVERIFY2(coloured > firstPage.width() * firstPage.height() / 20, qPrintable(QString::number(coloured)));
    for (std::size_t page = 0; page < rowsOnPage.size(); ++page) {
        const int extra = imagesOnPage[page] - 2 * rowsOnPage[page];
        QVERIFY2(extra == 0 || extra == 1, qPrintable(QStringLiteral("page %1: %2 pictures for %3 rows")
                                                          .arg(page + 1).arg(imagesOnPage[page]).arg(rowsOnPage[page])));
    }

    // A missing folder is created (the export dialogs create folders); one that cannot be, because a file
    // holds its name: an error naming the report, nothing written.
    const QString created = dir.filePath(QStringLiteral("new/folder/report.html"));
    QVERIFY2(window_->exportReport(created, &error), qPrintable(error));
    QVERIFY(QFile::exists(created));
    QFile blocker(dir.filePath(QStringLiteral("blocker")));
    QVERIFY(blocker.open(QIODevice::WriteOnly));
    blocker.close();
    const QString bad = dir.filePath(QStringLiteral("blocker/report.html"));
    QVERIFY(!window_->exportReport(bad, &error));
    QVERIFY2(error.contains(QStringLiteral("blocker/report.html")), qPrintable(error));
    QVERIFY(!QFile::exists(bad));
}

void LodStudioTest::exportedPackMatchesTheCli() {
    QVERIFY(load(spotPath));
    lodforge::Preset preset = window_->preset();
    preset.name = "pack test";
    preset.levels = lodforge::lod_targets_from_ratios({0.4, 0.1});
    preset.exports.ply = true;
    window_->setPreset(preset);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString presetPath = dir.filePath(QStringLiteral("pack.json"));
    QVERIFY(window_->savePreset(presetPath));

    const QString guiPack = dir.filePath(QStringLiteral("gui_pack"));
    QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
    auto* action = window_->findChild<QAction*>(QStringLiteral("actionExportPack"));
    QVERIFY(action && action->isEnabled());
    window_->exportPack(guiPack);
    QVERIFY(window_->isBusy());
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.at(0).at(0).toString(), MainWindow::packJobName());
    QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));
    const QStringList files = window_->lastPackFiles();
    qInfo("pack: %s", qPrintable(files.join(QStringLiteral(", "))));
    QVERIFY(files.contains(QStringLiteral("pack.json")));
    QVERIFY(std::any_of(files.begin(), files.end(), [](const QString& f) { return f.endsWith(QStringLiteral(".glb")); }));
    QVERIFY(std::count_if(files.begin(), files.end(), [](const QString& f) { return f.endsWith(QStringLiteral(".ply")); }) == 3);

    // `lodforge pack` with the preset the studio saved writes the very same files.
    const QString cliPack = dir.filePath(QStringLiteral("cli_pack"));
    QProcess cli;
    cli.start(QStringLiteral(LODFORGE_CLI),
              {QStringLiteral("pack"), spotPath, QStringLiteral("--preset"), presetPath, QStringLiteral("-o"), cliPack});
    QVERIFY(cli.waitForFinished(120000));
    QVERIFY2(cli.exitCode() == 0, cli.readAllStandardError().constData());
    QStringList cliFiles;
    QDirIterator it(cliPack, QDir::Files, QDirIterator::Subdirectories);
    while (it.hasNext()) cliFiles << QDir(cliPack).relativeFilePath(it.next());
    QStringList sortedGui = files;
    sortedGui.sort();
    cliFiles.sort();
    QCOMPARE(cliFiles, sortedGui);
    for (const QString& f : files) {
        QFile a(QDir(guiPack).filePath(f)), b(QDir(cliPack).filePath(f));
        QVERIFY(a.open(QIODevice::ReadOnly) && b.open(QIODevice::ReadOnly));
        QVERIFY2(a.readAll() == b.readAll(), qPrintable(f + QStringLiteral(" differs between the studio and the CLI")));
    }

    // A preset the method cannot run is refused with a message saying so, and writes nothing.
    preset.method = lodforge::LodMethod::octree;
    preset.levels = {{lodforge::LodTarget::Kind::error, 0.01}};
    window_->setPreset(preset);
    finished.clear();
    const QString refused = dir.filePath(QStringLiteral("refused_pack"));
    window_->exportPack(refused);
    QVERIFY(finished.wait(60000));
    QVERIFY(!finished.at(0).at(1).toBool());
    qInfo("refused: %s", qPrintable(finished.at(0).at(2).toString()));
    QVERIFY(finished.at(0).at(2).toString().contains(QStringLiteral("error targets")));
    QVERIFY(!QFile::exists(refused));
}

void LodStudioTest::cancelStopsALongJobOnTheDragon() {
    QVERIFY2(QFile::exists(dragonPath), qPrintable(dragonPath));
    QVERIFY(load(dragonPath));
    QCOMPARE(window_->levelViews()->levels()[0].triangles, std::size_t(871414));
    const QImage before = frameOf(window_->view());

    // The GUI keeps its event loop while the chain runs: a timer ticks all along.
    int ticks = 0;
    QTimer ticker;
    connect(&ticker, &QTimer::timeout, this, [&ticks] { ++ticks; });
    ticker.start(20);
    QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
    window_->buildLodChain();
    QVERIFY(window_->isBusy());
    auto* cancel = window_->findChild<QPushButton*>(QStringLiteral("cancelLoad"));
    QVERIFY(cancel && cancel->isVisible());
    QTest::qWait(800);
    QVERIFY2(finished.isEmpty(), "the chain on the full dragon takes longer than this");
    QVERIFY2(ticks >= 10, qPrintable(QString::number(ticks)));
    QElapsedTimer sinceCancel;
    sinceCancel.start();
    QTest::mouseClick(cancel, Qt::LeftButton);
    QVERIFY(finished.wait(10000));
    const qint64 ms = sinceCancel.elapsed();
    qInfo("cancelled after %lld ms", ms);
    QCOMPARE(finished.at(0).at(0).toString(), MainWindow::lodChainJobName());
    QCOMPARE(finished.at(0).at(1).toBool(), false);
    QVERIFY2(finished.at(0).at(2).toString().isEmpty(), "cancelling is not an error");
    QVERIFY(!window_->isBusy());
    QVERIFY(!cancel->isVisible());
    QCOMPARE(window_->levelViews()->levelCount(), 1);
    QVERIFY(window_->logView()->toPlainText().contains(QStringLiteral("cancelled")));
    QVERIFY(differingFraction(before, frameOf(window_->view()), viewBackgroundColor()) < 0.01);

    // The pack export is cancelled the same way, and leaves no directory behind.
    QTemporaryDir dir;
    const QString pack = dir.filePath(QStringLiteral("dragon_pack"));
    finished.clear();
    window_->exportPack(pack);
    QVERIFY(window_->isBusy() && cancel->isVisible());
    QTest::qWait(500);
    QVERIFY2(finished.isEmpty(), "the dragon's pack takes longer than this");
    window_->cancelLoading();
    QVERIFY(finished.wait(20000));
    QCOMPARE(finished.at(0).at(0).toString(), MainWindow::packJobName());
    QCOMPARE(finished.at(0).at(1).toBool(), false);
    QVERIFY(finished.at(0).at(2).toString().isEmpty());
    QVERIFY(!QFile::exists(pack));
    QCOMPARE(QDir(dir.path()).entryList(QDir::NoDotAndDotDot | QDir::AllEntries), QStringList());
}

void LodStudioTest::shortcutsSettingsAndErrorDialogs() {
    QVERIFY(buildSpotChain({0.5, 0.1}));
    window_->activateWindow();
    window_->view()->setFocus();
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    // The View menu's keys, pressed over the view.
    QVERIFY(window_->levelViews()->arrangement() == lodforge::widgets::LevelViews::Arrangement::single);
    QTest::keyClick(window_->view(), Qt::Key_S);
    QVERIFY(window_->levelViews()->arrangement() == lodforge::widgets::LevelViews::Arrangement::sideBySide);
    QTest::keyClick(window_->view(), Qt::Key_E);
    QVERIFY(window_->viewOptions().edges);
    QTest::keyClick(window_->view(), Qt::Key_PageUp);
    QCOMPARE(window_->levelViews()->currentLevel(), 1);

    // Toggles and layout come back in the next session.
    window_->close();
    window_ = std::make_unique<MainWindow>();
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    QVERIFY(window_->viewOptions().edges);
    QVERIFY(window_->findChild<QAction*>(QStringLiteral("actionSideBySide"))->isChecked());
    QVERIFY(window_->levelViews()->arrangement() == lodforge::widgets::LevelViews::Arrangement::sideBySide);
    QSettings().clear();

    // Interactive: a failed job opens an error dialog naming the job and the reason.
    QVERIFY(load(spotPath));
    lodforge::Preset preset = window_->preset();
    preset.method = lodforge::LodMethod::cluster;
    preset.levels = {{lodforge::LodTarget::Kind::error, 0.01}};
    window_->setPreset(preset);
    window_->buildLodChain();
    QMessageBox* box = nullptr;
    QTRY_VERIFY_WITH_TIMEOUT((box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) != nullptr, 5000);
    QCOMPARE(box->icon(), QMessageBox::Critical);
    QVERIFY2(box->text().contains(MainWindow::lodChainJobName()), qPrintable(box->text()));
    QVERIFY2(box->informativeText().contains(QStringLiteral("error targets")), qPrintable(box->informativeText()));
    box->close();
    QTRY_VERIFY_WITH_TIMEOUT(QApplication::activeModalWidget() == nullptr, 5000);
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("LodForgeTests"));
    QApplication::setApplicationName(QStringLiteral("gui_lod_studio_test"));
    LodStudioTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "lod_studio_test.moc"
