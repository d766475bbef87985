// The studio's main window: the level views (one level with a slider, or all side by side in one
// camera; heat maps; a split compare), the Statistics, Parameters, Report and Log docks, the File, Edit,
// LOD and View menus, background jobs (loading, LOD chains, heat maps) with progress and Cancel in the
// status bar, presets with undo/redo, report export, drag and drop, recent files, persisted layout.
#pragma once

#include "lodforge/pack/preset.h"
#include "lodforge/widgets/ViewOptions.h"

#include <QImage>
#include <QList>
#include <QMainWindow>
#include <QStringList>

#include <functional>
#include <memory>
#include <optional>

class QAction;
class QDockWidget;
class QDoubleSpinBox;
class QLabel;
class QKeyEvent;
class QMenu;
class QPlainTextEdit;
class QProgressBar;
class QPushButton;
class QSlider;
class QTimer;
class QUndoStack;

namespace lodforge::widgets {
class Job;
class LatestJob;
class LevelViews;
class LoadJob;
class McoPriorityPanel;
class OctreeTuningPanel;
class MorphPanel;
class ParametersPanel;
class ReportPanel;
class StatsPanel;
class VtkView;
struct JobResult;
struct LoadedModel;
struct LoadResult;
}  // namespace lodforge::widgets

namespace lodforge::studio {

class MainWindow : public QMainWindow {
    Q_OBJECT

public:
    static constexpr int maxRecentFiles = 10;

    explicit MainWindow(QWidget* parent = nullptr);
    ~MainWindow() override;

    // Loads `path` in the background. The current mesh stays on screen until the new one is ready, and
    // stays if loading fails or is cancelled. A load already running is cancelled, and so is a LOD job.
    void openFile(const QString& path);
    // Cancels the load or the job that is running (the Cancel button, Esc).
    void cancelLoading();
    bool isLoading() const;
    bool isBusy() const;  // a load or a job runs
    // The file whose mesh is shown; empty before the first successful load.
    QString currentFile() const;
    std::shared_ptr<const widgets::LoadedModel> model() const;

    // On by default. Off (--screenshot, tests): failures are reported only through loadFinished and
    // jobFinished (no dialog waits for a click) and loads do not change the recent-files list.
    void setInteractive(bool interactive);

    void setViewOptions(const widgets::ViewOptions& options);  // also updates the View menu
    widgets::ViewOptions viewOptions() const;

    // Jobs on the loaded mesh, in the background; each ends with jobFinished. Refused (jobFinished with
    // ok = false) when no mesh is loaded, or another job runs.
    void buildLodChain();
    void computeHeatmaps();
    // The levels' errors, measured after they show (a built chain starts the quick measure itself), on
    // a worker of their own beside any job: each level's label and report row fill in as it is done
    // (levelMeasured), the status bar shows the progress per level and Cancel stops it. `full`: at full
    // precision (LOD > Measure at full precision); else with the quick sample budget
    // (widgets::measureLevels). A new chain, a new mesh or another measure cancels the running one.
    void measureLevels(bool full = false);
    bool isMeasuring() const { return measure_ != nullptr; }
    static QString lodChainJobName();
    static QString heatmapJobName();

    // The parameters being edited. setPreset is one undoable step (as loading a preset is).
    const lodforge::Preset& preset() const;
    void setPreset(const lodforge::Preset& preset, const QString& undoText = {});
    bool savePreset(const QString& path, QString* error = nullptr);
    bool loadPreset(const QString& path, QString* error = nullptr);
    QUndoStack* undoStack() const { return undo_; }

    // Writes the LOD pack of the loaded file with the current preset into `directory`, in the background
    // (lodforge::write_lod_pack, the function `lodforge pack` calls: the file is read again exactly as the
    // CLI reads it, so the same preset gives the same pack). Ends with jobFinished(packJobName()).
    void exportPack(const QString& directory);
    static QString packJobName();
    // Files of the last pack written (relative to its directory), empty before.
    QStringList lastPackFiles() const { return lastPackFiles_; }

    // The report of the last LOD chain with the parameters and per level its picture and, once computed, its
    // heat map: HTML, or PDF for a .pdf path. A missing folder in `path` is created.
    bool exportReport(const QString& path, QString* error = nullptr);
    // The levels' image-space errors are being computed in the background (imageErrorsSettled at the end).
    bool isComputingImageErrors() const;

    // Side by side (all levels in synchronised views) or one level with the slider.
    void setSideBySide(bool sideBySide);
    void setHeatmapVisible(bool visible);  // computes the heat maps first when needed
    void setCompareVisible(bool visible);

    QStringList recentFiles() const;

    widgets::VtkView* view() const;  // the single-level view
    widgets::LevelViews* levelViews() const { return levels_; }
    widgets::StatsPanel* statsPanel() const { return stats_; }
    widgets::ParametersPanel* parametersPanel() const { return params_; }
    widgets::ReportPanel* reportPanel() const { return report_; }
    QPlainTextEdit* logView() const { return log_; }
    // The structure inspectors (docs/studio.md): the MC octree's priority slider, the octree's tuning
    // and view-dependent cut.
    widgets::McoPriorityPanel* mcoPriorityPanel() const { return mcoPanel_; }
    widgets::OctreeTuningPanel* octreeTuningPanel() const { return octreePanel_; }
    // The Morph dock (docs/studio.md, "Morph"): morph playback with LOD and landmark picking.
    widgets::MorphPanel* morphPanel() const { return morph_; }
    QDockWidget* morphDock() const { return morphDock_; }

    // The whole window as shown, with the 3D views' current frames in place.
    QImage grabWindowImage();

    // The levels shown were built with other parameters than the current ones (LevelViews::isStale).
    bool levelsStale() const;
    // LOD > Rebuild automatically (persisted): a parameter change that makes the levels stale rebuilds
    // them 500 ms after the last change, once no job runs.
    void setAutoRebuild(bool on);
    bool autoRebuild() const;
    // Help > Keyboard shortcuts: every action with its keys, generated from the actions themselves.
    void showShortcutsSheet();
    // Help > Documentation: docs/studio.md as installed (share/doc/lodforge) or in the source tree.
    static QString documentationPath();

signals:
    // After every load: ok, or the error (empty message when cancelled). Emitted after the view shows the
    // new mesh, or after the error dialog opened.
    void loadFinished(bool ok, const QString& message);
    // After every job (lodChainJobName(), heatmapJobName()): ok, or the error (empty when cancelled).
    void jobFinished(const QString& name, bool ok, const QString& message);
    // measureLevels: after each level (in level order), and once at the end (ok false: cancelled).
    void levelMeasured(int level);
    void measuringFinished(bool ok);
    // The background image-error job went idle (done, failed or cancelled).
    void imageErrorsSettled();

protected:
    // Single-letter shortcuts work whatever has focus in this window (spin boxes, sliders, lists),
    // except in a field that takes text, where they type (the status bar says so while it has focus).
    bool eventFilter(QObject* watched, QEvent* event) override;
    void dragEnterEvent(QDragEnterEvent* event) override;
    void dropEvent(QDropEvent* event) override;
    void closeEvent(QCloseEvent* event) override;

private:
    void createActions();
    void createMenus();
    void createToolBar();
    void createDocks();
    void createStatusBar();
    void createStructurePanels();
    void createMorph();  // the Morph dock and menu
    void restoreSettings();
    void saveSettings();
    void showOpenDialog();
    void showSavePresetDialog();
    void showLoadPresetDialog();
    void showExportReportDialog();
    void showExportPackDialog();
    void onLoadProgress(double fraction, const QString& stage);
    void onLoadFinished(widgets::LoadJob* job, const widgets::LoadResult& result);
    void addRecentFile(const QString& path);
    void updateRecentMenu();
    void applyViewActions();
    // The cells overlay is on but the levels shown carry no cells: say why in the status bar.
    void explainMissingCells();
    void setBusyUi(bool busy, const QString& format = {});
    // After a parameter change: marks the levels stale (or fresh again, after undo) and schedules the
    // automatic rebuild.
    void updateStale();
    QAction* singleKeyAction(const QKeyEvent* key) const;
    void updateActions();
    void appendLog(const QString& text);
    void showError(const QString& title, const QString& text, const QString& details);
    // Starts `job` as the running task; `onDone` runs on success before jobFinished is emitted.
    void startTask(widgets::Job* job, std::function<void()> onDone);
    void failTask(const QString& name, const QString& message);
    void stopMeasuring();  // lets the running measure go; its results no longer show
    void onTaskFinished(widgets::Job* job, const widgets::JobResult& result, const std::function<void()>& onDone);

    widgets::LevelViews* levels_ = nullptr;
    widgets::StatsPanel* stats_ = nullptr;
    widgets::ParametersPanel* params_ = nullptr;
    widgets::ReportPanel* report_ = nullptr;
    // The report's image-space errors, rendered beside the main task (they need no job slot).
    widgets::LatestJob* imageErrors_ = nullptr;
    // A chain was built: its image errors follow the end of its measure (requestImageErrors).
    bool imageErrorsAfterMeasure_ = false;
    void requestImageErrors();
    QPlainTextEdit* log_ = nullptr;
    QDockWidget* statsDock_ = nullptr;
    QDockWidget* paramsDock_ = nullptr;
    QDockWidget* reportDock_ = nullptr;
    QDockWidget* logDock_ = nullptr;
    widgets::McoPriorityPanel* mcoPanel_ = nullptr;
    widgets::OctreeTuningPanel* octreePanel_ = nullptr;
    QProgressBar* progressBar_ = nullptr;
    QPushButton* cancelButton_ = nullptr;
    QDoubleSpinBox* rangeBox_ = nullptr;
    QSlider* splitSlider_ = nullptr;
    QUndoStack* undo_ = nullptr;
    widgets::MorphPanel* morph_ = nullptr;
    QDockWidget* morphDock_ = nullptr;

    QAction* openAction_ = nullptr;
    QAction* quitAction_ = nullptr;
    QAction* loadPresetAction_ = nullptr;
    QAction* savePresetAction_ = nullptr;
    QAction* exportReportAction_ = nullptr;
    QAction* exportPackAction_ = nullptr;
    QAction* undoAction_ = nullptr;
    QAction* redoAction_ = nullptr;
    QAction* buildAction_ = nullptr;
    QAction* cancelAction_ = nullptr;
    QAction* measureFullAction_ = nullptr;
    QAction* sideBySideAction_ = nullptr;
    QAction* heatmapAction_ = nullptr;
    QAction* compareAction_ = nullptr;
    QAction* nextLevelAction_ = nullptr;
    QAction* previousLevelAction_ = nullptr;
    QAction* wireframeAction_ = nullptr;
    QAction* flatShadingAction_ = nullptr;
    QAction* texturesAction_ = nullptr;
    QAction* vertexColorsAction_ = nullptr;
    QAction* edgesAction_ = nullptr;
    QAction* normalColorsAction_ = nullptr;
    QAction* uvCheckerAction_ = nullptr;
    QAction* heatmapOutlineAction_ = nullptr;
    QAction* uvFinerAction_ = nullptr;
    QAction* uvCoarserAction_ = nullptr;
    int uvCheckerCells_ = widgets::ViewOptions{}.uvCheckerCells;
    void setUvCheckerCells(int cells);  // turns the checker on; the status bar says the density
    QAction* cellsAction_ = nullptr;
    QAction* cellsByTrianglesAction_ = nullptr;
    QAction* resetViewAction_ = nullptr;
    QAction* autoRebuildAction_ = nullptr;
    QAction* shortcutsAction_ = nullptr;
    QAction* docsAction_ = nullptr;
    QLabel* typingHint_ = nullptr;
    QTimer* rebuildTimer_ = nullptr;
    // The parameters the levels shown were built with; none before the first chain of the mesh.
    std::optional<lodforge::Preset> builtPreset_;
    QMenu* recentMenu_ = nullptr;
    // Each View toggle with the option it sets and its settings key.
    struct ViewToggle {
        QAction* action;
        bool widgets::ViewOptions::*option;
        QString key;
    };
    QList<ViewToggle> viewToggles_;

    widgets::LoadJob* job_ = nullptr;  // the load whose result will be shown; older ones are cancelled
    widgets::Job* task_ = nullptr;     // the LOD chain or heat map job running, if any
    widgets::Job* measure_ = nullptr;  // the levels' measure running, if any (beside task_)
    quint64 measureSerial_ = 0;        // of the newest measure; results of older ones are dropped
    std::shared_ptr<const widgets::LoadedModel> model_;
    QString presetPath_;
    QStringList lastPackFiles_;
    bool interactive_ = true;
};

}  // namespace lodforge::studio
