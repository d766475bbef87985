// The studio's main window: the 3D view, the statistics dock, the File and View menus, background
// loading with progress and Cancel in the status bar, drag and drop, recent files.
#pragma once

#include "lodforge/widgets/ViewOptions.h"

#include <QImage>
#include <QMainWindow>
#include <QStringList>

#include <memory>

class QAction;
class QDockWidget;
class QLabel;
class QMenu;
class QProgressBar;
class QPushButton;

namespace lodforge::widgets {
class LoadJob;
class StatsPanel;
class VtkView;
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
    // stays if loading fails or is cancelled. A load already running is cancelled.
    void openFile(const QString& path);
    void cancelLoading();
    bool isLoading() const;
    // The file whose mesh is shown; empty before the first successful load.
    QString currentFile() const;
    std::shared_ptr<const widgets::LoadedModel> model() const;

    // On by default. Off (--screenshot): a failed load is reported only through loadFinished (no dialog
    // waits for a click) and loads do not change the recent-files list.
    void setInteractive(bool interactive);

    void setViewOptions(const widgets::ViewOptions& options);  // also updates the View menu
    widgets::ViewOptions viewOptions() const;

    QStringList recentFiles() const;

    widgets::VtkView* view() const { return view_; }
    widgets::StatsPanel* statsPanel() const { return stats_; }

    // The whole window as shown, with the 3D view's current frame in place.
    QImage grabWindowImage();

signals:
    // After every load: ok, or the error (empty message when cancelled). Emitted after the view shows the
    // new mesh, or after the error dialog opened.
    void loadFinished(bool ok, const QString& message);

protected:
    void dragEnterEvent(QDragEnterEvent* event) override;
    void dropEvent(QDropEvent* event) override;
    void closeEvent(QCloseEvent* event) override;

private:
    void createActions();
    void createMenus();
    void createStatusBar();
    void showOpenDialog();
    void onLoadProgress(double fraction, const QString& stage);
    void onLoadFinished(widgets::LoadJob* job, const widgets::LoadResult& result);
    void addRecentFile(const QString& path);
    void updateRecentMenu();
    void applyViewActions();
    void setLoadingUi(bool loading);

    widgets::VtkView* view_ = nullptr;
    widgets::StatsPanel* stats_ = nullptr;
    QDockWidget* statsDock_ = nullptr;
    QProgressBar* progressBar_ = nullptr;
    QPushButton* cancelButton_ = nullptr;

    QAction* openAction_ = nullptr;
    QAction* quitAction_ = nullptr;
    QAction* wireframeAction_ = nullptr;
    QAction* flatShadingAction_ = nullptr;
    QAction* texturesAction_ = nullptr;
    QAction* vertexColorsAction_ = nullptr;
    QAction* resetViewAction_ = nullptr;
    QMenu* recentMenu_ = nullptr;

    widgets::LoadJob* job_ = nullptr;  // the load whose result will be shown; older ones are cancelled
    std::shared_ptr<const widgets::LoadedModel> model_;
    bool interactive_ = true;
};

}  // namespace lodforge::studio
