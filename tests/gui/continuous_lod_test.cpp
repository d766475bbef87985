// The continuous LOD slider, in process under Xvfb: Spot's LODStrips levels are built, the slider moves
// the LODStrips runtime from full detail down to factor 0.2 and the single view draws the runtime's strips
// (its label's count is the runtime's own), the strips can be coloured one by one and uncoloured again
// without a trace, and a collapse chain has no slider. Real pixels, tolerances.
#include "MainWindow.h"
#include "PixelStats.h"
#include "StudioSession.h"

#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/pack/preset.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LodLevels.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

#include <QApplication>
#include <QCheckBox>
#include <QFile>
#include <QLabel>
#include <QPlainTextEdit>
#include <QSettings>
#include <QSlider>

#include <memory>
#include <set>

using lodforge::studio::MainWindow;
using lodforge::testing::differingFraction;
using lodforge::testing::freshFrame;
using lodforge::testing::nearColor;
using lodforge::widgets::viewBackgroundColor;
using lodforge::widgets::VtkView;

namespace {

const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");

// "1,234 triangles" -> 1234 (whatever the locale's group separator).
long long countIn(const QString& text) {
    QString digits;
    for (QChar c : text) {
        if (c.isDigit()) digits += c;
        else if (c.isSpace() && !digits.isEmpty()) break;
    }
    return digits.isEmpty() ? -1 : digits.toLongLong();
}

// Distinct hues among the clearly coloured model pixels: 5-degree bins holding at least 0.2 % of them.
int distinctHues(const QImage& image) {
    int bins[72] = {};
    int total = 0;
    for (int y = 0; y < image.height(); ++y) {
        const auto* line = reinterpret_cast<const QRgb*>(image.constScanLine(y));
        for (int x = 0; x < image.width(); ++x) {
            const QRgb p = line[x];
            if (nearColor(p, viewBackgroundColor(), 2)) continue;
            const QColor c = QColor::fromRgb(p);
            if (c.hsvSaturation() < 80 || c.value() < 60 || c.hsvHue() < 0) continue;
            ++bins[c.hsvHue() / 5];
            ++total;
        }
    }
    int hues = 0;
    for (int n : bins) hues += total > 0 && n * 500 >= total ? 1 : 0;
    return hues;
}

}  // namespace

class ContinuousLodTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase();
    void init();
    void cleanup();

    void sliderMovesTheRuntimeAndColoursStrips();
    void collapseChainHasNoSlider();

private:
    bool load(const QString& path);
    bool build(lodforge::LodMethod method, QString* message);

    std::unique_ptr<MainWindow> window_;
};

void ContinuousLodTest::initTestCase() {
    QVERIFY2(QFile::exists(spotPath), qPrintable(spotPath));
    QSettings().clear();
}

void ContinuousLodTest::init() {
    window_ = lodforge::testing::openStudioWindow();
    QVERIFY(window_);
}

void ContinuousLodTest::cleanup() {
    while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
    window_.reset();
}

bool ContinuousLodTest::load(const QString& path) { return lodforge::testing::loadInStudio(*window_, path); }

bool ContinuousLodTest::build(lodforge::LodMethod method, QString* message) {
    lodforge::Preset preset = window_->preset();
    preset.method = method;
    preset.levels = {{lodforge::LodTarget::Kind::ratio, 0.5}, {lodforge::LodTarget::Kind::ratio, 0.05}};
    return lodforge::testing::buildInStudio(*window_, preset, message);
}

void ContinuousLodTest::sliderMovesTheRuntimeAndColoursStrips() {
    QVERIFY(load(spotPath));
    QString message;
    QVERIFY2(build(lodforge::LodMethod::lodstrips, &message), qPrintable(message));
    auto* levels = window_->levelViews();
    QVERIFY2(levels->hasContinuousLod(), qPrintable(window_->logView()->toPlainText()));
    QSlider* slider = levels->continuousSlider();
    QLabel* label = levels->continuousLabel();
    QVERIFY(slider->isVisible() && slider->minimum() == 0 && slider->maximum() == 1000);

    // A runtime of our own on the same bytes: the reference for every count the label shows.
    const auto& data = levels->levels().front().continuous;
    QVERIFY(data);
    lodstrips::LodStrips reference;
    std::string error;
    QVERIFY2(reference.load_memory(data->lodstripsFile.data(), data->lodstripsFile.size(), &error), error.c_str());

    VtkView* view = window_->view();
    QVERIFY(!levels->continuousActive() && slider->value() == 1000);
    levels->setContinuousFactor(1.0);  // the slider starts at 1: setting it again would signal nothing
    long long previous = -1;
    QImage full;
    for (int step : {1000, 800, 600, 400, 200}) {
        slider->setValue(step);
        QVERIFY(levels->continuousActive());
        reference.go_to_lod(step / 1000.0);
        const long long shown = countIn(label->text());
        qInfo("factor %.1f: %s", step / 1000.0, qPrintable(label->text()));
        QCOMPARE(shown, static_cast<long long>(reference.triangle_count()));
        QCOMPARE(static_cast<std::size_t>(shown), levels->continuousTriangles());
        // The view draws exactly the runtime's triangles.
        std::size_t drawn = 0;
        for (const auto& part : lodforge::widgets::describe(*view->scene()).parts) drawn += part.triangles;
        QCOMPARE(drawn, reference.triangle_count());
        if (step == 1000) {
            QCOMPARE(static_cast<std::size_t>(shown), levels->levels().front().triangles);
            full = freshFrame(view);
        } else {
            QVERIFY2(shown < previous, qPrintable(label->text()));
        }
        previous = shown;
    }
    QVERIFY(levels->singleLabel()->text().contains(QStringLiteral("Continuous")));
    QVERIFY(levels->continuousPatchesTriangles());  // Spot has one material: only the triangles change
    const QImage coarse = freshFrame(view);
    const double changed = differingFraction(full, coarse, viewBackgroundColor());
    qInfo("factor 1 -> 0.2 changes %.1f%% of the drawn pixels", 100 * changed);
    QVERIFY2(changed > 0.02, qPrintable(QString::number(changed)));

    // Strips coloured: many hues where the textured cow has few; off again restores the frame.
    QCheckBox* colours = levels->stripColorsBox();
    QVERIFY(colours->isVisible());
    colours->click();
    QVERIFY(levels->stripColors());
    const QImage striped = freshFrame(view);
    const int hues = distinctHues(striped), plainHues = distinctHues(coarse);
    qInfo("hues: %d coloured, %d textured", hues, plainHues);
    QVERIFY2(hues >= 20 && hues > plainHues, qPrintable(QStringLiteral("%1 / %2").arg(hues).arg(plainHues)));
    QCOMPARE(countIn(label->text()), previous);
    colours->click();
    const QImage off = freshFrame(view);
    const double restored = differingFraction(coarse, off, viewBackgroundColor());
    qInfo("after colouring off %.2f%% differ", 100 * restored);
    QVERIFY2(restored < 0.005, qPrintable(QString::number(restored)));

    // The heat map shows the stored level's error field; switched off, the continuous view is back.
    levels->setHeatmaps(lodforge::widgets::computeHeatmaps(levels->levels()));
    levels->setHeatmapVisible(true);
    QVERIFY(levels->heatmapVisible() && view->scene() == levels->heatmaps().scenes[std::size_t(levels->currentLevel())]);
    QVERIFY(!levels->singleLabel()->text().contains(QStringLiteral("Continuous")));
    levels->setHeatmapVisible(false);
    QVERIFY(levels->singleLabel()->text().contains(QStringLiteral("Continuous")));
    QVERIFY(differingFraction(coarse, freshFrame(view), viewBackgroundColor()) < 0.005);

    // A stored level leaves the continuous view.
    levels->setCurrentLevel(1);
    QVERIFY(!levels->continuousActive());
    QVERIFY(levels->singleLabel()->text().startsWith(QStringLiteral("LOD 1")));
}

void ContinuousLodTest::collapseChainHasNoSlider() {
    QVERIFY(load(spotPath));
    QString message;
    QVERIFY2(build(lodforge::LodMethod::collapse, &message), qPrintable(message));
    auto* levels = window_->levelViews();
    QVERIFY(!levels->hasContinuousLod());
    QVERIFY(!levels->continuousSlider()->isVisible());
    levels->setContinuousFactor(0.2);  // ignored without a runtime
    QVERIFY(!levels->continuousActive());
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("LodForgeTests"));
    QApplication::setApplicationName(QStringLiteral("gui_continuous_lod_test"));
    ContinuousLodTest test;
    return QTest::qExec(&test, argc, argv);
}
#include "continuous_lod_test.moc"
