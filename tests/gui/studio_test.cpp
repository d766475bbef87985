// The studio's main window in process, under Xvfb: loading, the error path, the View toggles, recent
// files, drag and drop, cancelling. Every check of what is shown reads real pixels of the 3D view.
#include "MainWindow.h"
#include "PixelStats.h"

#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/StatsPanel.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

#include <QAbstractButton>
#include <QAction>
#include <QApplication>
#include <QFile>
#include <QMenu>
#include <QMessageBox>
#include <QMimeData>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QTest>
#include <QUrl>

#include <memory>

using lodforge::studio::MainWindow;
using lodforge::testing::differingFraction;
using lodforge::testing::measure;
using lodforge::testing::PixelStats;
using lodforge::widgets::viewBackgroundColor;
using lodforge::widgets::ViewOptions;

namespace {

const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");
const QString colorPlyPath = QStringLiteral(LODFORGE_SHARED_DATA "/color-open3d-small/color.ply");
const QString dragonPath = QStringLiteral(LODFORGE_SHARED_DATA "/scan-dragon/dragon_vrip.ply");

QString describe(const PixelStats& s) {
    return QStringLiteral("view %1x%2, model %3 px (%4%), %5 colours, luma sd %6, chromatic %7%, r-b %8")
        .arg(s.view.width())
        .arg(s.view.height())
        .arg(s.modelPixels)
        .arg(100.0 * s.modelFraction(), 0, 'f', 1)
        .arg(s.distinctColors)
        .arg(s.lumaStdDev, 0, 'f', 1)
        .arg(100.0 * s.chromaticFraction, 0, 'f', 1)
        .arg(s.meanRedMinusBlue, 0, 'f', 1);
}

}  // namespace

class StudioTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase();
    void init();
    void cleanup();

    void spotShowsItsTexture();
    void vertexColorsAreShown();
    void brokenFileShowsErrorAndWindowStaysUsable();
    void wireframeChangesPixels();
    void flatShadingChangesPixels();
    void windowGrabContainsTheView();
    void statisticsDescribeTheMesh();
    void recentFilesArePersisted();
    void droppedFileIsOpened();
    void cancelKeepsThePreviousMesh();
    void progressIsShownWhileLoading();
    void nonInteractiveFailureOpensNoDialog();

private:
    // Opens `path` and waits for the result; returns loadFinished's arguments.
    bool load(const QString& path, QString* message = nullptr);
    QImage viewImage();  // the 3D view's current frame

    std::unique_ptr<MainWindow> window_;
};

void StudioTest::initTestCase() {
    QVERIFY2(QFile::exists(spotPath), qPrintable(spotPath));
    QVERIFY2(QFile::exists(colorPlyPath), qPrintable(colorPlyPath));
    QSettings().clear();
}

void StudioTest::init() {
    window_ = std::make_unique<MainWindow>();
    window_->resize(1100, 760);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
}

void StudioTest::cleanup() {
    // Close any dialog a failed check left open, then the window.
    while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
    window_.reset();
}

bool StudioTest::load(const QString& path, QString* message) {
    QSignalSpy finished(window_.get(), &MainWindow::loadFinished);
    window_->openFile(path);
    if (!finished.wait(60000)) {
        if (message) *message = QStringLiteral("no loadFinished within 60 s");
        return false;
    }
    if (message) *message = finished.at(0).at(1).toString();
    return finished.at(0).at(0).toBool();
}

QImage StudioTest::viewImage() {
    return window_->view()->grabFramebuffer().convertToFormat(QImage::Format_RGB32);
}

void StudioTest::spotShowsItsTexture() {
    QString message;
    QVERIFY2(load(spotPath, &message), qPrintable(message));
    QCOMPARE(window_->currentFile(), spotPath);
    QVERIFY(window_->windowTitle().contains(QStringLiteral("spot_triangulated.obj")));

    const QImage textured = viewImage();
    const PixelStats withTexture = measure(textured, viewBackgroundColor());
    qInfo("textured:   %s", qPrintable(describe(withTexture)));

    ViewOptions options = window_->viewOptions();
    QVERIFY(options.textures);
    options.textures = false;
    window_->setViewOptions(options);
    const QImage plain = viewImage();
    const PixelStats withoutTexture = measure(plain, viewBackgroundColor());
    qInfo("untextured: %s", qPrintable(describe(withoutTexture)));

    // The cow fills a good part of the view in both.
    QVERIFY2(withTexture.modelFraction() > 0.10, qPrintable(describe(withTexture)));
    QVERIFY2(withoutTexture.modelFraction() > 0.10, qPrintable(describe(withoutTexture)));
    // Textured: black spots on a pale pink hide, a pink muzzle, brown horns. Much more variation than
    // the smoothly shaded grey material, and a warm tint the grey does not have.
    QVERIFY2(withTexture.distinctColors > 150, qPrintable(describe(withTexture)));
    QVERIFY2(withTexture.lumaStdDev > 1.5 * withoutTexture.lumaStdDev,
             qPrintable(describe(withTexture) + " vs " + describe(withoutTexture)));
    QVERIFY2(withTexture.meanRedMinusBlue > withoutTexture.meanRedMinusBlue + 8.0,
             qPrintable(describe(withTexture) + " vs " + describe(withoutTexture)));
    const double changed = differingFraction(textured, plain, viewBackgroundColor());
    qInfo("texture on/off changes %.1f%% of the model's pixels", 100.0 * changed);
    QVERIFY2(changed > 0.15, qPrintable(QString::number(changed)));
}

void StudioTest::vertexColorsAreShown() {
    QString message;
    QVERIFY2(load(colorPlyPath, &message), qPrintable(message));
    const QImage colored = viewImage();
    const PixelStats withColors = measure(colored, viewBackgroundColor());
    qInfo("colours on:  %s", qPrintable(describe(withColors)));
    // A patch of an RGB-D scan: black and white surfaces and a red-orange object.
    QVERIFY2(withColors.modelFraction() > 0.05, qPrintable(describe(withColors)));
    QVERIFY2(withColors.chromaticFraction > 0.08, qPrintable(describe(withColors)));
    QVERIFY2(withColors.distinctColors > 100, qPrintable(describe(withColors)));

    // Switching the colours off leaves the neutral grey material.
    auto* action = window_->findChild<QAction*>(QStringLiteral("actionVertexColors"));
    QVERIFY(action);
    QVERIFY(action->isChecked());
    action->trigger();
    QVERIFY(!window_->viewOptions().vertexColors);
    const QImage plain = viewImage();
    const PixelStats withoutColors = measure(plain, viewBackgroundColor());
    qInfo("colours off: %s", qPrintable(describe(withoutColors)));
    QVERIFY2(withoutColors.chromaticFraction < 0.01, qPrintable(describe(withoutColors)));
    const double changed = differingFraction(colored, plain, viewBackgroundColor());
    qInfo("colours on/off changes %.1f%% of the model's pixels", 100.0 * changed);
    QVERIFY2(changed > 0.3, qPrintable(QString::number(changed)));
}

void StudioTest::brokenFileShowsErrorAndWindowStaysUsable() {
    QString message;
    QVERIFY2(load(colorPlyPath, &message), qPrintable(message));
    const QImage before = viewImage();

    // A PLY cut off in the middle of its vertex list.
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString broken = dir.filePath(QStringLiteral("truncated_mesh.ply"));
    {
        QFile file(broken);
        QVERIFY(file.open(QIODevice::WriteOnly));
        file.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
                   "0 0 0\n1 0 0\n1 1");
    }

    QSignalSpy finished(window_.get(), &MainWindow::loadFinished);
    window_->openFile(broken);
    QVERIFY(finished.wait(30000));
    QCOMPARE(finished.at(0).at(0).toBool(), false);
    QVERIFY2(!finished.at(0).at(1).toString().isEmpty(), "the failure must carry a message");

    // A critical message box names the file; close it like a user would.
    QMessageBox* box = nullptr;
    QTRY_VERIFY_WITH_TIMEOUT((box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) != nullptr, 5000);
    QCOMPARE(box->icon(), QMessageBox::Critical);
    QVERIFY2(box->text().contains(QStringLiteral("truncated_mesh.ply")), qPrintable(box->text()));
    QVERIFY2(!box->informativeText().isEmpty(), "the dialog must say what is wrong");
    qInfo("dialog: %s / %s", qPrintable(box->text()), qPrintable(box->informativeText()));
    QAbstractButton* ok = box->button(QMessageBox::Ok);
    QVERIFY(ok);
    QTest::mouseClick(ok, Qt::LeftButton);
    QTRY_VERIFY_WITH_TIMEOUT(QApplication::activeModalWidget() == nullptr, 5000);

    // The previous mesh is still there.
    QCOMPARE(window_->currentFile(), colorPlyPath);
    QVERIFY(!window_->isLoading());
    QVERIFY2(differingFraction(before, viewImage(), viewBackgroundColor()) < 0.01,
             "the view must still show the previous mesh");

    // And the window still works: another file loads and shows.
    QVERIFY2(load(spotPath, &message), qPrintable(message));
    QCOMPARE(window_->currentFile(), spotPath);
    const QImage after = viewImage();
    const PixelStats spot = measure(after, viewBackgroundColor());
    qInfo("after the error: %s", qPrintable(describe(spot)));
    QVERIFY2(spot.modelFraction() > 0.10, qPrintable(describe(spot)));
    QVERIFY2(differingFraction(before, after, viewBackgroundColor()) > 0.3, "the new mesh must replace the old");
}

void StudioTest::wireframeChangesPixels() {
    QString message;
    QVERIFY2(load(spotPath, &message), qPrintable(message));
    const QImage surface = viewImage();
    auto* action = window_->findChild<QAction*>(QStringLiteral("actionWireframe"));
    QVERIFY(action);
    QVERIFY(!action->isChecked());
    action->trigger();
    QVERIFY(window_->viewOptions().wireframe);
    const QImage wire = viewImage();
    const PixelStats s = measure(surface, viewBackgroundColor());
    const PixelStats w = measure(wire, viewBackgroundColor());
    qInfo("surface: %s", qPrintable(describe(s)));
    qInfo("wire:    %s", qPrintable(describe(w)));
    const double changed = differingFraction(surface, wire, viewBackgroundColor());
    qInfo("wireframe changes %.1f%% of the model's pixels", 100.0 * changed);
    QVERIFY2(changed > 0.2, qPrintable(QString::number(changed)));
    // Edges leave background showing between them: fewer covered pixels, but still a mesh on screen.
    QVERIFY2(w.modelPixels < s.modelPixels * 0.9 && w.modelPixels > s.modelPixels * 0.05,
             qPrintable(describe(s) + " vs " + describe(w)));

    action->trigger();
    QVERIFY(!window_->viewOptions().wireframe);
    QVERIFY(differingFraction(surface, viewImage(), viewBackgroundColor()) < 0.01);
}

void StudioTest::flatShadingChangesPixels() {
    QString message;
    QVERIFY2(load(spotPath, &message), qPrintable(message));
    ViewOptions options = window_->viewOptions();
    options.textures = false;  // facets show best on the plain material
    window_->setViewOptions(options);
    const QImage smooth = viewImage();
    auto* action = window_->findChild<QAction*>(QStringLiteral("actionFlatShading"));
    QVERIFY(action);
    action->trigger();
    QVERIFY(window_->viewOptions().flatShading);
    const QImage flat = viewImage();
    // Facets change the shade of most pixels a little (the surface is finely tessellated).
    const double changed = differingFraction(smooth, flat, viewBackgroundColor(), {}, 3);
    qInfo("flat shading changes %.1f%% of the model's pixels", 100.0 * changed);
    QVERIFY2(changed > 0.15, qPrintable(QString::number(changed)));
    action->trigger();
    QVERIFY(differingFraction(smooth, viewImage(), viewBackgroundColor(), {}, 3) < 0.01);
}

void StudioTest::windowGrabContainsTheView() {
    QString message;
    QVERIFY2(load(spotPath, &message), qPrintable(message));
    const QImage shot = window_->grabWindowImage();
    QCOMPARE(shot.size(), window_->size() * window_->devicePixelRatio());
    const PixelStats s = measure(shot, viewBackgroundColor());
    qInfo("window: %s", qPrintable(describe(s)));
    // The view's region is found from its background and holds the textured model.
    const QRect viewRect(window_->view()->mapTo(window_.get(), QPoint(0, 0)), window_->view()->size());
    QVERIFY2(viewRect.contains(s.view), "the background must lie inside the view");
    QVERIFY2(s.view.width() > viewRect.width() * 0.9, "the background must span the view");
    QVERIFY2(s.distinctColors > 150 && s.modelFraction() > 0.1, qPrintable(describe(s)));
}

void StudioTest::statisticsDescribeTheMesh() {
    QString message;
    QVERIFY2(load(spotPath, &message), qPrintable(message));
    const QString text = window_->statsPanel()->text();
    qInfo("%s", qPrintable(text));
    QVERIFY2(text.contains(QStringLiteral("Vertices: 2,930")) || text.contains(QStringLiteral("Vertices: 2930")),
             qPrintable(text));
    QVERIFY2(text.contains(QStringLiteral("Triangles: 5,856")) || text.contains(QStringLiteral("Triangles: 5856")),
             qPrintable(text));
    QVERIFY2(text.contains(QStringLiteral("spot_texture.png")), qPrintable(text));
    QVERIFY2(text.contains(QStringLiteral("texcoord")), qPrintable(text));
    QVERIFY(window_->model());
    QCOMPARE(window_->model()->info.triangles, std::size_t(5856));
}

void StudioTest::recentFilesArePersisted() {
    QSettings().remove(QStringLiteral("recentFiles"));
    QString message;
    QVERIFY2(load(colorPlyPath, &message), qPrintable(message));
    QVERIFY2(load(spotPath, &message), qPrintable(message));
    QCOMPARE(window_->recentFiles(), (QStringList{spotPath, colorPlyPath}));

    // A new window (a new session) lists them, most recent first, and opens one from the menu.
    window_ = std::make_unique<MainWindow>();
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    auto* recent = window_->findChild<QMenu*>(QStringLiteral("menuRecent"));
    QVERIFY(recent);
    QVERIFY(recent->isEnabled());
    QList<QAction*> entries;
    for (QAction* a : recent->actions()) {
        if (!a->data().toString().isEmpty()) entries << a;
    }
    QCOMPARE(entries.size(), 2);
    QCOMPARE(entries[0]->data().toString(), spotPath);
    QCOMPARE(entries[1]->data().toString(), colorPlyPath);
    QSignalSpy finished(window_.get(), &MainWindow::loadFinished);
    entries[1]->trigger();
    QVERIFY(finished.wait(30000));
    QVERIFY(finished.at(0).at(0).toBool());
    QCOMPARE(window_->currentFile(), colorPlyPath);
    QCOMPARE(window_->recentFiles().value(0), colorPlyPath);
}

void StudioTest::droppedFileIsOpened() {
    QMimeData mime;
    mime.setUrls({QUrl::fromLocalFile(spotPath)});
    const QPoint at = window_->view()->mapTo(window_.get(), window_->view()->rect().center());
    QDragEnterEvent enter(at, Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    enter.setAccepted(false);
    QApplication::sendEvent(window_.get(), &enter);
    QVERIFY(enter.isAccepted());

    QSignalSpy finished(window_.get(), &MainWindow::loadFinished);
    QDropEvent drop(at, Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    drop.setAccepted(false);
    QApplication::sendEvent(window_.get(), &drop);
    QVERIFY(drop.isAccepted());
    QVERIFY(finished.wait(30000));
    QVERIFY(finished.at(0).at(0).toBool());
    QCOMPARE(window_->currentFile(), spotPath);
    QVERIFY(measure(viewImage(), viewBackgroundColor()).modelFraction() > 0.1);

    // Text without a file is not accepted.
    QMimeData text;
    text.setText(QStringLiteral("not a file"));
    QDragEnterEvent enterText(at, Qt::CopyAction, &text, Qt::LeftButton, Qt::NoModifier);
    enterText.setAccepted(false);
    QApplication::sendEvent(window_.get(), &enterText);
    QVERIFY(!enterText.isAccepted());
}

void StudioTest::cancelKeepsThePreviousMesh() {
    QString message;
    QVERIFY2(load(spotPath, &message), qPrintable(message));
    const QImage before = viewImage();
    QVERIFY2(QFile::exists(dragonPath), qPrintable(dragonPath));

    auto* cancel = window_->findChild<QPushButton*>(QStringLiteral("cancelLoad"));
    auto* progress = window_->findChild<QProgressBar*>(QStringLiteral("loadProgress"));
    QVERIFY(cancel && progress);
    QVERIFY(!cancel->isVisible());

    QSignalSpy finished(window_.get(), &MainWindow::loadFinished);
    window_->openFile(dragonPath);
    QVERIFY(window_->isLoading());
    QVERIFY(cancel->isVisible() && progress->isVisible());
    QTest::mouseClick(cancel, Qt::LeftButton);
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.at(0).at(0).toBool(), false);
    QVERIFY2(finished.at(0).at(1).toString().isEmpty(), "cancelling is not an error");
    QVERIFY(QApplication::activeModalWidget() == nullptr);
    QVERIFY(!window_->isLoading());
    QVERIFY(!cancel->isVisible());
    QCOMPARE(window_->currentFile(), spotPath);
    QVERIFY(differingFraction(before, viewImage(), viewBackgroundColor()) < 0.01);
}

void StudioTest::progressIsShownWhileLoading() {
    const QString bigger = QStringLiteral(LODFORGE_SHARED_DATA "/scan-dragon/dragon_vrip_res2.ply");
    QVERIFY2(QFile::exists(bigger), qPrintable(bigger));
    auto* progress = window_->findChild<QProgressBar*>(QStringLiteral("loadProgress"));
    QVERIFY(progress);
    QSignalSpy values(progress, &QProgressBar::valueChanged);
    QString message;
    QVERIFY2(load(bigger, &message), qPrintable(message));
    QVERIFY(values.count() >= 1);
    for (const QList<QVariant>& v : values) QVERIFY(v.at(0).toInt() >= 0 && v.at(0).toInt() <= 1000);
    QVERIFY(!progress->isVisible());
    QVERIFY2(window_->statusBar()->currentMessage().contains(QStringLiteral("dragon_vrip_res2.ply")),
             qPrintable(window_->statusBar()->currentMessage()));
    QCOMPARE(window_->model()->info.triangles, std::size_t(202520));
}

void StudioTest::nonInteractiveFailureOpensNoDialog() {
    QSettings().remove(QStringLiteral("recentFiles"));
    window_->setInteractive(false);
    QTemporaryDir dir;
    const QString missing = dir.filePath(QStringLiteral("missing_mesh.obj"));
    QString message;
    QVERIFY(!load(missing, &message));
    QVERIFY2(message.contains(QStringLiteral("missing_mesh.obj")), qPrintable(message));
    QTest::qWait(100);
    QVERIFY(QApplication::activeModalWidget() == nullptr);
    QVERIFY(load(spotPath, &message));
    QVERIFY(window_->recentFiles().isEmpty());
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    // Settings of their own (and XDG_CONFIG_HOME points into the build tree under ctest).
    QApplication::setOrganizationName(QStringLiteral("LodForgeTests"));
    QApplication::setApplicationName(QStringLiteral("gui_studio_test"));
    StudioTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_test.moc"
