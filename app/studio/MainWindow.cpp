#include "MainWindow.h"
#include "OutputFolderDialog.h"

#include "lodforge/error.h"
#include "lodforge/pack/lod_pack.h"
#include "lodforge/pack/preset_library.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/render/image_compare.h"
#include "lodforge/widgets/Job.h"
#include "lodforge/widgets/LatestJob.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/LodLevels.h"
#include "lodforge/widgets/McoPriorityPanel.h"
#include "lodforge/widgets/OctreeTuningPanel.h"
#include "lodforge/widgets/MorphPanel.h"
#include "lodforge/widgets/ParametersPanel.h"
#include "lodforge/widgets/ReportPanel.h"
#include "lodforge/widgets/StatsPanel.h"
#include "lodforge/widgets/VtkView.h"

#include <QAbstractSpinBox>
#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDateTime>
#include <QDesktopServices>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDir>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QHeaderView>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QKeyEvent>
#include <QKeySequence>
#include <QKeySequenceEdit>
#include <QLabel>
#include <QLineEdit>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPainter>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QSettings>
#include <QSlider>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTabBar>
#include <QTableWidget>
#include <QTextEdit>
#include <QTimer>
#include <QToolBar>
#include <QUndoCommand>
#include <QUndoStack>
#include <QUrl>
#include <QVBoxLayout>

#include <tuple>

namespace lodforge::studio {

namespace {

const QString recentFilesKey = QStringLiteral("recentFiles");
const QString geometryKey = QStringLiteral("window/geometry");
const QString stateKey = QStringLiteral("window/state");
const QString lastPresetKey = QStringLiteral("preset/last");
const QString viewKey = QStringLiteral("view/");
const QString autoRebuildKey = QStringLiteral("lod/autoRebuild");
const QString packDirKey = QStringLiteral("export/packDir");
const QString reportDirKey = QStringLiteral("export/reportDir");

// Where exports start when none was made yet: the user's documents, not the data folder or the working
// directory.
QString defaultExportFolder() {
    const QString documents = QStandardPaths::writableLocation(QStandardPaths::DocumentsLocation);
    return documents.isEmpty() ? QDir::homePath() : documents;
}

// What the levels depend on: everything but the preset's name and the pack's contents.
lodforge::Preset levelParameters(lodforge::Preset preset) {
    preset.name.clear();
    preset.exports = {};
    return preset;
}

// A preset value as a reader writes it: numbers short, objects as "key value" pairs, lists comma-separated.
QString parameterText(const QJsonValue& value) {
    switch (value.type()) {
    case QJsonValue::Bool: return value.toBool() ? QStringLiteral("yes") : QStringLiteral("no");
    case QJsonValue::Double: return QString::number(value.toDouble(), 'g', 6);
    case QJsonValue::String: return value.toString();
    case QJsonValue::Array: {
        QStringList items;
        for (const QJsonValue& item : value.toArray()) items << parameterText(item);
        return items.join(QStringLiteral(", "));
    }
    case QJsonValue::Object: {
        QStringList items;
        const QJsonObject object = value.toObject();
        for (auto it = object.begin(); it != object.end(); ++it) items << it.key() + QLatin1Char(' ') + parameterText(it.value());
        return items.join(QStringLiteral(", "));
    }
    default: return {};
    }
}

// The parameters that made the levels, for the report: the preset's keys that `method` reads
// (build_preset_levels, the rule the Parameters dock's visible knobs follow), one line per key, blocks
// flattened to "block.key".
QList<QPair<QString, QString>> reportParameters(const lodforge::Preset& preset) {
    using lodforge::LodMethod;
    const LodMethod m = preset.method;
    const QJsonObject json = QJsonDocument::fromJson(QByteArray::fromStdString(lodforge::preset_to_json(preset))).object();
    auto reads = [&](const QString& key) {
        if (key == QLatin1String("version") || key == QLatin1String("name")) return false;
        if (key == QLatin1String("weights")) return m != LodMethod::mcoctree;
        if (key == QLatin1String("lock_border")) return m == LodMethod::collapse || m == LodMethod::lodstrips;
        if (key == QLatin1String("octree")) return m == LodMethod::octree;
        if (key == QLatin1String("mcoctree")) return m == LodMethod::mcoctree;
        if (key == QLatin1String("strips")) return m == LodMethod::lodstrips;
        if (key == QLatin1String("skin")) return preset.skin != lodforge::SkinOptions{};
        return true;
    };
    QList<QPair<QString, QString>> out;
    for (auto it = json.begin(); it != json.end(); ++it) {
        if (!reads(it.key())) continue;
        if (it.value().isObject()) {
            const QJsonObject block = it.value().toObject();
            for (auto b = block.begin(); b != block.end(); ++b)
                out.append({it.key() + QLatin1Char('.') + b.key(), parameterText(b.value())});
        } else {
            out.append({it.key(), parameterText(it.value())});
        }
    }
    return out;
}

// A field where letters are text: single-key shortcuts must type there. Spin boxes are not (their line
// edit takes numbers), nor read-only text.
bool takesText(const QWidget* w) {
    if (!w) return false;
    if (auto* line = qobject_cast<const QLineEdit*>(w))
        return !line->isReadOnly() && !qobject_cast<const QAbstractSpinBox*>(line->parentWidget());
    if (auto* text = qobject_cast<const QTextEdit*>(w)) return !text->isReadOnly();
    if (auto* text = qobject_cast<const QPlainTextEdit*>(w)) return !text->isReadOnly();
    return qobject_cast<const QKeySequenceEdit*>(w) != nullptr;
}

// The local file a drag carries, or an empty string.
QString droppedFile(const QMimeData* mime) {
    if (!mime || !mime->hasUrls()) return {};
    for (const QUrl& url : mime->urls()) {
        if (url.isLocalFile()) return url.toLocalFile();
    }
    return {};
}

// One parameter change. The panel already shows `after` when the command is pushed, so the first
// redo (QUndoStack::push calls it) does nothing.
class PresetCommand final : public QUndoCommand {
public:
    PresetCommand(widgets::ParametersPanel* panel, lodforge::Preset before, lodforge::Preset after, bool applied,
                  const QString& text)
        : QUndoCommand(text), panel_(panel), before_(std::move(before)), after_(std::move(after)), skipRedo_(applied) {}
    void undo() override { panel_->setPreset(before_); }
    void redo() override {
        if (skipRedo_) {
            skipRedo_ = false;
            return;
        }
        panel_->setPreset(after_);
    }

private:
    widgets::ParametersPanel* panel_;
    lodforge::Preset before_, after_;
    bool skipRedo_;
};

QString measureName(bool full) { return full ? MainWindow::tr("Full-precision measure") : MainWindow::tr("Measure"); }

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
    setObjectName(QStringLiteral("mainWindow"));
    setWindowTitle(tr("LodForge Studio[*]"));
    setAcceptDrops(true);

    levels_ = new widgets::LevelViews(this);
    levels_->setObjectName(QStringLiteral("levelViews"));
    setCentralWidget(levels_);
    undo_ = new QUndoStack(this);

    createDocks();
    createActions();
    createMenus();
    createToolBar();
    createStatusBar();
    createStructurePanels();
    createMorph();

    connect(levels_, &widgets::LevelViews::hoverText, this, [this](const QString& text) {
        if (text.isEmpty()) {
            statusBar()->clearMessage();
        } else {
            statusBar()->showMessage(text);
        }
    });
    connect(levels_, &widgets::LevelViews::currentLevelChanged, this, [this] { updateActions(); });
    connect(params_, &widgets::ParametersPanel::presetEdited, this,
            [this](const lodforge::Preset& before, const lodforge::Preset& after) {
                undo_->push(new PresetCommand(params_, before, after, true, tr("Change parameters")));
            });
    connect(undo_, &QUndoStack::cleanChanged, this, [this](bool clean) { setWindowModified(!clean); });
    connect(undo_, &QUndoStack::indexChanged, this, &MainWindow::updateStale);
    rebuildTimer_ = new QTimer(this);
    rebuildTimer_->setSingleShot(true);
    rebuildTimer_->setInterval(500);
    connect(rebuildTimer_, &QTimer::timeout, this, [this] {
        if (!levelsStale() || !autoRebuild()) return;
        if (isBusy()) return rebuildTimer_->start();  // after the running job
        appendLog(tr("Parameters changed: rebuilding the levels"));
        buildLodChain();
    });
    connect(levels_, &widgets::LevelViews::rebuildRequested, this, &MainWindow::buildLodChain);
    qApp->installEventFilter(this);
    connect(qApp, &QApplication::focusChanged, this, [this](QWidget*, QWidget* now) {
        typingHint_->setVisible(takesText(now) && now->window() == this);
    });

    restoreSettings();
    // Six docks share the right column: their tab titles scroll rather than shrink to "Stati…".
    const auto unelide = [this] {
        for (QTabBar* bar : findChildren<QTabBar*>(Qt::FindDirectChildrenOnly)) {
            bar->setElideMode(Qt::ElideNone);
            bar->setUsesScrollButtons(true);
        }
    };
    unelide();
    for (QDockWidget* d : findChildren<QDockWidget*>())
        connect(d, &QDockWidget::dockLocationChanged, this, [unelide] { QTimer::singleShot(0, unelide); });
    updateRecentMenu();
    updateActions();
    statusBar()->showMessage(tr("Open a mesh (PLY, OBJ, glTF) with File > Open or drop it here"));
}

MainWindow::~MainWindow() {
    // Focus moves while ~QWidget deletes the children: the typing hint must not hear of it then.
    disconnect(qApp, nullptr, this, nullptr);
    qApp->removeEventFilter(this);
    // Jobs report to this window: stop them before its members go.
    delete task_;
    task_ = nullptr;
    delete measure_;
    measure_ = nullptr;
}

QString MainWindow::lodChainJobName() { return tr("LOD chain"); }
QString MainWindow::heatmapJobName() { return tr("Heat map"); }
QString MainWindow::packJobName() { return tr("LOD pack"); }

widgets::VtkView* MainWindow::view() const { return levels_->singleView(); }

void MainWindow::createDocks() {
    auto dock = [this](const QString& title, const QString& name, QWidget* widget, Qt::DockWidgetArea area) {
        auto* d = new QDockWidget(title, this);
        d->setObjectName(name);
        d->setWidget(widget);
        d->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetClosable |
                       QDockWidget::DockWidgetFloatable);
        addDockWidget(area, d);
        return d;
    };
    stats_ = new widgets::StatsPanel(this);
    stats_->setObjectName(QStringLiteral("stats"));
    statsDock_ = dock(tr("Statistics"), QStringLiteral("statsDock"), stats_, Qt::RightDockWidgetArea);
    params_ = new widgets::ParametersPanel(this);
    params_->setObjectName(QStringLiteral("parameters"));
    // Scrolled: the panel is taller than small windows.
    auto* paramsScroll = new QScrollArea(this);
    paramsScroll->setWidget(params_);
    paramsScroll->setWidgetResizable(true);
    paramsScroll->setFrameShape(QFrame::NoFrame);
    paramsDock_ = dock(tr("Parameters"), QStringLiteral("parametersDock"), paramsScroll, Qt::RightDockWidgetArea);
    tabifyDockWidget(statsDock_, paramsDock_);
    report_ = new widgets::ReportPanel(this);
    imageErrors_ = new widgets::LatestJob([this]() -> std::optional<widgets::LatestJob::Run> {
        if (!model_ || levels_->levels().size() < 2) return std::nullopt;
        auto levels = levels_->levels();
        auto images = model_->images;
        auto out = std::make_shared<std::vector<lodforge::ImageError>>();
        return widgets::LatestJob::Run{
            tr("Image error"),
            [out, levels, images](lodforge::Progress* p) { *out = widgets::computeImageErrors(levels, images, p); },
            [this, out](const widgets::JobResult&) {
                report_->setImageErrors(*out);
                QStringList parts;
                for (const lodforge::ImageError& e : *out) parts << QString::number(e.mean_abs, 'f', 2);
                appendLog(tr("  image error per level (0-255): %1").arg(parts.join(QStringLiteral(", "))));
            }};
    }, this);
    connect(imageErrors_, &widgets::LatestJob::failed, this,
            [this](const QString& error) { appendLog(tr("Image error failed: %1").arg(error)); });
    connect(imageErrors_, &widgets::LatestJob::changed, this, [this] {
        if (!imageErrors_->isBusy()) emit imageErrorsSettled();
    });
    report_->setObjectName(QStringLiteral("report"));
    // All docks tabbed on the right by default, so the views keep the window's full height.
    reportDock_ = dock(tr("Report"), QStringLiteral("reportDock"), report_, Qt::RightDockWidgetArea);
    log_ = new QPlainTextEdit(this);
    log_->setObjectName(QStringLiteral("log"));
    log_->setReadOnly(true);
    log_->setMaximumBlockCount(5000);
    logDock_ = dock(tr("Log"), QStringLiteral("logDock"), log_, Qt::RightDockWidgetArea);
    tabifyDockWidget(paramsDock_, reportDock_);
    tabifyDockWidget(reportDock_, logDock_);
    paramsDock_->raise();
}

// Two docks beside the Log, their View menu toggles, and the few hooks they need: the loaded model and
// every parameter change (edits, undo, redo, presets) for their knobs.
void MainWindow::createStructurePanels() {
    mcoPanel_ = new widgets::McoPriorityPanel(levels_, this);
    mcoPanel_->setObjectName(QStringLiteral("mcoPriority"));
    octreePanel_ = new widgets::OctreeTuningPanel(levels_, this);
    octreePanel_->setObjectName(QStringLiteral("octreeTuning"));
    QDockWidget* previous = logDock_;
    QMenu* viewMenu = menuBar()->findChild<QMenu*>(QStringLiteral("menuView"));
    for (auto [panel, title, name] : {std::tuple<QWidget*, QString, QString>{mcoPanel_, tr("MC octree"), QStringLiteral("mcoDock")},
                                      {octreePanel_, tr("Octree"), QStringLiteral("octreeDock")}}) {
        auto* dock = new QDockWidget(title, this);
        dock->setObjectName(name);
        dock->setWidget(panel);
        addDockWidget(Qt::RightDockWidgetArea, dock);
        tabifyDockWidget(previous, dock);
        previous = dock;
        if (viewMenu) viewMenu->addAction(dock->toggleViewAction());
    }
    paramsDock_->raise();
    auto forward = [this] {
        mcoPanel_->setPreset(params_->preset());
        octreePanel_->setPreset(params_->preset());
    };
    forward();
    connect(undo_, &QUndoStack::indexChanged, this, forward);
    connect(mcoPanel_, &widgets::McoPriorityPanel::logMessage, this, &MainWindow::appendLog);
    connect(octreePanel_, &widgets::OctreeTuningPanel::logMessage, this, &MainWindow::appendLog);
    // A failed build opens the error dialog as the window's own jobs do (the message names the file).
    connect(mcoPanel_, &widgets::McoPriorityPanel::built, this, [this](bool ok, const QString& message) {
        if (!ok) showError(tr("MC octree failed"), tr("The marching-cube octree could not be built."), message);
    });
    connect(octreePanel_, &widgets::OctreeTuningPanel::built, this, [this](bool ok, const QString& message) {
        if (!ok) showError(tr("Octree failed"), tr("The out-of-core octree could not be built."), message);
    });
}

void MainWindow::createActions() {
    auto action = [this](const QString& text, const QString& name, const QKeySequence& key, const QString& tip) {
        auto* a = new QAction(text, this);
        a->setObjectName(name);
        a->setShortcut(key);
        a->setStatusTip(tip);
        a->setToolTip(tip + (key.isEmpty() ? QString() : QStringLiteral(" (%1)").arg(key.toString(QKeySequence::NativeText))));
        return a;
    };
    openAction_ = action(tr("&Open…"), QStringLiteral("actionOpen"), QKeySequence::Open, tr("Open a mesh"));
    connect(openAction_, &QAction::triggered, this, &MainWindow::showOpenDialog);
    quitAction_ = action(tr("&Quit"), QStringLiteral("actionQuit"), QKeySequence::Quit, tr("Quit"));
    quitAction_->setMenuRole(QAction::QuitRole);
    connect(quitAction_, &QAction::triggered, this, &QWidget::close);
    loadPresetAction_ = action(tr("&Load preset…"), QStringLiteral("actionLoadPreset"),
                               QKeySequence(Qt::CTRL | Qt::Key_L), tr("Load parameters from a preset JSON file"));
    connect(loadPresetAction_, &QAction::triggered, this, &MainWindow::showLoadPresetDialog);
    savePresetAction_ = action(tr("&Save preset…"), QStringLiteral("actionSavePreset"), QKeySequence::Save,
                               tr("Save the parameters as a preset JSON file (the CLI reads the same files)"));
    connect(savePresetAction_, &QAction::triggered, this, &MainWindow::showSavePresetDialog);
    exportReportAction_ = action(tr("&Export report…"), QStringLiteral("actionExportReport"),
                                 QKeySequence(Qt::CTRL | Qt::Key_E), tr("Export the LOD report as HTML or PDF"));
    connect(exportReportAction_, &QAction::triggered, this, &MainWindow::showExportReportDialog);
    exportPackAction_ = action(tr("Export LOD &pack…"), QStringLiteral("actionExportPack"),
                               QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_E),
                               tr("Write the LOD pack (.glb with MSFT_lod, per-level files, pack.json) of the preset"));
    connect(exportPackAction_, &QAction::triggered, this, &MainWindow::showExportPackDialog);

    undoAction_ = undo_->createUndoAction(this, tr("&Undo"));
    undoAction_->setObjectName(QStringLiteral("actionUndo"));
    undoAction_->setShortcut(QKeySequence::Undo);
    redoAction_ = undo_->createRedoAction(this, tr("&Redo"));
    redoAction_->setObjectName(QStringLiteral("actionRedo"));
    redoAction_->setShortcuts({QKeySequence::Redo, QKeySequence(Qt::CTRL | Qt::Key_Y)});

    buildAction_ = action(tr("&Build LOD chain"), QStringLiteral("actionBuildLodChain"), QKeySequence(Qt::CTRL | Qt::Key_B),
                          tr("Build the levels of the preset from the loaded mesh"));
    connect(buildAction_, &QAction::triggered, this, &MainWindow::buildLodChain);
    cancelAction_ = action(tr("&Cancel job"), QStringLiteral("actionCancel"), QKeySequence(Qt::Key_Escape),
                           tr("Cancel the load or job that is running"));
    connect(cancelAction_, &QAction::triggered, this, &MainWindow::cancelLoading);
    measureFullAction_ = action(tr("&Measure at full precision"), QStringLiteral("actionMeasureFull"), QKeySequence(),
                                tr("Measure every level's error with the full sample count (as lodforge compare)"));
    connect(measureFullAction_, &QAction::triggered, this, [this] { measureLevels(true); });
    nextLevelAction_ = action(tr("&Next level"), QStringLiteral("actionNextLevel"), QKeySequence(Qt::Key_PageDown),
                              tr("Show the next (coarser) level"));
    connect(nextLevelAction_, &QAction::triggered, this,
            [this] { levels_->setCurrentLevel(levels_->currentLevel() + 1); });
    previousLevelAction_ = action(tr("&Previous level"), QStringLiteral("actionPreviousLevel"),
                                  QKeySequence(Qt::Key_PageUp), tr("Show the previous (finer) level"));
    connect(previousLevelAction_, &QAction::triggered, this,
            [this] { levels_->setCurrentLevel(levels_->currentLevel() - 1); });

    auto toggle = [this, action](const QString& text, const QString& name, const QKeySequence& key, bool checked,
                                 const QString& tip) {
        QAction* a = action(text, name, key, tip);
        a->setCheckable(true);
        a->setChecked(checked);
        return a;
    };
    sideBySideAction_ = toggle(tr("&Side by side"), QStringLiteral("actionSideBySide"), QKeySequence(Qt::Key_S), false,
                               tr("Every level in its own view, one camera for all"));
    connect(sideBySideAction_, &QAction::toggled, this, &MainWindow::setSideBySide);
    heatmapAction_ = toggle(tr("&Heat map"), QStringLiteral("actionHeatmap"), QKeySequence(Qt::Key_H), false,
                            tr("Colour by the distance to the original"));
    connect(heatmapAction_, &QAction::toggled, this, &MainWindow::setHeatmapVisible);
    compareAction_ = toggle(tr("S&plit compare"), QStringLiteral("actionCompare"), QKeySequence(Qt::Key_X), false,
                            tr("Original left of the split, the level right of it"));
    connect(compareAction_, &QAction::toggled, this, &MainWindow::setCompareVisible);

    const widgets::ViewOptions defaults;
    auto viewToggle = [this, toggle](const QString& text, const QString& name, const QKeySequence& key, bool checked,
                                     const QString& tip) {
        QAction* a = toggle(text, name, key, checked, tip);
        connect(a, &QAction::toggled, this, &MainWindow::applyViewActions);
        return a;
    };
    wireframeAction_ = viewToggle(tr("&Wireframe"), QStringLiteral("actionWireframe"), QKeySequence(Qt::Key_W),
                                  defaults.wireframe, tr("Draw triangle edges only"));
    flatShadingAction_ = viewToggle(tr("&Flat shading"), QStringLiteral("actionFlatShading"), QKeySequence(Qt::Key_F),
                                    defaults.flatShading, tr("One normal per triangle instead of smooth vertex normals"));
    texturesAction_ = viewToggle(tr("&Texture"), QStringLiteral("actionTextures"), QKeySequence(Qt::Key_T),
                                 defaults.textures, tr("Apply the base colour texture"));
    vertexColorsAction_ = viewToggle(tr("Vertex &colours"), QStringLiteral("actionVertexColors"), QKeySequence(Qt::Key_C),
                                     defaults.vertexColors, tr("Show per-vertex colours where no texture is shown"));
    edgesAction_ = viewToggle(tr("&Edges over shading"), QStringLiteral("actionEdges"), QKeySequence(Qt::Key_E),
                              defaults.edges, tr("Wireframe drawn over the shaded surface"));
    normalColorsAction_ = viewToggle(tr("&Normals as colours"), QStringLiteral("actionNormalColors"),
                                     QKeySequence(Qt::Key_N), defaults.normalColors,
                                     tr("Colour each point by its shading normal"));
    uvCheckerAction_ = viewToggle(tr("&UV checker"), QStringLiteral("actionUvChecker"), QKeySequence(Qt::Key_U),
                                  defaults.uvChecker, tr("A checker texture on the texture coordinates"));
    heatmapOutlineAction_ = viewToggle(tr("Original's &outline over heat map"), QStringLiteral("actionHeatmapOutline"),
                                       QKeySequence(Qt::SHIFT | Qt::Key_H), defaults.heatmapOutline,
                                       tr("Draw the original's silhouette over each level's heat map"));
    // The checker's density: squares per UV unit doubled or halved (2..128), so small charts show theirs.
    uvFinerAction_ = action(tr("UV checker &finer"), QStringLiteral("actionUvFiner"), QKeySequence(Qt::SHIFT | Qt::Key_U),
                            tr("Twice as many UV checker squares per texture unit"));
    connect(uvFinerAction_, &QAction::triggered, this, [this] { setUvCheckerCells(uvCheckerCells_ * 2); });
    uvCoarserAction_ = action(tr("UV checker c&oarser"), QStringLiteral("actionUvCoarser"), QKeySequence(Qt::ALT | Qt::Key_U),
                              tr("Half as many UV checker squares per texture unit"));
    connect(uvCoarserAction_, &QAction::triggered, this, [this] { setUvCheckerCells(uvCheckerCells_ / 2); });
    cellsAction_ = viewToggle(tr("&Octree cells"), QStringLiteral("actionCells"), QKeySequence(Qt::Key_O),
                              defaults.cells,
                              tr("The cells of the octree the levels were cut from, as wireframe boxes"));
    cellsByTrianglesAction_ = viewToggle(tr("Cells coloured by triangle &count"),
                                         QStringLiteral("actionCellsByTriangles"),
                                         QKeySequence(Qt::SHIFT | Qt::Key_O), defaults.cellsByTriangles,
                                         tr("Colour the cells by the input triangles under them instead of "
                                            "their depth"));

    using widgets::ViewOptions;
    viewToggles_ = {{wireframeAction_, &ViewOptions::wireframe, QStringLiteral("wireframe")},
                    {flatShadingAction_, &ViewOptions::flatShading, QStringLiteral("flatShading")},
                    {texturesAction_, &ViewOptions::textures, QStringLiteral("textures")},
                    {vertexColorsAction_, &ViewOptions::vertexColors, QStringLiteral("vertexColors")},
                    {edgesAction_, &ViewOptions::edges, QStringLiteral("edges")},
                    {normalColorsAction_, &ViewOptions::normalColors, QStringLiteral("normalColors")},
                    {uvCheckerAction_, &ViewOptions::uvChecker, QStringLiteral("uvChecker")},
                    {heatmapOutlineAction_, &ViewOptions::heatmapOutline, QStringLiteral("heatmapOutline")},
                    {cellsAction_, &ViewOptions::cells, QStringLiteral("cells")},
                    {cellsByTrianglesAction_, &ViewOptions::cellsByTriangles, QStringLiteral("cellsByTriangles")}};

    autoRebuildAction_ = action(tr("Rebuild &automatically"), QStringLiteral("actionAutoRebuild"), QKeySequence(),
                                tr("Build the levels again whenever a parameter they depend on changes"));
    autoRebuildAction_->setCheckable(true);
    connect(autoRebuildAction_, &QAction::toggled, this, [this](bool on) {
        QSettings().setValue(autoRebuildKey, on);
        if (on) updateStale();
    });
    shortcutsAction_ = action(tr("&Keyboard shortcuts"), QStringLiteral("actionShortcuts"),
                              QKeySequence(QKeySequence::HelpContents), tr("Every key of the studio on one sheet"));
    connect(shortcutsAction_, &QAction::triggered, this, &MainWindow::showShortcutsSheet);
    docsAction_ = action(tr("&Documentation"), QStringLiteral("actionDocumentation"), QKeySequence(),
                         tr("Open the studio's documentation (docs/studio.md)"));
    connect(docsAction_, &QAction::triggered, this, [this] {
        const QString path = documentationPath();
        if (path.isEmpty() || !QDesktopServices::openUrl(QUrl::fromLocalFile(path)))
            showError(tr("No documentation"), tr("The documentation could not be opened."),
                      path.isEmpty() ? tr("docs/studio.md is neither installed nor in the source tree") : path);
    });

    resetViewAction_ = action(tr("&Reset view"), QStringLiteral("actionResetView"), QKeySequence(Qt::Key_R),
                              tr("Frame the mesh from the default viewpoint"));
    connect(resetViewAction_, &QAction::triggered, levels_, &widgets::LevelViews::resetView);
}

void MainWindow::createMenus() {
    QMenu* file = menuBar()->addMenu(tr("&File"));
    file->setObjectName(QStringLiteral("menuFile"));
    file->addAction(openAction_);
    recentMenu_ = file->addMenu(tr("Open &Recent"));
    recentMenu_->setObjectName(QStringLiteral("menuRecent"));
    file->addSeparator();
    file->addAction(loadPresetAction_);
    file->addAction(savePresetAction_);
    file->addSeparator();
    file->addAction(exportReportAction_);
    file->addAction(exportPackAction_);
    file->addSeparator();
    file->addAction(quitAction_);

    QMenu* edit = menuBar()->addMenu(tr("&Edit"));
    edit->setObjectName(QStringLiteral("menuEdit"));
    edit->addAction(undoAction_);
    edit->addAction(redoAction_);

    QMenu* lod = menuBar()->addMenu(tr("&LOD"));
    lod->setObjectName(QStringLiteral("menuLod"));
    lod->addAction(buildAction_);
    lod->addAction(cancelAction_);
    lod->addAction(measureFullAction_);
    lod->addAction(autoRebuildAction_);
    lod->addSeparator();
    lod->addAction(previousLevelAction_);
    lod->addAction(nextLevelAction_);

    QMenu* viewMenu = menuBar()->addMenu(tr("&View"));
    viewMenu->setObjectName(QStringLiteral("menuView"));
    viewMenu->addAction(sideBySideAction_);
    viewMenu->addAction(heatmapAction_);
    viewMenu->addAction(heatmapOutlineAction_);
    viewMenu->addAction(compareAction_);
    viewMenu->addSeparator();
    for (QAction* a : {wireframeAction_, edgesAction_, flatShadingAction_, texturesAction_, uvCheckerAction_,
                       uvFinerAction_, uvCoarserAction_, vertexColorsAction_, normalColorsAction_})
        viewMenu->addAction(a);
    viewMenu->addSeparator();
    viewMenu->addAction(cellsAction_);
    viewMenu->addAction(cellsByTrianglesAction_);
    viewMenu->addSeparator();
    viewMenu->addAction(resetViewAction_);
    viewMenu->addSeparator();
    for (QDockWidget* d : {statsDock_, paramsDock_, reportDock_, logDock_}) viewMenu->addAction(d->toggleViewAction());

    QMenu* help = menuBar()->addMenu(tr("&Help"));
    help->setObjectName(QStringLiteral("menuHelp"));
    help->addAction(shortcutsAction_);
    help->addAction(docsAction_);
    help->addSeparator();
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

void MainWindow::createToolBar() {
    QToolBar* bar = addToolBar(tr("LOD"));
    bar->setObjectName(QStringLiteral("lodToolBar"));
    bar->addAction(openAction_);
    bar->addAction(buildAction_);
    bar->addAction(exportPackAction_);
    bar->addSeparator();
    bar->addAction(sideBySideAction_);
    bar->addAction(heatmapAction_);
    bar->addWidget(new QLabel(tr(" Range "), bar));
    rangeBox_ = new QDoubleSpinBox(bar);
    rangeBox_->setObjectName(QStringLiteral("heatmapRange"));
    rangeBox_->setDecimals(6);
    rangeBox_->setRange(0.0, 1e9);
    rangeBox_->setSpecialValueText(tr("auto"));
    rangeBox_->setKeyboardTracking(false);
    rangeBox_->setToolTip(tr("Distance mapped to the top of the colour map (model units; 0 = the largest)"));
    connect(rangeBox_, &QDoubleSpinBox::valueChanged, levels_, &widgets::LevelViews::setHeatmapRange);
    bar->addWidget(rangeBox_);
    bar->addSeparator();
    bar->addAction(compareAction_);
    splitSlider_ = new QSlider(Qt::Horizontal, bar);
    splitSlider_->setObjectName(QStringLiteral("splitSlider"));
    splitSlider_->setRange(0, 1000);
    splitSlider_->setValue(500);
    splitSlider_->setMaximumWidth(160);
    splitSlider_->setToolTip(tr("Split position: original on the left, level on the right"));
    connect(splitSlider_, &QSlider::valueChanged, this, [this](int v) { levels_->setSplitPosition(v / 1000.0); });
    bar->addWidget(splitSlider_);
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
    typingHint_ = new QLabel(tr("Typing in a field: single-key shortcuts paused"), this);
    typingHint_->setObjectName(QStringLiteral("typingHint"));
    typingHint_->setToolTip(tr("Letters go to the field being typed in; click a view or press Tab to use "
                               "the single-key shortcuts again"));
    typingHint_->hide();
    statusBar()->addPermanentWidget(typingHint_);
    statusBar()->addPermanentWidget(progressBar_);
    statusBar()->addPermanentWidget(cancelButton_);
    setBusyUi(false);
}

void MainWindow::restoreSettings() {
    QSettings settings;
    if (const QByteArray geometry = settings.value(geometryKey).toByteArray(); !geometry.isEmpty()) {
        restoreGeometry(geometry);
    } else {
        resize(1280, 800);
    }
    if (!restoreState(settings.value(stateKey).toByteArray())) {
        // First start: the views get most of the window.
        resizeDocks({paramsDock_}, {360}, Qt::Horizontal);
    }
    const widgets::ViewOptions defaults;
    widgets::ViewOptions options;
    for (const ViewToggle& t : viewToggles_) options.*t.option = settings.value(viewKey + t.key, defaults.*t.option).toBool();
    options.uvCheckerCells = std::clamp(settings.value(viewKey + QStringLiteral("uvCheckerCells"), defaults.uvCheckerCells).toInt(),
                                        widgets::minUvCheckerCells, widgets::maxUvCheckerCells);
    setViewOptions(options);
    sideBySideAction_->setChecked(settings.value(viewKey + QStringLiteral("sideBySide"), false).toBool());
    autoRebuildAction_->setChecked(settings.value(autoRebuildKey, false).toBool());
    const QString last = settings.value(lastPresetKey).toString();
    if (!last.isEmpty() && QFile::exists(last)) {
        try {
            params_->setPreset(lodforge::load_preset(QFile::encodeName(last).toStdString()));
            presetPath_ = last;
            appendLog(tr("Preset %1 restored").arg(last));
        } catch (const lodforge::Error& e) {
            appendLog(tr("Last preset not restored: %1").arg(QString::fromUtf8(e.what())));
        }
    }
}

void MainWindow::saveSettings() {
    QSettings settings;
    settings.setValue(geometryKey, saveGeometry());
    settings.setValue(stateKey, saveState());
    const widgets::ViewOptions o = viewOptions();
    for (const ViewToggle& t : viewToggles_) settings.setValue(viewKey + t.key, o.*t.option);
    settings.setValue(viewKey + QStringLiteral("uvCheckerCells"), o.uvCheckerCells);
    settings.setValue(viewKey + QStringLiteral("sideBySide"), sideBySideAction_->isChecked());
    if (!presetPath_.isEmpty()) settings.setValue(lastPresetKey, presetPath_);
}

void MainWindow::setBusyUi(bool busy, const QString& format) {
    // A measure runs beside the jobs: the bar shows it when no job does.
    const bool measuring = !busy && measure_ != nullptr;
    progressBar_->setVisible(busy || measuring);
    cancelButton_->setVisible(busy || measuring);
    cancelButton_->setEnabled(busy || (measuring && !measure_->isCancelling()));
    if (busy) {
        progressBar_->setValue(0);
        progressBar_->setFormat(format.isEmpty() ? tr("Loading %p%") : format);
    } else if (measuring) {
        progressBar_->setFormat(tr("Measuring %p%"));
    }
    if (buildAction_) updateActions();
}

void MainWindow::updateActions() {
    const bool busy = isBusy();
    const bool haveMesh = model_ != nullptr;
    buildAction_->setEnabled(haveMesh && !busy);
    cancelAction_->setEnabled(busy || measure_ != nullptr);
    measureFullAction_->setEnabled(levels_->levelCount() > 1 && !levelsStale());
    exportReportAction_->setEnabled(!report_->isEmpty());
    exportPackAction_->setEnabled(haveMesh && !busy);
    const int level = levels_->currentLevel();
    nextLevelAction_->setEnabled(level + 1 < levels_->levelCount());
    previousLevelAction_->setEnabled(level > 0);
}

void MainWindow::appendLog(const QString& text) {
    log_->appendPlainText(QStringLiteral("[%1] %2").arg(QDateTime::currentDateTime().toString(QStringLiteral("HH:mm:ss")), text));
}

void MainWindow::showError(const QString& title, const QString& text, const QString& details) {
    if (!interactive_) return;
    // Window-modal and not blocking: the event loop (and the signal listeners) go on.
    auto* box = new QMessageBox(QMessageBox::Critical, title, text, QMessageBox::Ok, this);
    box->setObjectName(QStringLiteral("errorBox"));
    box->setInformativeText(details);
    box->setAttribute(Qt::WA_DeleteOnClose);
    box->open();
}

void MainWindow::showOpenDialog() {
    const QString dir = currentFile().isEmpty() ? QString() : QFileInfo(currentFile()).absolutePath();
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Open mesh"), dir, tr("Meshes (*.ply *.obj *.gltf *.glb);;All files (*)"));
    if (!path.isEmpty()) openFile(path);
}

void MainWindow::openFile(const QString& path) {
    if (job_) job_->cancel();  // its result is dropped when it arrives
    if (task_) task_->cancel();  // it works on the mesh being replaced
    auto* job = new widgets::LoadJob(QFileInfo(path).absoluteFilePath(), this);
    job_ = job;
    connect(job, &widgets::LoadJob::progressChanged, this, [this, job](double fraction, const QString& stage) {
        if (job == job_) onLoadProgress(fraction, stage);
    });
    connect(job, &widgets::LoadJob::finished, this,
            [this, job](const widgets::LoadResult& result) { onLoadFinished(job, result); });
    setBusyUi(true);
    statusBar()->showMessage(tr("Loading %1…").arg(QFileInfo(path).fileName()));
    appendLog(tr("Loading %1").arg(path));
    job->start();
}

void MainWindow::cancelLoading() {
    if (!job_ && !task_ && !measure_) return;
    if (job_) job_->cancel();
    if (task_) task_->cancel();
    if (measure_) measure_->cancel();
    cancelButton_->setEnabled(false);
    progressBar_->setFormat(tr("Cancelling…"));
}

bool MainWindow::isLoading() const { return job_ != nullptr; }

bool MainWindow::isBusy() const { return job_ != nullptr || task_ != nullptr; }

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
    setBusyUi(task_ != nullptr);

    const QString name = QFileInfo(result.path).fileName();
    switch (result.status) {
    case widgets::LoadResult::Status::ok: {
        imageErrors_->cancel();  // the old mesh's levels
        imageErrorsAfterMeasure_ = false;
        stopMeasuring();
        model_ = result.model;
        widgets::LevelData original;
        original.index = 0;
        original.triangles = model_->mesh.triangle_count();
        original.vertices = model_->mesh.vertex_count();
        original.mesh = std::shared_ptr<const lodforge::Mesh>(model_, &model_->mesh);
        original.scene = model_->scene;
        {
            const QSignalBlocker b1(heatmapAction_), b2(compareAction_);
            heatmapAction_->setChecked(false);
            compareAction_->setChecked(false);
        }
        levels_->setCompareVisible(false);
        rangeBox_->setValue(0.0);  // a range is a distance of one mesh: the next starts automatic
        levels_->setLevels({original});
        builtPreset_.reset();
        mcoPanel_->setModel(model_);
        octreePanel_->setModel(model_);
        report_->clear();
        stats_->showInfo(model_->info, model_->elapsedMs, model_->warnings);
        params_->setMesh(model_->mesh.triangle_count(), model_->mesh.has_colors(), model_->mesh.has_texcoords());
        setWindowTitle(tr("%1[*] — LodForge Studio").arg(name));
        setWindowFilePath(result.path);
        if (interactive_) addRecentFile(result.path);
        QString message = tr("Loaded %1 in %2 ms").arg(name).arg(model_->elapsedMs);
        if (!model_->warnings.isEmpty()) message += tr(" (%n warning(s), see Statistics)", "", int(model_->warnings.size()));
        statusBar()->showMessage(message);
        appendLog(message);
        for (const QString& w : model_->warnings) appendLog(tr("warning: %1").arg(w));
        updateActions();
        emit loadFinished(true, message);
        return;
    }
    case widgets::LoadResult::Status::cancelled:
        statusBar()->showMessage(tr("Loading %1 cancelled").arg(name), 5000);
        appendLog(tr("Loading %1 cancelled").arg(name));
        emit loadFinished(false, QString());
        return;
    case widgets::LoadResult::Status::failed:
        break;
    }

    statusBar()->showMessage(tr("Could not open %1").arg(name), 10000);
    appendLog(tr("error: %1").arg(result.error));
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

void MainWindow::failTask(const QString& name, const QString& message) {
    appendLog(tr("%1: %2").arg(name, message));
    statusBar()->showMessage(message, 10000);
    showError(tr("%1 failed").arg(name), tr("%1 could not run.").arg(name), message);
    emit jobFinished(name, false, message);
}

void MainWindow::startTask(widgets::Job* job, std::function<void()> onDone) {
    task_ = job;
    connect(job, &widgets::Job::progressChanged, this, [this, job](double fraction, const QString& stage) {
        if (job == task_) onLoadProgress(fraction, stage);
    });
    connect(job, &widgets::Job::finished, this, [this, job, onDone = std::move(onDone)](const widgets::JobResult& r) {
        onTaskFinished(job, r, onDone);
    });
    setBusyUi(true, job->name() + tr(" %p%"));
    statusBar()->showMessage(tr("%1…").arg(job->name()));
    appendLog(tr("%1 started").arg(job->name()));
    job->start();
}

void MainWindow::onTaskFinished(widgets::Job* job, const widgets::JobResult& result,
                                const std::function<void()>& onDone) {
    job->deleteLater();
    if (job == task_) task_ = nullptr;
    setBusyUi(job_ != nullptr);
    widgets::JobResult::Status status = result.status;
    // Cancelled (e.g. by opening another file) but done before it noticed: its output is stale.
    if (status == widgets::JobResult::Status::ok && job->isCancelling()) status = widgets::JobResult::Status::cancelled;
    switch (status) {
    case widgets::JobResult::Status::ok: {
        onDone();
        const QString message = tr("%1 done in %2 ms").arg(result.name).arg(result.elapsedMs);
        appendLog(message);
        statusBar()->showMessage(message, 10000);
        updateActions();
        emit jobFinished(result.name, true, message);
        return;
    }
    case widgets::JobResult::Status::cancelled:
        appendLog(tr("%1 cancelled after %2 ms").arg(result.name).arg(result.elapsedMs));
        statusBar()->showMessage(tr("%1 cancelled").arg(result.name), 5000);
        updateActions();
        emit jobFinished(result.name, false, QString());
        return;
    case widgets::JobResult::Status::failed:
        updateActions();
        failTask(result.name, result.error);
        return;
    }
}

void MainWindow::buildLodChain() {
    const QString name = lodChainJobName();
    if (!model_) return failTask(name, tr("open a mesh first"));
    if (isBusy()) return failTask(name, tr("another job is running; wait for it or cancel it"));
    const lodforge::Preset preset = params_->preset();
    stopMeasuring();  // the levels it measures are about to go

    const widgets::LevelData original = levels_->levels().front();
    struct Output {
        std::vector<widgets::LevelData> levels;
    };
    auto out = std::make_shared<Output>();
    auto images = model_->images;
    auto* job = new widgets::Job(
        name, [out, original, preset, images](lodforge::Progress* p) {
            out->levels = widgets::buildLodLevels(original, preset, images, p);
        },
        this);
    const QString meshName = QFileInfo(currentFile()).fileName();
    startTask(job, [this, out, preset, meshName] {
        {
            const QSignalBlocker block(heatmapAction_);
            heatmapAction_->setChecked(false);
        }
        levels_->setSwitchParams(preset.switching);
        levels_->setLevels(out->levels, false);
        builtPreset_ = preset;
        updateStale();  // the parameters may have moved on while it built
        report_->setReport(meshName, QString::fromStdString(preset.name), widgets::methodDisplayName(preset.method),
                           out->levels);
        for (const widgets::LevelData& l : out->levels) {
            if (l.index == 0) continue;
            appendLog(tr("  LOD %1: %2 triangles, %3 vertices, %4 ms, %5")
                          .arg(l.index)
                          .arg(l.triangles)
                          .arg(l.vertices)
                          .arg(l.buildMs, 0, 'f', 1)
                          .arg(l.stopReason)
                      + (l.missedTarget ? tr(", target %1 missed").arg(l.targetTriangles) : QString())
                      + (l.sameAs > 0 ? tr(", same as LOD %1").arg(l.sameAs) : QString()));
        }
        if (!out->levels.empty() && !out->levels.front().structureSummary.isEmpty())
            appendLog(QStringLiteral("  ") + out->levels.front().structureSummary);
        explainMissingCells();
        // The measure first (the labels wait for it), the image errors once it ends: both want both cores.
        imageErrorsAfterMeasure_ = true;
        measureLevels(false);
        if (!measure_) requestImageErrors();
    });
}

void MainWindow::stopMeasuring() {
    if (!measure_) return;
    measure_->cancel();  // it deletes itself when it ends (finished below)
    measure_ = nullptr;
    ++measureSerial_;
    levels_->setMeasuring(false);
    setBusyUi(job_ || task_);
}

void MainWindow::measureLevels(bool full) {
    stopMeasuring();
    const std::vector<widgets::LevelData> levels = levels_->levels();
    if (levels.size() < 2) return;
    const quint64 serial = ++measureSerial_;
    auto* job = new widgets::Job(
        measureName(full),
        [this, levels, full, serial](lodforge::Progress* p) {
            widgets::measureLevels(levels, full, [this, serial](const widgets::LevelMeasure& m) {
                // To the GUI thread; `this` outlives the job (~Job waits for its worker).
                QMetaObject::invokeMethod(
                    this, [this, serial, m] {
                        if (serial != measureSerial_ || !measure_ || measure_->isCancelling()) return;
                        levels_->setLevelMeasure(m);
                        report_->setLevelMeasure(m);
                        appendLog(tr("  LOD %1: error %2 (%3 % of the diagonal)%4")
                                      .arg(m.level)
                                      .arg(m.error, 0, 'g', 4)
                                      .arg(100.0 * m.errorRelative, 0, 'f', 4)
                                      .arg(m.measured == widgets::Measured::sampled ? tr(", sampled") : QString()));
                        emit levelMeasured(m.level);
                    },
                    Qt::QueuedConnection);
            }, p);
        },
        this);
    measure_ = job;
    levels_->setMeasuring(true);
    connect(job, &widgets::Job::progressChanged, this, [this, job](double fraction, const QString& stage) {
        if (job == measure_ && !job_ && !task_) onLoadProgress(fraction, stage);
    });
    connect(job, &widgets::Job::finished, this, [this, job](const widgets::JobResult& r) {
        job->deleteLater();
        if (job != measure_) return;  // let go by stopMeasuring
        const bool ok = r.ok() && !job->isCancelling();
        measure_ = nullptr;
        levels_->setMeasuring(false);
        setBusyUi(job_ || task_);
        updateActions();
        if (ok) {
            appendLog(tr("%1 done in %2 ms").arg(r.name).arg(r.elapsedMs));
        } else if (r.status == widgets::JobResult::Status::failed) {
            appendLog(tr("%1: %2").arg(r.name, r.error));
        } else {
            appendLog(tr("%1 cancelled after %2 ms").arg(r.name).arg(r.elapsedMs));
            statusBar()->showMessage(tr("%1 cancelled").arg(r.name), 5000);
        }
        requestImageErrors();
        emit measuringFinished(ok);
    });
    appendLog(tr("%1 started").arg(job->name()));
    setBusyUi(job_ || task_);
    updateActions();
    job->start();
}

void MainWindow::computeHeatmaps() {
    const QString name = heatmapJobName();
    if (!model_) return failTask(name, tr("open a mesh first"));
    if (isBusy()) return failTask(name, tr("another job is running; wait for it or cancel it"));
    auto levels = levels_->levels();
    auto out = std::make_shared<widgets::HeatmapData>();
    auto* job = new widgets::Job(
        name, [out, levels](lodforge::Progress* p) { *out = widgets::computeHeatmaps(levels, p); }, this);
    startTask(job, [this, out] {
        levels_->setHeatmaps(*out);
        levels_->setHeatmapVisible(true);
        const QSignalBlocker block(heatmapAction_);
        heatmapAction_->setChecked(true);
        appendLog(tr("  largest distance to the original: %1").arg(out->maxError, 0, 'g', 4));
    });
}

void MainWindow::exportPack(const QString& directory) {
    const QString name = packJobName();
    if (!model_) return failTask(name, tr("open a mesh first"));
    if (isBusy()) return failTask(name, tr("another job is running; wait for it or cancel it"));
    if (directory.isEmpty()) return failTask(name, tr("no output directory given"));
    lodforge::PackParams params;
    params.preset = params_->preset();
    params.source_path = QFile::encodeName(currentFile()).toStdString();
    params.output_dir = QFile::encodeName(directory).toStdString();
    if (params.preset.exports.image_error) params.image_error = lodforge::render::packImageError();
    auto result = std::make_shared<lodforge::PackResult>();
    auto* job = new widgets::Job(
        name, [params, result](lodforge::Progress* p) {
            // Read as `lodforge pack` reads it (the view's copy places every glTF instance).
            const lodforge::Mesh mesh = lodforge::read_mesh(params.source_path, {}, p);
            *result = lodforge::write_lod_pack(mesh, params, p);
        },
        this);
    startTask(job, [this, result, directory] {
        lastPackFiles_.clear();
        for (const std::string& f : result->files) lastPackFiles_ << QString::fromStdString(f);
        for (std::size_t k = 0; k < result->levels.size(); ++k) {
            const lodforge::PackLevel& l = result->levels[k];
            appendLog(tr("  lod%1: %2 triangles, error %3 % of the diagonal, screen coverage %4, until distance %5")
                          .arg(k)
                          .arg(l.triangles)
                          .arg(100.0 * l.error_relative, 0, 'f', 4)
                          .arg(l.screen_coverage, 0, 'g', 4)
                          .arg(l.switching.godot.range_end, 0, 'g', 4));
        }
        // Levels identical to the one before them are left out (same_surface, the rule the labels' "same
        // as LOD" flag follows): the notes say which.
        for (const std::string& note : result->notes) appendLog(tr("  note: %1").arg(QString::fromStdString(note)));
        appendLog(tr("  wrote %1 to %2").arg(lastPackFiles_.join(QStringLiteral(", ")), directory));
    });
}

void MainWindow::showExportPackDialog() {
    // Beside the last pack (its parent folder), named after this mesh: one folder per mesh.
    const QString last = QSettings().value(packDirKey).toString();
    const QString parent = last.isEmpty() ? defaultExportFolder() : QFileInfo(last).absolutePath();
    const QString name = QFileInfo(currentFile()).completeBaseName() + QStringLiteral("_pack");
    auto* dialog = new OutputFolderDialog(tr("Export LOD pack into"), packDirKey, parent + QLatin1Char('/') + name, this);
    dialog->setAttribute(Qt::WA_DeleteOnClose);
    connect(dialog, &QDialog::accepted, this, [this, dialog] { exportPack(dialog->folder()); });
    dialog->open();
}

void MainWindow::setSideBySide(bool sideBySide) {
    if (sideBySideAction_->isChecked() != sideBySide) {
        sideBySideAction_->setChecked(sideBySide);  // comes back here through toggled
        return;
    }
    levels_->setArrangement(sideBySide ? widgets::LevelViews::Arrangement::sideBySide
                                       : widgets::LevelViews::Arrangement::single);
}

void MainWindow::setHeatmapVisible(bool visible) {
    if (heatmapAction_->isChecked() != visible) {
        heatmapAction_->setChecked(visible);
        return;
    }
    if (visible && !levels_->hasHeatmaps()) {
        {
            const QSignalBlocker block(heatmapAction_);
            heatmapAction_->setChecked(false);  // checked once the maps are there
        }
        computeHeatmaps();
        return;
    }
    levels_->setHeatmapVisible(visible);
}

void MainWindow::setCompareVisible(bool visible) {
    if (compareAction_->isChecked() != visible) {
        compareAction_->setChecked(visible);
        return;
    }
    levels_->setCompareVisible(visible);
    levels_->setSplitPosition(splitSlider_->value() / 1000.0);
}

const lodforge::Preset& MainWindow::preset() const { return params_->preset(); }

void MainWindow::setPreset(const lodforge::Preset& preset, const QString& undoText) {
    const lodforge::Preset before = params_->preset();
    if (before == preset) return;
    undo_->push(new PresetCommand(params_, before, preset, false, undoText.isEmpty() ? tr("Set parameters") : undoText));
}

bool MainWindow::savePreset(const QString& path, QString* error) {
    try {
        lodforge::save_preset(QFile::encodeName(path).toStdString(), params_->preset());
    } catch (const lodforge::Error& e) {
        const QString message = QString::fromUtf8(e.what());
        if (error) *error = message;
        appendLog(tr("error: %1").arg(message));
        showError(tr("Cannot save preset"), tr("Could not save the preset."), message);
        return false;
    }
    presetPath_ = QFileInfo(path).absoluteFilePath();
    undo_->setClean();
    appendLog(tr("Preset saved to %1").arg(path));
    return true;
}

bool MainWindow::loadPreset(const QString& path, QString* error) {
    lodforge::Preset preset;
    try {
        // A file, or a shipped preset by name, as the CLI's --preset takes it.
        preset = lodforge::resolve_preset(QFile::encodeName(path).toStdString());
    } catch (const lodforge::Error& e) {
        const QString message = QString::fromUtf8(e.what());
        if (error) *error = message;
        appendLog(tr("error: %1").arg(message));
        showError(tr("Cannot load preset"), tr("Could not load the preset."), message);
        return false;
    }
    setPreset(preset, tr("Load preset %1").arg(QFileInfo(path).fileName()));
    if (QFileInfo(path).isFile()) presetPath_ = QFileInfo(path).absoluteFilePath();
    undo_->setClean();
    appendLog(tr("Preset loaded from %1").arg(path));
    return true;
}

void MainWindow::showSavePresetDialog() {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save preset"), presetPath_,
                                                      tr("Presets (*.json);;All files (*)"));
    if (!path.isEmpty()) savePreset(path);
}

void MainWindow::showLoadPresetDialog() {
    const QString path = QFileDialog::getOpenFileName(this, tr("Load preset"), presetPath_,
                                                      tr("Presets (*.json);;All files (*)"));
    if (!path.isEmpty()) loadPreset(path);
}

bool MainWindow::exportReport(const QString& path, QString* error) {
    QDir().mkpath(QFileInfo(path).absolutePath());  // a new folder typed with the name
    // Each level shaded and, once the heat maps were computed, as its heat map; the view's state is
    // put back afterwards.
    widgets::ReportImages images;
    if (!report_->isEmpty()) {
        const bool heatmap = levels_->heatmapVisible();
        const bool both = levels_->hasHeatmaps();
        levels_->setHeatmapVisible(false);
        for (int i = 0; i < levels_->levelCount(); ++i) images.shaded << levels_->levelImage(i, QSize(240, 180));
        if (both) {
            levels_->setHeatmapVisible(true);
            for (int i = 0; i < levels_->levelCount(); ++i) images.heatmap << levels_->levelImage(i, QSize(240, 180));
        }
        levels_->setHeatmapVisible(heatmap);
    }
    report_->setParameters(builtPreset_ ? reportParameters(*builtPreset_) : QList<QPair<QString, QString>>{});
    QString message;
    if (!report_->exportTo(path, images, &message)) {
        if (error) *error = message;
        appendLog(tr("error: %1").arg(message));
        showError(tr("Cannot export report"), tr("Could not export the report."), message);
        return false;
    }
    appendLog(tr("Report exported to %1").arg(path));
    return true;
}

bool MainWindow::isComputingImageErrors() const { return imageErrors_->isBusy(); }

void MainWindow::requestImageErrors() {
    if (!std::exchange(imageErrorsAfterMeasure_, false)) return;
    imageErrors_->requestNow();
}

void MainWindow::showExportReportDialog() {
    // Qt's own dialog (the same on every desktop, and driven by the GUI tests; New Folder included), in
    // the folder of the last report.
    auto* dialog = new QFileDialog(this, tr("Export report"),
                                   QSettings().value(reportDirKey, defaultExportFolder()).toString(),
                                   tr("HTML (*.html);;PDF (*.pdf)"));
    dialog->setObjectName(QStringLiteral("reportDialog"));
    dialog->setOption(QFileDialog::DontUseNativeDialog);
    dialog->setAcceptMode(QFileDialog::AcceptSave);
    dialog->setDefaultSuffix(QStringLiteral("html"));
    dialog->setAttribute(Qt::WA_DeleteOnClose);
    if (!currentFile().isEmpty()) dialog->selectFile(QFileInfo(currentFile()).completeBaseName() + QStringLiteral("_report.html"));
    connect(dialog, &QFileDialog::fileSelected, this, [this](const QString& path) {
        if (exportReport(path)) QSettings().setValue(reportDirKey, QFileInfo(path).absolutePath());
    });
    dialog->open();
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
    for (const ViewToggle& t : viewToggles_) {
        const QSignalBlocker block(t.action);
        t.action->setChecked(options.*t.option);
    }
    uvCheckerCells_ = options.uvCheckerCells;
    levels_->setViewOptions(options);
}

widgets::ViewOptions MainWindow::viewOptions() const { return levels_->viewOptions(); }

void MainWindow::applyViewActions() {
    widgets::ViewOptions options;
    for (const ViewToggle& t : viewToggles_) options.*t.option = t.action->isChecked();
    options.uvCheckerCells = uvCheckerCells_;
    levels_->setViewOptions(options);
    explainMissingCells();
}

void MainWindow::setUvCheckerCells(int cells) {
    uvCheckerCells_ = std::clamp(cells, widgets::minUvCheckerCells, widgets::maxUvCheckerCells);
    if (uvCheckerAction_->isChecked()) {
        applyViewActions();
        morph_->setViewOptions(viewOptions());
    } else {
        uvCheckerAction_->setChecked(true);  // applies through toggled
    }
    statusBar()->showMessage(tr("UV checker: %1 × %1 squares per texture unit").arg(uvCheckerCells_), 4000);
}

void MainWindow::explainMissingCells() {
    if (!cellsAction_->isChecked() || levels_->hasCells()) return;
    statusBar()->showMessage(tr("Octree cells: these levels were not cut from an octree; build with the "
                                "Out-of-core octree or Marching-cube octree method to see its cells"),
                             10000);
}

bool MainWindow::levelsStale() const { return levels_->isStale(); }

void MainWindow::setAutoRebuild(bool on) { autoRebuildAction_->setChecked(on); }

bool MainWindow::autoRebuild() const { return autoRebuildAction_->isChecked(); }

void MainWindow::updateStale() {
    const bool stale = builtPreset_ && levels_->levelCount() > 1 &&
                       levelParameters(*builtPreset_) != levelParameters(params_->preset());
    levels_->setStale(stale);
    if (stale && autoRebuild()) rebuildTimer_->start();
}

QAction* MainWindow::singleKeyAction(const QKeyEvent* key) const {
    if (key->key() < Qt::Key_A || key->key() > Qt::Key_Z) return nullptr;
    if (key->modifiers() & ~(Qt::ShiftModifier | Qt::KeypadModifier)) return nullptr;
    const QKeySequence sequence(QKeyCombination(key->modifiers() & Qt::ShiftModifier, Qt::Key(key->key())));
    for (QAction* a : findChildren<QAction*>()) {
        if (a->shortcut() == sequence) return a;
    }
    return nullptr;
}

bool MainWindow::eventFilter(QObject* watched, QEvent* event) {
    if (event->type() != QEvent::ShortcutOverride && event->type() != QEvent::KeyPress)
        return QMainWindow::eventFilter(watched, event);
    auto* widget = qobject_cast<QWidget*>(watched);
    // Only keys bound for this window's widgets (docked or floating), never a dialog's.
    if (!widget || widget != QApplication::focusWidget() || takesText(widget) ||
        (widget->window() != this && !qobject_cast<QDockWidget*>(widget->window())))
        return QMainWindow::eventFilter(watched, event);
    auto* key = static_cast<QKeyEvent*>(event);
    QAction* action = singleKeyAction(key);
    if (!action) return QMainWindow::eventFilter(watched, event);
    // Claim the key from the shortcut map (a spin box would swallow it as text otherwise) and trigger
    // the action on the key press itself: one path whatever the focus widget does with letters.
    if (event->type() == QEvent::ShortcutOverride) {
        event->accept();
        return true;
    }
    if (action->isEnabled()) action->trigger();
    return true;
}

QString MainWindow::documentationPath() {
    const QString installed = QCoreApplication::applicationDirPath() + QStringLiteral("/../share/doc/lodforge/studio.md");
    if (QFileInfo::exists(installed)) return QFileInfo(installed).canonicalFilePath();
#ifdef LODFORGE_DOCS_DIR
    const QString source = QStringLiteral(LODFORGE_DOCS_DIR "/studio.md");
    if (QFileInfo::exists(source)) return QFileInfo(source).canonicalFilePath();
#endif
    return {};
}

void MainWindow::showShortcutsSheet() {
    if (auto* open = findChild<QDialog*>(QStringLiteral("shortcutsSheet"))) {
        open->raise();
        open->activateWindow();
        return;
    }
    auto* sheet = new QDialog(this);
    sheet->setObjectName(QStringLiteral("shortcutsSheet"));
    sheet->setWindowTitle(tr("Keyboard shortcuts"));
    sheet->setAttribute(Qt::WA_DeleteOnClose);
    auto* layout = new QVBoxLayout(sheet);
    auto* table = new QTableWidget(0, 3, sheet);
    table->setObjectName(QStringLiteral("shortcutsTable"));
    table->setHorizontalHeaderLabels({tr("Keys"), tr("Action"), tr("Menu")});
    table->verticalHeader()->hide();
    table->setEditTriggers(QAbstractItemView::NoEditTriggers);
    table->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
    table->horizontalHeader()->setStretchLastSection(true);
    auto addRow = [table](const QString& keys, const QString& what, const QString& where) {
        const int row = table->rowCount();
        table->insertRow(row);
        table->setItem(row, 0, new QTableWidgetItem(keys));
        table->setItem(row, 1, new QTableWidgetItem(what));
        table->setItem(row, 2, new QTableWidgetItem(where));
    };
    // From the menus, so the sheet cannot drift from the keys that work.
    for (QAction* menuAction : menuBar()->actions()) {
        QMenu* menu = menuAction->menu();
        if (!menu) continue;
        const QString where = menu->title().remove(QLatin1Char('&'));
        for (QAction* a : menu->actions()) {
            if (a->shortcuts().isEmpty()) continue;
            QStringList keys;
            for (const QKeySequence& k : a->shortcuts()) keys << k.toString(QKeySequence::NativeText);
            addRow(keys.join(QStringLiteral(", ")), a->text().remove(QLatin1Char('&')).remove(QStringLiteral("…")),
                   where);
        }
    }
    addRow(tr("Left drag"), tr("Rotate the view"), tr("View"));
    addRow(tr("Middle drag, Shift+left drag"), tr("Pan"), tr("View"));
    addRow(tr("Right drag, wheel"), tr("Zoom"), tr("View"));
    layout->addWidget(new QLabel(tr("Single-letter keys work wherever the focus is, except while typing in a "
                                    "text field (the status bar then says so)."),
                                 sheet));
    layout->addWidget(table);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close, sheet);
    connect(buttons, &QDialogButtonBox::rejected, sheet, &QDialog::close);
    layout->addWidget(buttons);
    sheet->resize(560, 640);
    sheet->show();
}

QImage MainWindow::grabWindowImage() {
    QImage image = grab().toImage().convertToFormat(QImage::Format_RGB32);
    // Draw every visible view's framebuffer over its place explicitly, so the shot holds the frames VTK
    // rendered whatever way the widget grab composes OpenGL children.
    QPainter painter(&image);
    for (widgets::VtkView* view : findChildren<widgets::VtkView*>()) {
        if (!view->isVisible()) continue;
        const QImage frame = view->grabFramebuffer();
        if (!frame.isNull()) painter.drawImage(QRect(view->mapTo(this, QPoint(0, 0)), view->size()), frame);
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
    saveSettings();
    if (job_) job_->cancel();
    if (task_) task_->cancel();
    QMainWindow::closeEvent(event);
}

// The morph workspace lives in its own dock with its own views and jobs; the window only hosts it.
void MainWindow::createMorph() {
    morph_ = new widgets::MorphPanel(this);
    morph_->setObjectName(QStringLiteral("morph"));
    morphDock_ = new QDockWidget(tr("Morph"), this);
    morphDock_->setObjectName(QStringLiteral("morphDock"));
    morphDock_->setWidget(morph_);
    addDockWidget(Qt::BottomDockWidgetArea, morphDock_);
    morphDock_->hide();
    connect(morph_, &widgets::MorphPanel::logMessage, this, &MainWindow::appendLog);
    connect(morph_, &widgets::MorphPanel::morphLoaded, this, [this](bool ok, const QString& message) {
        if (!ok && !message.isEmpty())  // empty: cancelled, which is not an error
            showError(tr("Morph failed"), tr("The morph could not be opened or built."), message);
    });
    connect(morph_, &widgets::MorphPanel::landmarkMeshFailed, this, [this](const QString& message) {
        showError(tr("Landmarks failed"), tr("The landmark mesh could not be opened."), message);
    });
    // The View menu's toggles apply to the morph views as well.
    const auto syncViewOptions = [this] { morph_->setViewOptions(viewOptions()); };
    for (const ViewToggle& t : viewToggles_) connect(t.action, &QAction::toggled, this, syncViewOptions);
    connect(morphDock_, &QDockWidget::visibilityChanged, this, syncViewOptions);

    auto showMorph = [this](bool landmarks) {
        morphDock_->show();
        morphDock_->raise();
        if (landmarks) {
            morph_->showLandmarks();
        } else {
            morph_->showAnimation();
        }
    };
    QMenu* menu = new QMenu(tr("&Morph"), this);
    menu->setObjectName(QStringLiteral("menuMorph"));
    menuBar()->insertMenu(menuBar()->actions().constLast(), menu);  // before Help
    QAction* openFile = menu->addAction(tr("Open &morph…"));
    openFile->setObjectName(QStringLiteral("actionOpenMorph"));
    openFile->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_M));
    openFile->setStatusTip(tr("Open a glTF with morph targets or a .lfmorph file and build its LOD"));
    connect(openFile, &QAction::triggered, this, [this, showMorph] {
        const QString path = QFileDialog::getOpenFileName(this, tr("Open morph"), QString(),
                                                          tr("Morphs (*.gltf *.glb *.lfmorph);;All files (*)"));
        if (path.isEmpty()) return;
        showMorph(false);
        morph_->openMorph(path);
    });
    QAction* openSequence = menu->addAction(tr("Open keyframe &sequence…"));
    openSequence->setObjectName(QStringLiteral("actionOpenMorphSequence"));
    openSequence->setShortcut(QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_M));
    openSequence->setStatusTip(tr("Open a directory of OBJ/PLY keyframes with one connectivity and build its LOD"));
    connect(openSequence, &QAction::triggered, this, [this, showMorph] {
        const QString path = QFileDialog::getExistingDirectory(this, tr("Open keyframe sequence"));
        if (path.isEmpty()) return;
        showMorph(false);
        morph_->openMorph(path);
    });
    QAction* landmarks = menu->addAction(tr("&Landmark picking"));
    landmarks->setObjectName(QStringLiteral("actionLandmarks"));
    landmarks->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_K));
    landmarks->setStatusTip(tr("Pick landmark pairs on two meshes for the two-mesh morph"));
    connect(landmarks, &QAction::triggered, this, [showMorph] { showMorph(true); });
    menu->addSeparator();
    menu->addAction(morphDock_->toggleViewAction());
}

}  // namespace lodforge::studio
