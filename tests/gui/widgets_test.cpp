// lodforge::widgets on its own: scene building from meshes made in code, the 3D view's pixels (colours,
// texture orientation, toggles), the background loader and the progress bridge.
#include "PixelStats.h"

#include "lodforge/error.h"
#include "lodforge/io/image_decode.h"
#include "lodforge/mesh.h"
#include "lodforge/widgets/Job.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/LodLevels.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/ParametersPanel.h"
#include "lodforge/pack/preset_library.h"
#include "lodforge/widgets/QueuedProgress.h"
#include "lodforge/widgets/StatsPanel.h"
#include "lodforge/widgets/VtkView.h"

#include <QApplication>
#include <QComboBox>
#include <QTableWidget>
#include <QMouseEvent>
#include <QWheelEvent>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <QThread>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

using namespace lodforge;
using lodforge::testing::measure;
using lodforge::testing::PixelStats;
using lodforge::widgets::ViewOptions;
using lodforge::widgets::viewBackgroundColor;

namespace {

const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");

// A unit square in the XY plane, two triangles, uv (0,0) at the bottom-left corner.
Mesh square() {
    Mesh mesh;
    mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    mesh.texcoords = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

// 2x2 pixels: top row red, bottom row blue (first row = top of the image).
std::shared_ptr<const Image> redOverBlue() {
    auto image = std::make_shared<Image>();
    image->width = 2;
    image->height = 2;
    image->rgba = {255, 0, 0, 255, 255, 0, 0, 255, 0, 0, 255, 255, 0, 0, 255, 255};
    return image;
}

// Mean colour of the model pixels in a horizontal band of the view [from, to) (fractions of the height).
QColor bandColor(const QImage& image, double from, double to) {
    const int top = int(image.height() * from), bottom = int(image.height() * to);
    double r = 0, g = 0, b = 0;
    qint64 n = 0;
    for (int y = top; y < bottom; ++y) {
        for (int x = 0; x < image.width(); ++x) {
            const QRgb p = image.pixel(x, y);
            if (lodforge::testing::nearColor(p, viewBackgroundColor(), 2)) continue;
            r += qRed(p);
            g += qGreen(p);
            b += qBlue(p);
            ++n;
        }
    }
    if (n == 0) return {};
    return QColor(int(r / double(n)), int(g / double(n)), int(b / double(n)));
}

}  // namespace

class WidgetsTest : public QObject {
    Q_OBJECT

private slots:
    void sceneOfPlainMeshIsOnePartWithComputedNormals();
    void scenePartPerMaterialWithItsTexture();
    void sceneWithoutFaceMaterialsUsesFirstTexturedMaterial();
    void sceneRejectsBadIndices();
    void viewShowsVertexColorsAndNeutralMaterial();
    void viewTextureIsUprightAndTogglable();
    void viewWireframeChangesPixels();
    void viewMouseRotatesAndZooms();
    void loadJobLoadsInBackground();
    void loadJobReportsErrorsWithTheFile();
    void loadJobCancelled();
    void queuedProgressDeliversOnReceiverThread();
    void statsPanelShowsInfo();
    void jobTurnsExceptionsIntoResults();
    void jobCancelledFromTheGuiThread();
    void lodLevelsRefuseWhatTheyCannotBuild();
    void parametersPanelStartsFromAShippedPreset();
    void scalarSceneShowsValuesAndRange();
};

void WidgetsTest::sceneOfPlainMeshIsOnePartWithComputedNormals() {
    Mesh mesh = square();
    mesh.texcoords.clear();
    const auto scene = widgets::buildMeshScene(mesh, {});
    const widgets::MeshSceneInfo info = widgets::describe(*scene);
    QCOMPARE(info.parts.size(), std::size_t(1));
    QCOMPARE(info.parts[0].points, std::size_t(4));
    QCOMPARE(info.parts[0].triangles, std::size_t(2));
    QVERIFY(!info.parts[0].textured);
    QVERIFY(info.computedNormals);
    QVERIFY(!info.hasColors);
}

void WidgetsTest::scenePartPerMaterialWithItsTexture() {
    Mesh mesh = square();
    mesh.normals.assign(4, Vec3f{0, 0, 1});
    mesh.colors.assign(4, Vec4f{1, 0, 0, 1});
    mesh.materials.resize(2);
    mesh.materials[0].name = "plain";
    mesh.materials[1].name = "painted";
    mesh.materials[1].base_color_texture.path = "paint.png";
    mesh.face_materials = {0, 1};
    const auto scene = widgets::buildMeshScene(mesh, {nullptr, redOverBlue()});
    const widgets::MeshSceneInfo info = widgets::describe(*scene);
    QCOMPARE(info.parts.size(), std::size_t(2));
    QCOMPARE(info.parts[0].material, std::string("plain"));
    QCOMPARE(info.parts[0].triangles, std::size_t(1));
    QCOMPARE(info.parts[0].points, std::size_t(3));  // only the vertices its triangle uses
    QVERIFY(!info.parts[0].textured);
    QCOMPARE(info.parts[1].material, std::string("painted"));
    QVERIFY(info.parts[1].textured);
    QCOMPARE(info.parts[1].textureWidth, 2);
    QCOMPARE(info.parts[1].textureHeight, 2);
    QVERIFY(!info.computedNormals);
    QVERIFY(info.hasColors);
}

void WidgetsTest::sceneWithoutFaceMaterialsUsesFirstTexturedMaterial() {
    Mesh mesh = square();
    mesh.materials.resize(3);
    mesh.materials[2].name = "textured";
    const auto scene = widgets::buildMeshScene(mesh, {nullptr, nullptr, redOverBlue()});
    const widgets::MeshSceneInfo info = widgets::describe(*scene);
    QCOMPARE(info.parts.size(), std::size_t(1));
    QCOMPARE(info.parts[0].material, std::string("textured"));
    QVERIFY(info.parts[0].textured);
    QCOMPARE(info.parts[0].points, std::size_t(4));
}

void WidgetsTest::sceneRejectsBadIndices() {
    Mesh mesh = square();
    mesh.indices[4] = 7;
    QVERIFY_THROWS_EXCEPTION(lodforge::Error, widgets::buildMeshScene(mesh, {}));
    Mesh materials = square();
    materials.materials.resize(1);
    materials.face_materials = {0, 3};
    QVERIFY_THROWS_EXCEPTION(lodforge::Error, widgets::buildMeshScene(materials, {}));
}

void WidgetsTest::viewShowsVertexColorsAndNeutralMaterial() {
    Mesh mesh = square();
    mesh.texcoords.clear();
    mesh.colors = {{0.1f, 0.9f, 0.1f, 1}, {0.1f, 0.9f, 0.1f, 1}, {0.1f, 0.9f, 0.1f, 1}, {0.1f, 0.9f, 0.1f, 1}};
    widgets::VtkView view;
    view.resize(400, 300);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setScene(widgets::buildMeshScene(mesh, {}));

    const QImage colored = view.grabFramebuffer();
    const PixelStats s = measure(colored, viewBackgroundColor(), colored.rect());
    QVERIFY2(s.modelFraction() > 0.2, qPrintable(QString::number(s.modelFraction())));
    const QColor center = colored.pixelColor(colored.rect().center());
    QVERIFY2(center.green() > 120 && center.green() > 2 * center.red() && center.green() > 2 * center.blue(),
             qPrintable(center.name()));

    ViewOptions options;
    options.vertexColors = false;
    view.setViewOptions(options);
    const QColor grey = view.grabFramebuffer().pixelColor(colored.rect().center());
    QVERIFY2(std::abs(grey.red() - grey.green()) < 12 && grey.green() > 100, qPrintable(grey.name()));
    QVERIFY(view.frameCount() >= 2);
}

void WidgetsTest::viewTextureIsUprightAndTogglable() {
    Mesh mesh = square();
    mesh.materials.resize(1);
    mesh.materials[0].base_color_texture.path = "red_over_blue.png";
    widgets::VtkView view;
    view.resize(400, 400);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setScene(widgets::buildMeshScene(mesh, {redOverBlue()}));

    // The texture's top row (red) is sampled at v = 1, the top of the square; blue at the bottom.
    const QImage textured = view.grabFramebuffer();
    const QColor top = bandColor(textured, 0.0, 0.4);
    const QColor bottom = bandColor(textured, 0.6, 1.0);
    QVERIFY2(top.isValid() && bottom.isValid(), "the square must cover both bands");
    QVERIFY2(top.red() > 2 * top.blue() + 20, qPrintable(top.name()));
    QVERIFY2(bottom.blue() > 2 * bottom.red() + 20, qPrintable(bottom.name()));

    ViewOptions options;
    options.textures = false;
    view.setViewOptions(options);
    const QImage plain = view.grabFramebuffer();
    const QColor plainTop = bandColor(plain, 0.0, 0.4);
    QVERIFY2(std::abs(plainTop.red() - plainTop.blue()) < 12, qPrintable(plainTop.name()));
    QVERIFY(lodforge::testing::differingFraction(textured, plain, viewBackgroundColor()) > 0.5);
}

void WidgetsTest::viewWireframeChangesPixels() {
    widgets::VtkView view;
    view.resize(400, 400);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setScene(widgets::buildMeshScene(square(), {}));
    const PixelStats surface = measure(view.grabFramebuffer(), viewBackgroundColor(), QRect(0, 0, 400, 400));
    ViewOptions options;
    options.wireframe = true;
    view.setViewOptions(options);
    const PixelStats wire = measure(view.grabFramebuffer(), viewBackgroundColor(), QRect(0, 0, 400, 400));
    // Five edges of one pixel against a filled square.
    QVERIFY2(wire.modelPixels > 100 && wire.modelPixels < surface.modelPixels / 10,
             qPrintable(QStringLiteral("%1 vs %2").arg(wire.modelPixels).arg(surface.modelPixels)));
}

void WidgetsTest::viewMouseRotatesAndZooms() {
    widgets::VtkView view;
    view.resize(400, 400);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setScene(widgets::buildMeshScene(square(), {}));
    const QRect all(0, 0, 400, 400);
    const QImage start = view.grabFramebuffer();
    const qint64 startPixels = measure(start, viewBackgroundColor(), all).modelPixels;

    // Left drag: the trackball turns the square about the vertical axis, so it looks narrower.
    auto send = [&view](QEvent::Type type, QPointF at, Qt::MouseButton button, Qt::MouseButtons buttons) {
        QMouseEvent event(type, at, view.mapToGlobal(at), button, buttons, Qt::NoModifier);
        QApplication::sendEvent(&view, &event);
    };
    send(QEvent::MouseButtonPress, QPointF(200, 200), Qt::LeftButton, Qt::LeftButton);
    for (int x = 210; x <= 300; x += 10) send(QEvent::MouseMove, QPointF(x, 200), Qt::NoButton, Qt::LeftButton);
    send(QEvent::MouseButtonRelease, QPointF(300, 200), Qt::LeftButton, Qt::NoButton);
    const QImage turned = view.grabFramebuffer();
    QVERIFY2(lodforge::testing::differingFraction(start, turned, viewBackgroundColor()) > 0.2,
             "dragging must rotate the camera");

    // Wheel forward zooms in: the square covers more of the view.
    view.resetView();
    QVERIFY(lodforge::testing::differingFraction(start, view.grabFramebuffer(), viewBackgroundColor()) < 0.01);
    for (int i = 0; i < 3; ++i) {
        QWheelEvent wheel(QPointF(200, 200), view.mapToGlobal(QPointF(200, 200)), QPoint(), QPoint(0, 120),
                          Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase, false);
        QApplication::sendEvent(&view, &wheel);
    }
    const qint64 zoomedPixels = measure(view.grabFramebuffer(), viewBackgroundColor(), all).modelPixels;
    QVERIFY2(zoomedPixels > startPixels * 1.2, qPrintable(QStringLiteral("%1 vs %2").arg(zoomedPixels).arg(startPixels)));
}

void WidgetsTest::loadJobLoadsInBackground() {
    widgets::LoadJob job(spotPath);
    QSignalSpy progress(&job, &widgets::LoadJob::progressChanged);
    QSignalSpy finished(&job, &widgets::LoadJob::finished);
    job.start();
    QVERIFY(job.isRunning() || finished.count() == 1);
    QVERIFY(finished.wait(30000));
    const auto result = finished.at(0).at(0).value<widgets::LoadResult>();
    QCOMPARE(result.status, widgets::LoadResult::Status::ok);
    QVERIFY(result.model);
    QCOMPARE(result.model->mesh.triangle_count(), std::size_t(5856));
    QVERIFY(result.model->warnings.isEmpty());
    const widgets::MeshSceneInfo info = widgets::describe(*result.model->scene);
    QCOMPARE(info.parts.size(), std::size_t(1));
    QVERIFY(info.parts[0].textured);
    QCOMPARE(info.parts[0].textureWidth, 1024);
    QVERIFY(progress.count() >= 1);
    for (const QList<QVariant>& p : progress) {
        const double f = p.at(0).toDouble();
        QVERIFY(f >= 0.0 && f <= 1.0);
    }
}

void WidgetsTest::loadJobReportsErrorsWithTheFile() {
    QTemporaryDir dir;
    const QString missing = dir.filePath(QStringLiteral("no_such_mesh.ply"));
    const widgets::LoadResult result = widgets::LoadJob::load(missing);
    QCOMPARE(result.status, widgets::LoadResult::Status::failed);
    QVERIFY2(result.error.contains(QStringLiteral("no_such_mesh.ply")), qPrintable(result.error));
    QVERIFY(!result.model);

    // A texture that does not exist is a warning, not a failure.
    const QString obj = dir.filePath(QStringLiteral("lost_texture.obj"));
    const QString mtl = dir.filePath(QStringLiteral("lost_texture.mtl"));
    {
        QFile f(obj);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write("mtllib lost_texture.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                "usemtl skin\nf 1/1 2/2 3/3\n");
        QFile m(mtl);
        QVERIFY(m.open(QIODevice::WriteOnly));
        m.write("newmtl skin\nKd 1 1 1\nmap_Kd gone.png\n");
    }
    const widgets::LoadResult partial = widgets::LoadJob::load(obj);
    QCOMPARE(partial.status, widgets::LoadResult::Status::ok);
    QVERIFY2(!partial.model->warnings.isEmpty(), "the missing texture must be reported");
    QVERIFY2(partial.model->warnings.join(' ').contains(QStringLiteral("gone.png")),
             qPrintable(partial.model->warnings.join(' ')));
    QVERIFY(!widgets::describe(*partial.model->scene).parts[0].textured);
}

void WidgetsTest::loadJobCancelled() {
    struct Silent final : lodforge::CancelFlagProgress {
        void report(double, std::string_view) override {}
    } progress;
    progress.cancel();
    const widgets::LoadResult result = widgets::LoadJob::load(spotPath, &progress);
    QCOMPARE(result.status, widgets::LoadResult::Status::cancelled);
    QVERIFY(!result.model);

    widgets::LoadJob job(spotPath);
    QSignalSpy finished(&job, &widgets::LoadJob::finished);
    job.start();
    job.cancel();
    QVERIFY(finished.wait(30000));
    // Cancelled, unless the worker was already past its last check: either way no failure.
    QVERIFY(finished.at(0).at(0).value<widgets::LoadResult>().status != widgets::LoadResult::Status::failed);
}

void WidgetsTest::queuedProgressDeliversOnReceiverThread() {
    QObject receiver;
    QList<double> fractions;
    QStringList stages;
    bool onReceiverThread = true;
    widgets::QueuedProgress progress(&receiver, [&](double f, const QString& stage) {
        onReceiverThread = onReceiverThread && QThread::currentThread() == receiver.thread();
        fractions << f;
        stages << stage;
    });
    std::thread worker([&] {
        for (int i = 0; i <= 100000; ++i) progress.report(i / 100000.0, "reading");
        progress.report(0.5, "writing");
        progress.report(1.5, "writing");  // clamped
    });
    worker.join();
    QVERIFY(fractions.isEmpty());  // nothing runs on the worker
    QTRY_VERIFY(fractions.size() >= 3);
    QCoreApplication::processEvents();
    QVERIFY(onReceiverThread);
    QVERIFY2(fractions.size() <= 1003, qPrintable(QString::number(fractions.size())));  // rate-limited
    QCOMPARE(stages.first(), QStringLiteral("reading"));
    QCOMPARE(stages.last(), QStringLiteral("writing"));
    QCOMPARE(fractions.last(), 1.0);
    QVERIFY(!progress.cancelled());
    progress.cancel();
    QVERIFY(progress.cancelled());
}

void WidgetsTest::statsPanelShowsInfo() {
    const widgets::LoadResult result = widgets::LoadJob::load(spotPath);
    QCOMPARE(result.status, widgets::LoadResult::Status::ok);
    widgets::StatsPanel panel;
    panel.showInfo(result.model->info, 42, {QStringLiteral("a warning")});
    const QString text = panel.text();
    QVERIFY2(text.contains(QStringLiteral("42 ms")), qPrintable(text));
    QVERIFY2(text.contains(QStringLiteral("a warning")), qPrintable(text));
    QVERIFY2(text.contains(QStringLiteral("OBJ"), Qt::CaseInsensitive), qPrintable(text));
    QVERIFY2(text.contains(QStringLiteral("Validation")), qPrintable(text));
    panel.clear();
    QVERIFY(!panel.text().contains(QStringLiteral("Triangles")));

    lodforge::MeshInfo withNotes = result.model->info;
    withNotes.warnings = {"material library gone.mtl not found"};
    panel.showInfo(withNotes, -1, {});
    QVERIFY2(panel.text().contains(QStringLiteral("Import notes")), qPrintable(panel.text()));
    QVERIFY2(panel.text().contains(QStringLiteral("gone.mtl")), qPrintable(panel.text()));
}

void WidgetsTest::jobTurnsExceptionsIntoResults() {
    using lodforge::widgets::Job;
    using lodforge::widgets::JobResult;
    // Whatever the work throws comes back as a result on the GUI thread, never as an exception.
    struct Case {
        Job::Work work;
        JobResult::Status status;
        const char* message;
    };
    const Case cases[] = {
        {[](Progress*) {}, JobResult::Status::ok, ""},
        {[](Progress*) { throw Error(Error::Kind::io, "mesh.ply: cannot write"); }, JobResult::Status::failed,
         "mesh.ply: cannot write"},
        {[](Progress*) { throw std::runtime_error("boom"); }, JobResult::Status::failed, "test job: boom"},
        {[](Progress*) { throw std::bad_alloc(); }, JobResult::Status::failed, "not enough memory"},
        {[](Progress*) { throw 42; }, JobResult::Status::failed, "unknown error"},
        {[](Progress* p) { check_progress(p, 0.5, "stage"); throw Error(Error::Kind::cancelled, "cancelled"); },
         JobResult::Status::cancelled, "cancelled"},
    };
    for (const Case& c : cases) {
        Job job(QStringLiteral("test job"), c.work);
        QSignalSpy finished(&job, &Job::finished);
        job.start();
        QVERIFY(finished.wait(10000));
        const auto result = finished.at(0).at(0).value<lodforge::widgets::JobResult>();
        QCOMPARE(result.status, c.status);
        QCOMPARE(result.name, QStringLiteral("test job"));
        QVERIFY2(result.error.contains(QString::fromLatin1(c.message)), qPrintable(result.error));
    }
}

void WidgetsTest::jobCancelledFromTheGuiThread() {
    using lodforge::widgets::Job;
    std::atomic<bool> started{false};
    Job job(QStringLiteral("long"), [&started](Progress* p) {
        started = true;
        for (int i = 0; i < 100000; ++i) {
            check_progress(p, i / 100000.0, "waiting");
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    });
    QSignalSpy finished(&job, &Job::finished);
    QSignalSpy progress(&job, &Job::progressChanged);
    job.start();
    QTRY_VERIFY_WITH_TIMEOUT(started && progress.count() > 0, 5000);
    QVERIFY(job.isRunning());
    QCOMPARE(QThread::currentThread(), job.thread());
    job.cancel();
    QVERIFY(job.isCancelling());
    QVERIFY(finished.wait(5000));
    QCOMPARE(finished.at(0).at(0).value<lodforge::widgets::JobResult>().status,
             lodforge::widgets::JobResult::Status::cancelled);
}

void WidgetsTest::lodLevelsRefuseWhatTheyCannotBuild() {
    using namespace lodforge::widgets;
    LevelData original;
    original.mesh = std::make_shared<Mesh>(square());
    original.triangles = 2;
    Preset preset;
    preset.method = LodMethod::octree;
    preset.levels = {{LodTarget::Kind::error, 0.01}};
    try {
        buildLodLevels(original, preset, {});
        QFAIL("an error target must be refused by the octree method");
    } catch (const Error& e) {
        QCOMPARE(e.kind(), Error::Kind::argument);
        QVERIFY2(QString::fromUtf8(e.what()).contains(QStringLiteral("error targets")), e.what());
    }
    preset.method = LodMethod::cluster;
    preset.levels = {{LodTarget::Kind::error, 0.01}};
    try {
        buildLodLevels(original, preset, {});
        QFAIL("clustering takes no error targets");
    } catch (const Error& e) {
        QCOMPARE(e.kind(), Error::Kind::argument);
    }
    LevelData empty;
    empty.mesh = std::make_shared<Mesh>();
    try {
        buildLodLevels(empty, Preset{}, {});
        QFAIL("a mesh without triangles must be refused");
    } catch (const Error& e) {
        QCOMPARE(e.kind(), Error::Kind::invalid);
    }
}

// The shipped presets are offered in a combo box; choosing one with the keyboard replaces every option
// (one undoable edit) and the panel redraws with the preset's levels.
void WidgetsTest::parametersPanelStartsFromAShippedPreset() {
    using lodforge::widgets::ParametersPanel;
    ParametersPanel panel;
    panel.resize(420, 900);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    auto* library = panel.findChild<QComboBox*>(QStringLiteral("presetLibrary"));
    auto* levels = panel.findChild<QTableWidget*>();
    QVERIFY(library && levels);
    QCOMPARE(library->count(), 5);  // the prompt, then console, mobile, scan-archive, web
    QCOMPARE(library->itemText(2), QStringLiteral("mobile"));
    QCOMPARE(levels->rowCount(), 4);  // the default preset's levels
    const QImage before = panel.grab().toImage();

    QSignalSpy edited(&panel, &ParametersPanel::presetEdited);
    library->setFocus();
    QTest::keyClick(library, Qt::Key_Down);
    QTest::keyClick(library, Qt::Key_Down);
    QCOMPARE(library->currentText(), QStringLiteral("mobile"));
    QCOMPARE(edited.count(), 2);  // console, then mobile: each choice is one edit
    const Preset mobile = load_shipped_preset("mobile");
    QCOMPARE(panel.preset(), mobile);
    QCOMPARE(levels->rowCount(), int(mobile.levels.size()));
    QTest::qWait(50);
    const QImage after = panel.grab().toImage();
    QCOMPARE(after.size(), before.size());
    int changed = 0;
    for (int y = 0; y < after.height(); ++y)
        for (int x = 0; x < after.width(); ++x) changed += after.pixel(x, y) != before.pixel(x, y);
    QVERIFY2(changed > 200, qPrintable(QStringLiteral("%1 pixels changed").arg(changed)));

    // A preset that is not a shipped one shows the prompt again.
    panel.setPreset(Preset{});
    QCOMPARE(library->currentIndex(), 0);
}

void WidgetsTest::scalarSceneShowsValuesAndRange() {
    using namespace lodforge::widgets;
    const Mesh mesh = square();
    QVERIFY_THROWS_EXCEPTION(Error, buildScalarScene(mesh, {0.f, 1.f}));
    // Left edge 0, right edge 1: the view colours it from viridis purple to yellow.
    const auto scene = buildScalarScene(mesh, {0.f, 1.f, 1.f, 0.f});
    const MeshSceneInfo info = describe(*scene);
    QVERIFY(info.hasScalars);
    QCOMPARE(info.scalarMax, 1.0);
    VtkView view;
    view.resize(400, 300);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setScene(scene);
    view.setScalarBarVisible(false);
    view.resetView();
    QCOMPARE(view.scalarRange(), 1.0);
    const QImage image = view.grabFramebuffer().convertToFormat(QImage::Format_RGB32);
    const PixelStats s = measure(image, viewBackgroundColor());
    QVERIFY2(s.modelFraction() > 0.2, qPrintable(QString::number(s.modelFraction())));
    QVERIFY(lodforge::testing::hueClusters(image, viewBackgroundColor()) > 2);
    // The value under the cursor follows the field: small on the left, large on the right.
    const QRect model = lodforge::testing::backgroundRect(image, viewBackgroundColor());
    const int y = image.height() / 2;
    int left = -1, right = -1;
    for (int x = 0; x < image.width(); ++x) {
        if (lodforge::testing::nearColor(image.pixel(x, y), viewBackgroundColor(), 2)) continue;
        if (left < 0) left = x;
        right = x;
    }
    QVERIFY(left >= 0 && right > left + 20 && model.isValid());
    const auto atLeft = view.scalarAt(QPoint(left + 5, y));
    const auto atRight = view.scalarAt(QPoint(right - 5, y));
    QVERIFY(atLeft && atRight);
    qInfo("scalar at left %.3f, right %.3f", *atLeft, *atRight);
    // The view looks from the -Z side, so which screen side holds x = +1 depends on the camera; what must
    // hold: the two ends differ by most of the range, and the yellower end (viridis top) has the larger value.
    QVERIFY(std::abs(*atLeft - *atRight) > 0.6 && std::min(*atLeft, *atRight) >= 0 && std::max(*atLeft, *atRight) <= 1.0001);
    auto yellowness = [&](int x) {
        const QRgb p = image.pixel(x, y);
        return qRed(p) + qGreen(p) - 2 * qBlue(p);
    };
    QCOMPARE(yellowness(right - 5) > yellowness(left + 5), *atRight > *atLeft);
    // A smaller range maps more of the surface to the top colour.
    view.setScalarRange(0.25);
    QCOMPARE(view.scalarRange(), 0.25);
    const QImage narrowed = view.grabFramebuffer().convertToFormat(QImage::Format_RGB32);
    QVERIFY(lodforge::testing::differingFraction(image, narrowed, viewBackgroundColor()) > 0.3);
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    WidgetsTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "widgets_test.moc"
