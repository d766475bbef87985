// The octree cells overlay, in process under Xvfb: on the textured Spot sample, an out-of-core octree
// (300 triangles per node) is built and its cells drawn over the level; the lines carry the depth (or the
// triangle count) colours, the overlay goes away again without a trace, the octree's statistics reach the
// report, and a collapse chain (no structure) shows no cells and says why. Real pixels, tolerances.
#include "MainWindow.h"
#include "PixelStats.h"
#include "StudioSession.h"

#include "lodforge/pack/preset.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/ReportPanel.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

#include <QAction>
#include <QApplication>
#include <QFile>
#include <QHash>
#include <QPlainTextEdit>
#include <QSettings>
#include <QStatusBar>
#include <QTest>

#include <algorithm>
#include <memory>

using lodforge::studio::MainWindow;
using lodforge::testing::differingFraction;
using lodforge::testing::freshFrame;
using lodforge::testing::nearColor;
using lodforge::widgets::cellDepthColor;
using lodforge::widgets::viewBackgroundColor;
using lodforge::widgets::VtkView;

namespace {

const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");

// Pixels of `after` that differ from `before` (any channel by more than 24).
QList<QRgb> changedPixels(const QImage& before, const QImage& after) {
    QList<QRgb> out;
    for (int y = 0; y < after.height(); ++y) {
        const auto* a = reinterpret_cast<const QRgb*>(before.constScanLine(y));
        const auto* b = reinterpret_cast<const QRgb*>(after.constScanLine(y));
        for (int x = 0; x < after.width(); ++x)
            if (!nearColor(b[x], QColor::fromRgb(a[x]), 24)) out << b[x];
    }
    return out;
}

}  // namespace

class CellsOverlayTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase();
    void init();
    void cleanup();

    void octreeCellsDrawnByDepthAndByTriangles();
    void collapseChainShowsNoCells();

private:
    bool load(const QString& path);
    bool build(lodforge::LodMethod method, QString* message);
    QAction* action(const char* name) { return window_->findChild<QAction*>(QString::fromLatin1(name)); }

    std::unique_ptr<MainWindow> window_;
};

void CellsOverlayTest::initTestCase() {
    QVERIFY2(QFile::exists(spotPath), qPrintable(spotPath));
    QSettings().clear();
}

void CellsOverlayTest::init() {
    window_ = lodforge::testing::openStudioWindow();
    QVERIFY(window_);
}

void CellsOverlayTest::cleanup() {
    while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
    window_.reset();
}

bool CellsOverlayTest::load(const QString& path) { return lodforge::testing::loadInStudio(*window_, path); }

bool CellsOverlayTest::build(lodforge::LodMethod method, QString* message) {
    lodforge::Preset preset = window_->preset();
    preset.method = method;
    preset.levels = {{lodforge::LodTarget::Kind::ratio, 0.5}, {lodforge::LodTarget::Kind::ratio, 0.2}};
    preset.octree.max_triangles_per_node = 300;
    return lodforge::testing::buildInStudio(*window_, preset, message);
}

void CellsOverlayTest::octreeCellsDrawnByDepthAndByTriangles() {
    QVERIFY(load(spotPath));
    QString message;
    QVERIFY2(build(lodforge::LodMethod::octree, &message), qPrintable(message));
    auto* levels = window_->levelViews();
    QVERIFY2(levels->hasCells(), qPrintable(window_->logView()->toPlainText()));
    const auto info = lodforge::widgets::describe(*levels->levels()[1].cells);
    QVERIFY(info.isCells && info.lines > 12);
    qInfo("cells overlay: %zu lines", info.lines);

    // The octree's statistics are in the report (and the log).
    const QString summary = window_->reportPanel()->structureSummary();
    qInfo("%s", qPrintable(summary));
    QVERIFY2(summary.contains(QStringLiteral("nodes")) && summary.contains(QStringLiteral("leaves")) &&
                 summary.contains(QStringLiteral("depth")) && summary.contains(QStringLiteral("triangles per level")),
             qPrintable(summary));

    levels->setCurrentLevel(1);
    VtkView* view = window_->view();
    const QImage plain = freshFrame(view);
    QAction* cells = action("actionCells");
    QAction* byTriangles = action("actionCellsByTriangles");
    QVERIFY(cells && byTriangles && !cells->isChecked() && !byTriangles->isChecked());
    QCOMPARE(cells->shortcut(), QKeySequence(Qt::Key_O));

    cells->trigger();
    QVERIFY(view->overlayVisible());
    const QImage withCells = freshFrame(view);
    const double changed = differingFraction(plain, withCells, viewBackgroundColor());
    qInfo("the overlay changes %.1f%% of the drawn pixels", 100 * changed);
    QVERIFY2(changed > 0.05, qPrintable(QString::number(changed)));

    // The changed pixels carry the line colours of at least two depths.
    const QList<QRgb> lines = changedPixels(plain, withCells);
    int depthsSeen = 0;
    for (int depth = 0; depth < 8; ++depth) {
        const QColor c = cellDepthColor(depth);
        const auto n = std::count_if(lines.begin(), lines.end(), [&](QRgb p) { return nearColor(p, c, 12); });
        qInfo("depth %d: %lld pixels", depth, qlonglong(n));
        if (n > 50) ++depthsSeen;
    }
    QVERIFY2(depthsSeen >= 2, qPrintable(QString::number(depthsSeen)));

    // Coloured by triangle count: a different picture with at least two distinct line colours.
    byTriangles->trigger();
    const QImage byCount = freshFrame(view);
    QVERIFY(differingFraction(withCells, byCount, viewBackgroundColor()) > 0.01);
    QHash<int, int> bins;
    const QList<QRgb> countLines = changedPixels(plain, byCount);
    for (QRgb p : countLines) ++bins[((qRed(p) >> 4) << 8) | ((qGreen(p) >> 4) << 4) | (qBlue(p) >> 4)];
    int colours = 0;
    for (int n : bins) colours += n > std::max<qsizetype>(50, countLines.size() / 50) ? 1 : 0;
    qInfo("coloured by triangle count: %d colours", colours);
    QVERIFY2(colours >= 2, qPrintable(QString::number(colours)));
    byTriangles->trigger();

    // Off again: the frame is the plain one.
    cells->trigger();
    QVERIFY(!view->overlayVisible());
    const QImage off = freshFrame(view);
    const double restored = differingFraction(plain, off, viewBackgroundColor());
    qInfo("after turning it off %.2f%% differ", 100 * restored);
    QVERIFY2(restored < 0.005, qPrintable(QString::number(restored)));

    // Persisted like the other toggles.
    cells->trigger();
    window_->close();
    QVERIFY(QSettings().value(QStringLiteral("view/cells")).toBool());
    QSettings().clear();
}

void CellsOverlayTest::collapseChainShowsNoCells() {
    QVERIFY(load(spotPath));
    QString message;
    QVERIFY2(build(lodforge::LodMethod::collapse, &message), qPrintable(message));
    auto* levels = window_->levelViews();
    QVERIFY(!levels->hasCells());
    QVERIFY(window_->reportPanel()->structureSummary().isEmpty());
    VtkView* view = window_->view();
    const QImage plain = freshFrame(view);
    action("actionCells")->trigger();
    QVERIFY(action("actionCells")->isChecked());
    QVERIFY(!view->overlayVisible());
    const QImage after = freshFrame(view);
    QVERIFY(differingFraction(plain, after, viewBackgroundColor()) < 0.005);
    const QString status = window_->statusBar()->currentMessage();
    QVERIFY2(status.contains(QStringLiteral("Octree cells")), qPrintable(status));
    action("actionCells")->trigger();
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("LodForgeTests"));
    QApplication::setApplicationName(QStringLiteral("gui_cells_overlay_test"));
    CellsOverlayTest test;
    return QTest::qExec(&test, argc, argv);
}
#include "cells_overlay_test.moc"
