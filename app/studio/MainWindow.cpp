#include "MainWindow.h"

#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/StatsPanel.h"
#include "lodforge/widgets/VtkView.h"

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QKeySequence>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPainter>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QStatusBar>
#include <QUrl>

namespace lodforge::studio {

namespace {

const QString recentFilesKey = QStringLiteral("recentFiles");
const QString geometryKey = QStringLiteral("window/geometry");
const QString stateKey = QStringLiteral("window/state");

// The local file a drag carries, or an empty string.
QString droppedFile(const QMimeData* mime) {
    if (!mime || !mime->hasUrls()) return {};
    for (const QUrl& url : mime->urls()) {
        if (url.isLocalFile()) return url.toLocalFile();
    }
    return {};
}

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
    setObjectName(QStringLiteral("mainWindow"));
    setWindowTitle(tr("LodForge Studio"));
    setAcceptDrops(true);

    view_ = new widgets::VtkView(this);
    view_->setObjectName(QStringLiteral("view"));
    setCentralWidget(view_);

    stats_ = new widgets::StatsPanel(this);
    stats_->setObjectName(QStringLiteral("stats"));
    statsDock_ = new QDockWidget(tr("Statistics"), this);
    statsDock_->setObjectName(QStringLiteral("statsDock"));
    statsDock_->setWidget(stats_);
    statsDock_->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetClosable |
                            QDockWidget::DockWidgetFloatable);
    addDockWidget(Qt::RightDockWidgetArea, statsDock_);

    createActions();
    createMenus();
    createStatusBar();

    QSettings settings;
    if (const QByteArray geometry = settings.value(geometryKey).toByteArray(); !geometry.isEmpty()) {
        restoreGeometry(geometry);
    } else {
        resize(1280, 800);
    }
    restoreState(settings.value(stateKey).toByteArray());
    updateRecentMenu();
    statusBar()->showMessage(tr("Open a mesh (PLY, OBJ, glTF) with File > Open or drop it here"));
}

MainWindow::~MainWindow() = default;

void MainWindow::createActions() {
    openAction_ = new QAction(tr("&Open…"), this);
    openAction_->setObjectName(QStringLiteral("actionOpen"));
    openAction_->setShortcut(QKeySequence::Open);
    connect(openAction_, &QAction::triggered, this, &MainWindow::showOpenDialog);

    quitAction_ = new QAction(tr("&Quit"), this);
    quitAction_->setObjectName(QStringLiteral("actionQuit"));
    quitAction_->setShortcut(QKeySequence::Quit);
    quitAction_->setMenuRole(QAction::QuitRole);
    connect(quitAction_, &QAction::triggered, this, &QWidget::close);

    auto toggle = [this](const QString& text, const QString& name, const QKeySequence& key, bool checked,
                         const QString& tip) {
        auto* action = new QAction(text, this);
        action->setObjectName(name);
        action->setCheckable(true);
        action->setChecked(checked);
        action->setShortcut(key);
        action->setStatusTip(tip);
        connect(action, &QAction::toggled, this, &MainWindow::applyViewActions);
        return action;
    };
    const widgets::ViewOptions defaults;
    wireframeAction_ = toggle(tr("&Wireframe"), QStringLiteral("actionWireframe"), QKeySequence(Qt::Key_W),
                              defaults.wireframe, tr("Draw triangle edges only"));
    flatShadingAction_ = toggle(tr("&Flat shading"), QStringLiteral("actionFlatShading"),
                                QKeySequence(Qt::Key_F), defaults.flatShading,
                                tr("One normal per triangle instead of smooth vertex normals"));
    texturesAction_ = toggle(tr("&Texture"), QStringLiteral("actionTextures"), QKeySequence(Qt::Key_T),
                             defaults.textures, tr("Apply the base colour texture"));
    vertexColorsAction_ = toggle(tr("Vertex &colours"), QStringLiteral("actionVertexColors"),
                                 QKeySequence(Qt::Key_C), defaults.vertexColors,
                                 tr("Show per-vertex colours where no texture is shown"));

    resetViewAction_ = new QAction(tr("&Reset view"), this);
    resetViewAction_->setObjectName(QStringLiteral("actionResetView"));
    resetViewAction_->setShortcut(QKeySequence(Qt::Key_R));
    connect(resetViewAction_, &QAction::triggered, view_, &widgets::VtkView::resetView);
}

void MainWindow::createMenus() {
    QMenu* file = menuBar()->addMenu(tr("&File"));
    file->setObjectName(QStringLiteral("menuFile"));
    file->addAction(openAction_);
    recentMenu_ = file->addMenu(tr("Open &Recent"));
    recentMenu_->setObjectName(QStringLiteral("menuRecent"));
    file->addSeparator();
    file->addAction(quitAction_);

    QMenu* viewMenu = menuBar()->addMenu(tr("&View"));
    viewMenu->setObjectName(QStringLiteral("menuView"));
    viewMenu->addAction(wireframeAction_);
    viewMenu->addAction(flatShadingAction_);
    viewMenu->addAction(texturesAction_);
    viewMenu->addAction(vertexColorsAction_);
    viewMenu->addSeparator();
    viewMenu->addAction(resetViewAction_);
    viewMenu->addSeparator();
    QAction* showStats = statsDock_->toggleViewAction();
    showStats->setText(tr("&Statistics"));
    viewMenu->addAction(showStats);

    QMenu* help = menuBar()->addMenu(tr("&Help"));
    QAction* about = help->addAction(tr("&About LodForge Studio"));
    about->setMenuRole(QAction::AboutRole);
    connect(about, &QAction::triggered, this, [this] {
        QMessageBox::about(this, tr("About LodForge Studio"),
                           tr("<b>LodForge Studio %1</b><p>Level-of-detail authoring for heavy meshes.</p>"
                              "<p>Drag with the left button to rotate, the middle button (or Shift) to pan, "
                              "the right button or the wheel to zoom.</p>")
                               .arg(QApplication::applicationVersion()));
    });
}

void MainWindow::createStatusBar() {
    progressBar_ = new QProgressBar(this);
    progressBar_->setObjectName(QStringLiteral("loadProgress"));
    progressBar_->setRange(0, 1000);
    progressBar_->setMaximumWidth(320);
    progressBar_->setTextVisible(true);
    cancelButton_ = new QPushButton(tr("Cancel"), this);
    cancelButton_->setObjectName(QStringLiteral("cancelLoad"));
    connect(cancelButton_, &QPushButton::clicked, this, &MainWindow::cancelLoading);
    statusBar()->addPermanentWidget(progressBar_);
    statusBar()->addPermanentWidget(cancelButton_);
    setLoadingUi(false);
}

void MainWindow::setLoadingUi(bool loading) {
    progressBar_->setVisible(loading);
    cancelButton_->setVisible(loading);
    cancelButton_->setEnabled(loading);
    if (loading) {
        progressBar_->setValue(0);
        progressBar_->setFormat(tr("Loading %p%"));
    }
}

void MainWindow::showOpenDialog() {
    const QString dir = currentFile().isEmpty() ? QString() : QFileInfo(currentFile()).absolutePath();
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Open mesh"), dir, tr("Meshes (*.ply *.obj *.gltf *.glb);;All files (*)"));
    if (!path.isEmpty()) openFile(path);
}

void MainWindow::openFile(const QString& path) {
    if (job_) job_->cancel();  // its result is dropped when it arrives
    auto* job = new widgets::LoadJob(QFileInfo(path).absoluteFilePath(), this);
    job_ = job;
    connect(job, &widgets::LoadJob::progressChanged, this, [this, job](double fraction, const QString& stage) {
        if (job == job_) onLoadProgress(fraction, stage);
    });
    connect(job, &widgets::LoadJob::finished, this,
            [this, job](const widgets::LoadResult& result) { onLoadFinished(job, result); });
    setLoadingUi(true);
    statusBar()->showMessage(tr("Loading %1…").arg(QFileInfo(path).fileName()));
    job->start();
}

void MainWindow::cancelLoading() {
    if (!job_) return;
    job_->cancel();
    cancelButton_->setEnabled(false);
    progressBar_->setFormat(tr("Cancelling…"));
}

bool MainWindow::isLoading() const { return job_ != nullptr; }

QString MainWindow::currentFile() const { return model_ ? model_->path : QString(); }

std::shared_ptr<const widgets::LoadedModel> MainWindow::model() const { return model_; }

void MainWindow::setInteractive(bool interactive) { interactive_ = interactive; }

void MainWindow::onLoadProgress(double fraction, const QString& stage) {
    progressBar_->setValue(static_cast<int>(fraction * 1000.0));
    if (cancelButton_->isEnabled()) progressBar_->setFormat(stage.isEmpty() ? tr("%p%") : stage + tr(" %p%"));
}

void MainWindow::onLoadFinished(widgets::LoadJob* job, const widgets::LoadResult& result) {
    job->deleteLater();
    if (job != job_) return;  // superseded by a later openFile
    job_ = nullptr;
    setLoadingUi(false);

    const QString name = QFileInfo(result.path).fileName();
    switch (result.status) {
    case widgets::LoadResult::Status::ok: {
        model_ = result.model;
        view_->setScene(model_->scene);
        stats_->showInfo(model_->info, model_->elapsedMs, model_->warnings);
        setWindowTitle(tr("%1 — LodForge Studio").arg(name));
        setWindowFilePath(result.path);
        if (interactive_) addRecentFile(result.path);
        QString message = tr("Loaded %1 in %2 ms").arg(name).arg(model_->elapsedMs);
        if (!model_->warnings.isEmpty()) message += tr(" (%n warning(s), see Statistics)", "", int(model_->warnings.size()));
        statusBar()->showMessage(message);
        emit loadFinished(true, message);
        return;
    }
    case widgets::LoadResult::Status::cancelled:
        statusBar()->showMessage(tr("Loading %1 cancelled").arg(name), 5000);
        emit loadFinished(false, QString());
        return;
    case widgets::LoadResult::Status::failed:
        break;
    }

    statusBar()->showMessage(tr("Could not open %1").arg(name), 10000);
    if (interactive_) {
        // Window-modal and not blocking: the event loop (and the loadFinished listeners) go on.
        auto* box = new QMessageBox(QMessageBox::Critical, tr("Cannot open file"),
                                    tr("Could not open %1.").arg(name), QMessageBox::Ok, this);
        box->setObjectName(QStringLiteral("loadErrorBox"));
        box->setInformativeText(result.error);
        box->setDetailedText(result.path);
        box->setAttribute(Qt::WA_DeleteOnClose);
        box->open();
    }
    emit loadFinished(false, result.error.isEmpty() ? tr("Could not open %1").arg(result.path) : result.error);
}

QStringList MainWindow::recentFiles() const {
    return QSettings().value(recentFilesKey).toStringList();
}

void MainWindow::addRecentFile(const QString& path) {
    QStringList files = recentFiles();
    files.removeAll(path);
    files.prepend(path);
    while (files.size() > maxRecentFiles) files.removeLast();
    QSettings().setValue(recentFilesKey, files);
    updateRecentMenu();
}

void MainWindow::updateRecentMenu() {
    recentMenu_->clear();
    const QStringList files = recentFiles();
    for (int i = 0; i < files.size(); ++i) {
        const QString& path = files[i];
        const QString name = QFileInfo(path).fileName();
        QAction* action = recentMenu_->addAction(i < 9 ? tr("&%1 %2").arg(i + 1).arg(name) : name);
        action->setToolTip(path);
        action->setStatusTip(path);
        action->setData(path);
        connect(action, &QAction::triggered, this, [this, path] { openFile(path); });
    }
    if (!files.isEmpty()) {
        recentMenu_->addSeparator();
        QAction* clear = recentMenu_->addAction(tr("&Clear list"));
        connect(clear, &QAction::triggered, this, [this] {
            QSettings().remove(recentFilesKey);
            updateRecentMenu();
        });
    }
    recentMenu_->setEnabled(!files.isEmpty());
}

void MainWindow::setViewOptions(const widgets::ViewOptions& options) {
    const QSignalBlocker b1(wireframeAction_), b2(flatShadingAction_), b3(texturesAction_),
        b4(vertexColorsAction_);
    wireframeAction_->setChecked(options.wireframe);
    flatShadingAction_->setChecked(options.flatShading);
    texturesAction_->setChecked(options.textures);
    vertexColorsAction_->setChecked(options.vertexColors);
    view_->setViewOptions(options);
}

widgets::ViewOptions MainWindow::viewOptions() const { return view_->viewOptions(); }

void MainWindow::applyViewActions() {
    widgets::ViewOptions options;
    options.wireframe = wireframeAction_->isChecked();
    options.flatShading = flatShadingAction_->isChecked();
    options.textures = texturesAction_->isChecked();
    options.vertexColors = vertexColorsAction_->isChecked();
    view_->setViewOptions(options);
}

QImage MainWindow::grabWindowImage() {
    QImage image = grab().toImage().convertToFormat(QImage::Format_RGB32);
    // Draw the view's framebuffer over its place explicitly, so the shot holds the frame VTK rendered
    // whatever way the widget grab composes OpenGL children.
    const QImage frame = view_->grabFramebuffer();
    if (!frame.isNull()) {
        QPainter painter(&image);
        painter.drawImage(QRect(view_->mapTo(this, QPoint(0, 0)), view_->size()), frame);
    }
    return image;
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
    if (!droppedFile(event->mimeData()).isEmpty()) event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
    const QString path = droppedFile(event->mimeData());
    if (path.isEmpty()) return;
    event->acceptProposedAction();
    openFile(path);
}

void MainWindow::closeEvent(QCloseEvent* event) {
    QSettings settings;
    settings.setValue(geometryKey, saveGeometry());
    settings.setValue(stateKey, saveState());
    if (job_) job_->cancel();
    QMainWindow::closeEvent(event);
}

}  // namespace lodforge::studio
