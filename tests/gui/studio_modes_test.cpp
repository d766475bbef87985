// View modes that compose, driven by the studio's keys under Xvfb: side by side (S), wireframe (W),
// split compare (X) and heat map (H) together. Split compare is honoured in every level's tile (the
// original's dense wireframe left of the split), and the heat map, drawn on each level's own surface,
// keeps side by side and the split on; its scale bar's labels stay inside small tiles. The Parameters
// dock, driven by keys, shows only the knobs the method and the mesh use and previews each target's
// triangle count. The UV checker's density follows Shift+U (finer) and Alt+U (coarser); Shift+H draws the
// original's silhouette over a level's heat map.
#include "PixelStats.h"
#include "StudioSession.h"

#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/ParametersPanel.h"

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QLabel>
#include <QDoubleSpinBox>
#include <QLocale>
#include <QTableWidget>
#include <QSettings>
#include <QSignalSpy>
#include <QTest>

#include <algorithm>
#include <cmath>
#include <memory>

using lodforge::studio::MainWindow;
using lodforge::testing::PixelStats;
using lodforge::widgets::LevelViews;
using lodforge::widgets::ParametersPanel;
using lodforge::widgets::VtkView;
using lodforge::widgets::viewBackgroundColor;

namespace {

const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");
const QString bunnyPath = QStringLiteral(LODFORGE_SHARED_DATA "/scan-bunny/bun_zipper.ply");

QRect leftHalf(const QImage& image) { return QRect(0, 0, image.width() / 2 - 4, image.height()); }

}  // namespace

class StudioModesTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase() { QSettings().clear(); }
    void cleanup() { QSettings().clear(); }

    void splitCompareAndHeatmapComposeWithSideBySide();
    void parametersShowWhatTheMethodAndMeshUse();
    void uvCheckerDensityFollowsTheKeys();
    void heatmapOutlineShowsTheOriginalsSilhouette();
    void automaticLevelsReplaceTheListAndBuild();
};

namespace {

// Changes between the checker's grey and tinted squares along every row of the model's pixels: the squares
// crossed. Pixels are told apart by chroma, which shading does not change much; the blend at an edge is
// skipped.
long checkerEdges(const QImage& image) {
    long edges = 0;
    for (int y = 0; y < image.height(); ++y) {
        int previous = -1;
        for (int x = 0; x < image.width(); ++x) {
            const QRgb p = image.pixel(x, y);
            if (lodforge::testing::nearColor(p, viewBackgroundColor(), 2)) {
                previous = -1;
                continue;
            }
            const int chroma = std::max({qRed(p), qGreen(p), qBlue(p)}) - std::min({qRed(p), qGreen(p), qBlue(p)});
            if (chroma > 25 && chroma < 60) continue;
            const int tinted = chroma >= 60 ? 1 : 0;
            if (previous >= 0 && tinted != previous) ++edges;
            previous = tinted;
        }
    }
    return edges;
}

}  // namespace

void StudioModesTest::splitCompareAndHeatmapComposeWithSideBySide() {
    auto window = lodforge::testing::openStudioWith(spotPath);
    QVERIFY(window);
    lodforge::Preset preset = window->preset();
    preset.levels = lodforge::lod_targets_from_ratios({0.3, 0.02});
    QString message;
    QVERIFY2(lodforge::testing::buildInStudio(*window, preset, &message), qPrintable(message));
    LevelViews* levels = window->levelViews();

    QTest::keyClick(window.get(), Qt::Key_S);
    QTest::keyClick(window.get(), Qt::Key_W);
    QCOMPARE(levels->arrangement(), LevelViews::Arrangement::sideBySide);
    QVERIFY(levels->viewOptions().wireframe);
    const QList<VtkView*> tiles = levels->tileViews();
    QCOMPARE(tiles.size(), 3);
    QTRY_VERIFY_WITH_TIMEOUT(tiles[2]->isVisible() && tiles[2]->frameCount() > 0, 10000);
    const QImage coarse = lodforge::testing::freshFrame(tiles[2]);
    const PixelStats before = lodforge::testing::measure(coarse, viewBackgroundColor(), leftHalf(coarse));

    // Split compare in side by side: the coarsest tile's left half now shows the original's wireframe,
    // far denser than the 2 % level's.
    QTest::keyClick(window.get(), Qt::Key_X);
    QVERIFY(window->findChild<QAction*>(QStringLiteral("actionCompare"))->isChecked());
    QVERIFY(tiles[0]->compareScene() == nullptr);
    QVERIFY(tiles[2]->compareScene() == levels->levels().front().scene);
    const QImage split = lodforge::testing::freshFrame(tiles[2]);
    const PixelStats after = lodforge::testing::measure(split, viewBackgroundColor(), leftHalf(split));
    qInfo("left half of LOD 2 in wireframe: %lld model pixels alone, %lld split with the original", before.modelPixels,
          after.modelPixels);
    QVERIFY2(after.modelPixels > before.modelPixels * 3 / 2,
             qPrintable(QStringLiteral("%1 vs %2").arg(after.modelPixels).arg(before.modelPixels)));

    // The heat map (computed on first use) keeps side by side and the split: each tile shows its
    // level's map, the original still left of the split.
    QTest::keyClick(window.get(), Qt::Key_W);
    QSignalSpy finished(window.get(), &MainWindow::jobFinished);
    QTest::keyClick(window.get(), Qt::Key_H);
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.at(0).at(0).toString(), MainWindow::heatmapJobName());
    QVERIFY(finished.at(0).at(1).toBool());
    QVERIFY(levels->heatmapVisible());
    QCOMPARE(levels->arrangement(), LevelViews::Arrangement::sideBySide);
    QVERIFY(window->findChild<QAction*>(QStringLiteral("actionSideBySide"))->isChecked());
    QVERIFY(window->findChild<QAction*>(QStringLiteral("actionCompare"))->isChecked());
    for (int i = 0; i < 3; ++i) {
        QVERIFY(tiles[i]->scene() == levels->heatmaps().scenes[std::size_t(i)]);
        // On the level's own surface (its outline is what the map shows), not on the original's.
        std::size_t triangles = 0;
        for (const auto& part : lodforge::widgets::describe(*tiles[i]->scene()).parts) triangles += part.triangles;
        QCOMPARE(triangles, levels->levels()[std::size_t(i)].triangles);
    }
    QVERIFY(tiles[2]->compareScene() == levels->levels().front().scene);
    const QImage heat = lodforge::testing::freshFrame(tiles[2]);
    const QRect right(heat.width() / 2 + 4, 0, heat.width() / 2 - 4, heat.height());
    const PixelStats heatRight = lodforge::testing::measure(heat, viewBackgroundColor(), right);
    qInfo("right half of LOD 2's heat map: %.2f chromatic", heatRight.chromaticFraction);
    QVERIFY(heatRight.modelPixels > 0);
    QVERIFY2(heatRight.chromaticFraction > 0.5, qPrintable(QString::number(heatRight.chromaticFraction)));

    // Scale-bar labels stay inside small tiles: only background in the tile's last columns, the bar and
    // its labels just left of them.
    window->resize(760, 560);
    QTRY_VERIFY_WITH_TIMEOUT(tiles[1]->width() < 320, 5000);
    const QImage small = lodforge::testing::freshFrame(tiles[1]);
    const QRect edge(small.width() - 3, 0, 3, small.height());
    const QRect strip(small.width() - 100, 0, 97, small.height());
    const PixelStats edgeStats = lodforge::testing::measure(small, viewBackgroundColor(), edge);
    const PixelStats stripStats = lodforge::testing::measure(small, viewBackgroundColor(), strip);
    qInfo("tile %dx%d: %lld pixels at the right edge, %lld in the bar's strip", small.width(), small.height(),
          edgeStats.modelPixels, stripStats.modelPixels);
    QCOMPARE(edgeStats.modelPixels, 0);
    QVERIFY(stripStats.modelPixels > 300);

    // Off again (X): the tiles lose the split, side by side and the heat map stay.
    QTest::keyClick(window.get(), Qt::Key_X);
    QVERIFY(tiles[2]->compareScene() == nullptr);
    QCOMPARE(levels->arrangement(), LevelViews::Arrangement::sideBySide);
    QVERIFY(levels->heatmapVisible());
}

void StudioModesTest::parametersShowWhatTheMethodAndMeshUse() {
    auto window = lodforge::testing::openStudioWith(bunnyPath);
    QVERIFY(window);
    const std::size_t triangles = window->model()->mesh.triangle_count();
    QVERIFY(!window->model()->mesh.has_colors() && !window->model()->mesh.has_texcoords());
    ParametersPanel* panel = window->parametersPanel();
    auto shown = [panel](const char* name) {
        QWidget* w = panel->findChild<QWidget*>(QString::fromLatin1(name));
        return w && w->isVisibleTo(panel);
    };
    auto* method = panel->findChild<QComboBox*>(QStringLiteral("method"));
    QVERIFY(method);
    // Chooses a method with the arrow keys, as from the keyboard.
    auto choose = [method](const char* name) {
        method->setFocus();
        const int target = method->findData(QString::fromLatin1(name));
        while (method->currentIndex() != target)
            QTest::keyClick(method, method->currentIndex() < target ? Qt::Key_Down : Qt::Key_Up);
    };

    // An untextured, uncoloured scan: no colour or UV weight, for any method.
    choose("collapse");
    QCOMPARE(window->preset().method, lodforge::LodMethod::collapse);
    QVERIFY(shown("normalWeight") && shown("lockBorder") && shown("placement"));
    QVERIFY(!shown("colorWeight") && !shown("uvWeight"));
    QVERIFY(!shown("mcResolution") && !shown("maxTrianglesPerNode") && !shown("structureBox"));
    choose("mcoctree");
    QCOMPARE(window->preset().method, lodforge::LodMethod::mcoctree);
    QVERIFY(shown("mcResolution") && !shown("maxTrianglesPerNode") && !shown("primitiveRestart"));
    QVERIFY(!shown("normalWeight") && !shown("lockBorder"));
    choose("octree");
    QVERIFY(shown("maxTrianglesPerNode") && shown("maxDepth") && shown("memoryMb") && !shown("mcResolution"));
    QVERIFY(shown("normalWeight") && !shown("lockBorder"));
    choose("lodstrips");
    QVERIFY(shown("primitiveRestart") && shown("lockBorder") && shown("exportLodstrips") && !shown("maxDepth"));
    QVERIFY(!shown("placement"));  // its strips replay one half-edge collapse prefix
    choose("collapse");
    QVERIFY(!shown("exportLodstrips"));
    // Placement: optimal by default (each level its own vertices), half-edge chosen from the keyboard.
    auto* placement = panel->findChild<QComboBox*>(QStringLiteral("placement"));
    QVERIFY(placement);
    QCOMPARE(window->preset().placement, lodforge::Placement::optimal);
    placement->setFocus();
    QTest::keyClick(placement, Qt::Key_Down);
    QCOMPARE(window->preset().placement, lodforge::Placement::half_edge);
    QTest::keyClick(placement, Qt::Key_Up);
    QCOMPARE(window->preset().placement, lodforge::Placement::optimal);

    // The targets preview their triangle counts, and follow a typed value.
    auto* levels = panel->findChild<QTableWidget*>(QStringLiteral("levels"));
    QVERIFY(levels && levels->columnCount() == 3);
    const auto& targets = window->preset().levels;
    for (int row = 0; row < int(targets.size()); ++row) {
        QCOMPARE(targets[std::size_t(row)].kind, lodforge::LodTarget::Kind::ratio);
        const auto expected = qulonglong(std::floor(targets[std::size_t(row)].value * double(triangles)));
        QCOMPARE(levels->item(row, 2)->text(), QLocale().toString(expected));
    }
    auto* value = qobject_cast<QDoubleSpinBox*>(levels->cellWidget(0, 1));
    QVERIFY(value);
    value->setFocus();
    value->selectAll();
    QTest::keyClicks(value, QStringLiteral("0.1"));
    QTest::keyClick(value, Qt::Key_Return);
    QCOMPARE(window->preset().levels.front().value, 0.1);
    QCOMPARE(levels->item(0, 2)->text(), QLocale().toString(qulonglong(std::floor(0.1 * double(triangles)))));

    // A textured mesh shows the UV weight again.
    QVERIFY(lodforge::testing::loadInStudio(*window, spotPath));
    QVERIFY(shown("uvWeight") && !shown("colorWeight"));
    QCOMPARE(levels->item(0, 2)->text(), QLocale().toString(qulonglong(std::floor(0.1 * 5856.0))));
}

void StudioModesTest::uvCheckerDensityFollowsTheKeys() {
    auto window = lodforge::testing::openStudioWith(spotPath);
    QVERIFY(window);
    VtkView* view = window->view();
    QTest::keyClick(window.get(), Qt::Key_U);
    QVERIFY(window->viewOptions().uvChecker);
    QCOMPARE(window->viewOptions().uvCheckerCells, 8);
    const long coarse = checkerEdges(lodforge::testing::freshFrame(view));
    // Shift+U twice: 32 squares per unit, four times as many squares across the same charts (at least twice
    // the edges: rows also end at the silhouette).
    QTest::keyClick(window.get(), Qt::Key_U, Qt::ShiftModifier);
    QTest::keyClick(window.get(), Qt::Key_U, Qt::ShiftModifier);
    QCOMPARE(window->viewOptions().uvCheckerCells, 32);
    const long fine = checkerEdges(lodforge::testing::freshFrame(view));
    qInfo("checker edges: %ld at 8 squares per unit, %ld at 32", coarse, fine);
    QVERIFY2(fine > 2 * coarse, qPrintable(QStringLiteral("%1 -> %2").arg(coarse).arg(fine)));
    // Alt+U at the coarsest stays there; the checker turned off keeps its density for next time.
    for (int i = 0; i < 8; ++i) QTest::keyClick(window.get(), Qt::Key_U, Qt::AltModifier);
    QCOMPARE(window->viewOptions().uvCheckerCells, lodforge::widgets::minUvCheckerCells);
    QTest::keyClick(window.get(), Qt::Key_U);
    QVERIFY(!window->viewOptions().uvChecker);
    QTest::keyClick(window.get(), Qt::Key_U, Qt::ShiftModifier);  // turns it back on, one step finer
    QVERIFY(window->viewOptions().uvChecker);
    QCOMPARE(window->viewOptions().uvCheckerCells, 2 * lodforge::widgets::minUvCheckerCells);
}

void StudioModesTest::heatmapOutlineShowsTheOriginalsSilhouette() {
    auto window = lodforge::testing::openStudioWith(spotPath);
    QVERIFY(window);
    lodforge::Preset preset = window->preset();
    preset.levels = lodforge::lod_targets_from_ratios({0.02});
    QString message;
    QVERIFY2(lodforge::testing::buildInStudio(*window, preset, &message), qPrintable(message));
    LevelViews* levels = window->levelViews();
    levels->setCurrentLevel(1);
    QSignalSpy finished(window.get(), &MainWindow::jobFinished);
    QTest::keyClick(window.get(), Qt::Key_H);
    QVERIFY(finished.wait(60000) && finished.at(0).at(1).toBool());
    VtkView* view = window->view();
    // White: on no heat map colour, nor the background.
    auto outlinePixels = [](const QImage& image) {
        long n = 0;
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x)
                if (lodforge::testing::nearColor(image.pixel(x, y), QColor(255, 255, 255), 12)) ++n;
        return n;
    };
    const long without = outlinePixels(lodforge::testing::freshFrame(view));
    QVERIFY(view->outlineScene() == nullptr);
    QTest::keyClick(window.get(), Qt::Key_H, Qt::ShiftModifier);
    QVERIFY(window->viewOptions().heatmapOutline);
    QVERIFY(view->outlineScene() == levels->levels().front().scene);
    const long with = outlinePixels(lodforge::testing::freshFrame(view));
    qInfo("white pixels: %ld without the outline, %ld with it", without, with);
    QVERIFY2(with > without + 500, qPrintable(QStringLiteral("%1 -> %2").arg(without).arg(with)));
    // The original itself (level 0) and the heat map off: no outline.
    levels->setCurrentLevel(0);
    QVERIFY(view->outlineScene() == nullptr);
    levels->setCurrentLevel(1);
    QTest::keyClick(window.get(), Qt::Key_H);
    QVERIFY(!levels->heatmapVisible());
    QVERIFY(view->outlineScene() == nullptr);
}

void StudioModesTest::automaticLevelsReplaceTheListAndBuild() {
    auto window = lodforge::testing::openStudioWith(spotPath);
    QVERIFY(window);
    ParametersPanel* panel = window->parametersPanel();
    auto* box = panel->findChild<QCheckBox*>(QStringLiteral("autoLevels"));
    auto* table = panel->findChild<QTableWidget*>(QStringLiteral("levels"));
    auto* note = panel->findChild<QLabel*>(QStringLiteral("autoLevelsNote"));
    QVERIFY(box && table && note);
    QVERIFY(box->isVisibleTo(panel) && !box->isChecked() && table->isEnabled() && !note->isVisibleTo(panel));
    QTest::mouseClick(box, Qt::LeftButton, {}, QPoint(8, box->height() / 2));
    QVERIFY(window->preset().auto_levels);
    QVERIFY(!table->isEnabled());
    QVERIFY2(note->isVisibleTo(panel) && note->text().contains(QStringLiteral("halves")), qPrintable(note->text()));

    // Ctrl+B builds the automatic chain: every level at least halves the one before.
    QSignalSpy finished(window.get(), &MainWindow::jobFinished);
    QTest::keyClick(window.get(), Qt::Key_B, Qt::ControlModifier);
    QVERIFY(finished.wait(120000));
    QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));
    const auto& built = window->levelViews()->levels();
    QVERIFY(built.size() >= 3);
    for (std::size_t k = 1; k < built.size(); ++k)
        QVERIFY2(2 * built[k].triangles <= built[k - 1].triangles,
                 qPrintable(QStringLiteral("LOD %1: %2 after %3").arg(k).arg(built[k].triangles).arg(built[k - 1].triangles)));
    QVERIFY(lodforge::testing::measuredInStudio(*window));

    // Undo gives the list back; the box shows only for the method that can choose levels.
    QTest::keyClick(window.get(), Qt::Key_Z, Qt::ControlModifier);
    QVERIFY(!window->preset().auto_levels && !box->isChecked() && table->isEnabled());
    auto* method = panel->findChild<QComboBox*>(QStringLiteral("method"));
    method->setFocus();
    QTest::keyClick(method, Qt::Key_Down);
    QVERIFY(window->preset().method != lodforge::LodMethod::collapse);
    QVERIFY(!box->isVisibleTo(panel));
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("LodForgeTests"));
    QApplication::setApplicationName(QStringLiteral("gui_studio_modes_test"));
    StudioModesTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_modes_test.moc"
