// Measuring that never blocks, driven by real key and mouse events under Xvfb: a built chain's levels
// show before their errors are measured ("error measuring…"), the errors fill in level by level in
// order (labels and report), the window goes on answering keys while the dragon's levels are measured,
// the status bar's Cancel stops a measure (the levels stay, "not measured" or with the measure they
// had), and LOD > Measure at full
// precision gives exactly what compare() gives with its defaults (as `lodforge compare`).
#include "StudioSession.h"

#include "lodforge/metrics/metrics.h"
#include "lodforge/pack/switch_points.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/ReportPanel.h"

#include <QAction>
#include <QApplication>
#include <QElapsedTimer>
#include <QFile>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QTableWidget>
#include <QTest>
#include <QTimer>

#include <algorithm>
#include <cmath>
#include <memory>

using lodforge::studio::MainWindow;
using lodforge::widgets::LevelViews;
using lodforge::widgets::Measured;

namespace {

const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");
const QString dragonPath = QStringLiteral(LODFORGE_SHARED_DATA "/scan-dragon/dragon_vrip.ply");

}  // namespace

class StudioMeasureTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase() { QSettings().clear(); }
    void init() {
        window_ = lodforge::testing::openStudioWindow();
        QVERIFY(window_);
        window_->activateWindow();
        QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    }
    void cleanup() {
        while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
        window_.reset();
        QSettings().clear();
    }

    void levelsShowFirstAndTheirErrorsFillInInOrder();
    void fullPrecisionMeasureIsCompareWithItsDefaults();
    void dragonStaysResponsiveWhileMeasuredAndCancels();

private:
    std::unique_ptr<MainWindow> window_;
};

void StudioMeasureTest::levelsShowFirstAndTheirErrorsFillInInOrder() {
    QVERIFY(lodforge::testing::loadInStudio(*window_, spotPath));
    lodforge::Preset preset = window_->preset();
    preset.levels = lodforge::lod_targets_from_ratios({0.5, 0.2, 0.05});
    window_->setPreset(preset);
    LevelViews* levels = window_->levelViews();

    // What the window shows when the chain's job reports its end: every level, none measured yet.
    int levelsAtEnd = 0, measuredAtEnd = -1;
    QString labelAtEnd;
    QSignalSpy measured(window_.get(), &MainWindow::levelMeasured);
    QSignalSpy measureEnd(window_.get(), &MainWindow::measuringFinished);
    QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
    connect(window_.get(), &MainWindow::jobFinished, this, [&](const QString& name, bool ok) {
        if (name != MainWindow::lodChainJobName() || !ok) return;
        levelsAtEnd = levels->levelCount();
        measuredAtEnd = int(measured.count());
        labelAtEnd = levels->singleLabel()->text();
    });
    QTest::keyClick(window_.get(), Qt::Key_B, Qt::ControlModifier);
    QVERIFY(finished.wait(60000));
    QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));
    QCOMPARE(levelsAtEnd, 4);
    QCOMPARE(measuredAtEnd, 0);
    QVERIFY2(labelAtEnd.contains(QStringLiteral("error measuring…")), qPrintable(labelAtEnd));

    QVERIFY(measureEnd.wait(60000));
    QCOMPARE(measureEnd.at(0).at(0).toBool(), true);
    QVERIFY(!window_->isMeasuring());
    QCOMPARE(int(measured.count()), 3);
    for (int i = 0; i < 3; ++i) QCOMPARE(measured.at(i).at(0).toInt(), i + 1);

    // Labels, level data and report rows carry the quick measure, marked as an estimate.
    const auto& data = levels->levels();
    const auto& rows = window_->reportPanel()->rows();
    QVERIFY(window_->reportPanel()->allMeasured());
    for (int k = 1; k < 4; ++k) {
        QCOMPARE(data[std::size_t(k)].measured, Measured::sampled);
        QVERIFY(data[std::size_t(k)].errorRelative > 0);
        QVERIFY(data[std::size_t(k)].errorRelative >= data[std::size_t(k - 1)].errorRelative);
        QCOMPARE(rows[std::size_t(k)].errorRelative, data[std::size_t(k)].errorRelative);
        const QString text = levels->levelLabelText(k);
        QVERIFY2(text.contains(QStringLiteral("error ≈ ")), qPrintable(text));
        const QString cell = window_->reportPanel()->table()->item(k, 4)->text();
        QVERIFY2(cell.startsWith(QStringLiteral("≈ ")), qPrintable(cell));
    }
    QVERIFY2(levels->singleLabel()->text().contains(QStringLiteral("error ≈ ")), qPrintable(levels->singleLabel()->text()));

    // Built again and the measure cancelled from the status bar as the levels appear: they stay, and
    // say their error is not measured.
    auto* cancel = window_->findChild<QPushButton*>(QStringLiteral("cancelLoad"));
    QVERIFY(cancel);
    bool clicked = false;
    connect(window_.get(), &MainWindow::jobFinished, this, [&](const QString& name, bool ok) {
        if (name != MainWindow::lodChainJobName() || !ok || clicked) return;
        clicked = cancel->isVisible() && cancel->isEnabled();
        QTest::mouseClick(cancel, Qt::LeftButton);
    });
    measured.clear();
    measureEnd.clear();
    finished.clear();
    QTest::keyClick(window_.get(), Qt::Key_B, Qt::ControlModifier);
    QVERIFY(finished.wait(60000));
    QVERIFY(clicked);
    QVERIFY(measureEnd.wait(60000));
    QCOMPARE(measureEnd.at(0).at(0).toBool(), false);
    QCOMPARE(int(measured.count()), 0);
    QCOMPARE(levels->levelCount(), 4);
    QVERIFY(!cancel->isVisible());
    QVERIFY2(levels->singleLabel()->text().contains(QStringLiteral("error not measured")),
             qPrintable(levels->singleLabel()->text()));
    QVERIFY(!window_->reportPanel()->allMeasured());
    QCOMPARE(window_->reportPanel()->table()->item(3, 4)->text(), QStringLiteral("…"));
}

void StudioMeasureTest::fullPrecisionMeasureIsCompareWithItsDefaults() {
    QVERIFY(lodforge::testing::loadInStudio(*window_, spotPath));
    lodforge::Preset preset = window_->preset();
    preset.levels = lodforge::lod_targets_from_ratios({0.3, 0.05});
    preset.switching.pixels = 2;
    preset.switching.fov_deg = 45;
    QString message;
    QVERIFY2(lodforge::testing::buildInStudio(*window_, preset, &message), qPrintable(message));
    auto* full = window_->findChild<QAction*>(QStringLiteral("actionMeasureFull"));
    QVERIFY(full && full->isEnabled());
    QSignalSpy measureEnd(window_.get(), &MainWindow::measuringFinished);
    full->trigger();
    QVERIFY(window_->isMeasuring());
    QVERIFY(measureEnd.wait(60000));
    QCOMPARE(measureEnd.at(0).at(0).toBool(), true);
    const auto& data = window_->levelViews()->levels();
    for (std::size_t k = 1; k < data.size(); ++k) {
        QCOMPARE(data[k].measured, Measured::full);
        const lodforge::DistanceResult expected = lodforge::compare(*data[0].mesh, *data[k].mesh);
        QCOMPARE(data[k].error, expected.hausdorff);
        QCOMPARE(data[k].errorRelative, expected.hausdorff_relative);
        const QString text = window_->levelViews()->levelLabelText(int(k));
        QVERIFY2(text.contains(QStringLiteral(" · error ")) && !text.contains(QStringLiteral("≈")), qPrintable(text));
    }
    // Each level says where it takes over on the preset's switch screen: the sphere's diameter in pixels
    // and the camera distance, as pack.json's switch points give them (two pixels, 45 degrees).
    std::vector<double> errors;
    for (const auto& l : data) errors.push_back(l.errorRelative);
    const lodforge::SwitchPoints s = lodforge::switch_points(errors, data[0].mesh->bounds(), preset.switching);
    QCOMPARE(s.levels.size(), data.size());
    for (std::size_t k = 1; k < data.size(); ++k) {
        const double pixels = 2 / data[k].errorRelative;  // level k's error is 2 px at this diameter
        QVERIFY(std::abs(s.levels[k - 1].screen_size * 1080 - pixels) < 1e-6 * pixels);
        const QString expected = QStringLiteral(" · takes over at %1 px (distance %2)")
                                     .arg(pixels, 0, 'f', 0)
                                     .arg(QString::number(s.levels[k - 1].godot.range_end, 'g', 3));
        const QString text = window_->levelViews()->levelLabelText(int(k));
        QVERIFY2(text.contains(expected), qPrintable(text + QStringLiteral(" lacks") + expected));
    }
    QVERIFY(!window_->levelViews()->levelLabelText(0).contains(QStringLiteral("takes over")));
    window_->levelViews()->setCurrentLevel(1);
    QVERIFY2(window_->levelViews()->singleLabel()->text().contains(QStringLiteral("takes over at")),
             qPrintable(window_->levelViews()->singleLabel()->text()));
}

void StudioMeasureTest::dragonStaysResponsiveWhileMeasuredAndCancels() {
    QVERIFY2(QFile::exists(dragonPath), qPrintable(dragonPath));
    QVERIFY(lodforge::testing::loadInStudio(*window_, dragonPath));
    lodforge::Preset preset = window_->preset();
    preset.method = lodforge::LodMethod::octree;
    preset.levels = lodforge::lod_targets_from_ratios({0.5, 0.25, 0.1, 0.03, 0.01});
    window_->setPreset(preset);
    LevelViews* levels = window_->levelViews();

    // First measure to completion, to see the chain whole and time it (printed, never asserted).
    QElapsedTimer clock;
    qint64 shownMs = 0;
    QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
    QSignalSpy measureEnd(window_.get(), &MainWindow::measuringFinished);
    QSignalSpy measured(window_.get(), &MainWindow::levelMeasured);
    connect(window_.get(), &MainWindow::jobFinished, this, [&] { shownMs = clock.elapsed(); });
    clock.start();
    QTest::keyClick(window_.get(), Qt::Key_B, Qt::ControlModifier);
    QVERIFY(finished.wait(120000));
    QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));
    QCOMPARE(levels->levelCount(), 6);
    QVERIFY(window_->isMeasuring());

    // The window answers while the levels are measured: Page Up moves the slider to the level above,
    // a timer ticks, the status bar shows the measure's progress with Cancel.
    int ticks = 0;
    QTimer ticker;
    connect(&ticker, &QTimer::timeout, this, [&ticks] { ++ticks; });
    ticker.start(20);
    auto* bar = window_->findChild<QProgressBar*>();
    auto* cancel = window_->findChild<QPushButton*>(QStringLiteral("cancelLoad"));
    QVERIFY(bar && cancel);
    QVERIFY(cancel->isVisible() && cancel->isEnabled());
    QCOMPARE(levels->currentLevel(), 5);
    window_->levelViews()->singleView()->setFocus();
    QTest::keyClick(window_.get(), Qt::Key_PageUp);
    QCOMPARE(levels->currentLevel(), 4);
    QVERIFY(measureEnd.wait(120000));
    const qint64 measuredMs = clock.elapsed();
    qInfo("dragon, octree, 5 levels: shown after %lld ms, all measured after %lld ms (%d ticks meanwhile)", shownMs,
          measuredMs, ticks);
    QCOMPARE(measureEnd.at(0).at(0).toBool(), true);
    QCOMPARE(int(measured.count()), 5);
    // The event loop turned while the levels were measured (drawing the dragon's levels on llvmpipe
    // takes the GUI thread seconds, so no rate is asked).
    QVERIFY2(ticks >= 1, qPrintable(QString::number(ticks)));
    QVERIFY(!cancel->isVisible());
    for (int k = 1; k <= 5; ++k) QVERIFY(levels->levels()[std::size_t(k)].measured == Measured::sampled);

    // Measured again at full precision and cancelled from the status bar right away: no level changes,
    // the quick measure stays.
    measureEnd.clear();
    measured.clear();
    window_->measureLevels(true);
    QVERIFY(cancel->isVisible());
    QTest::mouseClick(cancel, Qt::LeftButton);
    QVERIFY(measureEnd.wait(120000));
    QCOMPARE(measureEnd.at(0).at(0).toBool(), false);
    QCOMPARE(int(measured.count()), 0);
    QCOMPARE(levels->levelCount(), 6);
    QVERIFY(!window_->isMeasuring() && !cancel->isVisible());
    const QString text = levels->singleLabel()->text();
    QVERIFY2(text.contains(QStringLiteral("error ≈ ")), qPrintable(text));  // the quick measure stays
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("LodForgeTests"));
    QApplication::setApplicationName(QStringLiteral("gui_studio_measure_test"));
    StudioMeasureTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_measure_test.moc"
