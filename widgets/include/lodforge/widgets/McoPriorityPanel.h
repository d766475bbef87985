// The marching-cube octree's priority slider (docs/studio.md, "Marching-cube octree priority"): the
// octree is built from the loaded mesh in the background at the Parameters' resolution, then every
// priority index is one slider step. A move extracts the mesh at that index (McOctreeExtractor, table
// look-ups only) on a worker and shows it, with the input's vertex colours, in the single view, labelled
// with the index and the triangle count; the cells overlay shows the cut's nodes at that index.
//
// One extraction runs at a time. Moves made while it runs coalesce into one request for the newest index,
// extracted once the worker is free; a result that is no longer the newest request when it arrives is
// dropped, so the view never shows an index the slider has left.
#pragma once

#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/pack/preset.h"
#include "lodforge/widgets/LatestJob.h"

#include <QString>
#include <QWidget>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>

class QLabel;
class QProgressBar;
class QPushButton;
class QSlider;
class QSpinBox;

namespace lodforge::widgets {

class LevelViews;
class MeshScene;
struct JobResult;
struct LoadedModel;

class McoPriorityPanel : public QWidget {
    Q_OBJECT

public:
    McoPriorityPanel(LevelViews* views, QWidget* parent = nullptr);
    // Cancels and waits for its workers (a build, an extraction, and extractions already let go).
    ~McoPriorityPanel() override;

    // A new mesh: the tree of the previous one is dropped (a running build or extraction is cancelled
    // and its result dropped).
    void setModel(std::shared_ptr<const LoadedModel> model);
    // Takes the marching-cube resolution of the next build.
    void setPreset(const lodforge::Preset& preset);

    // Builds the tree of the loaded mesh in the background; ends with built().
    void build();
    // Cancels the build and the extraction; the slider returns to the index shown.
    void cancel();
    bool isBuilding() const;
    bool hasTree() const { return built_ != nullptr; }
    const lodforge::McOctree* tree() const;
    // The tree shared with the workers: expires once the panel and every worker have let it go.
    std::weak_ptr<const lodforge::McOctree> treeHandle() const;

    // Asks for the mesh at `priority` (clamped to the tree's range); it is extracted on the worker and
    // shown when it arrives (extracted()).
    void setPriority(std::size_t priority);
    // The largest priority whose mesh has at most `triangles` (the tree's cumulative table), asked for.
    void setTriangleBudget(std::uint64_t triangles);
    // Of the mesh in the view.
    std::size_t priority() const { return shown_; }
    std::uint64_t triangles() const { return shownTriangles_; }
    std::size_t cutCells() const { return shownCells_; }  // 0 while the cells overlay is off
    // The index asked for last (the slider's).
    std::size_t requestedPriority() const { return requested_; }
    // An extraction runs or waits for the worker.
    bool isExtracting() const;
    // An extraction job is on the worker now (started, its end not handled yet).
    bool isWorkerBusy() const;
    // Extractions shown, those that ran to the end but were superseded when they arrived (dropped), and
    // those stopped early because a newer request came (cancelled).
    int extractionsRun() const;
    int resultsDropped() const;
    int extractionsCancelled() const;
    // Worker time of the last result shown, and the GUI thread's time to put it in the view.
    double lastExtractMs() const { return lastWorkMs_; }
    double lastShowMs() const { return lastShowMs_; }
    // Where the last update's time went: "extract 3.1 ms, cells 0.2 ms, scene 5.0 ms, cells scene 1.0 ms,
    // view 0.4 ms".
    const QString& timing() const { return timing_; }
    // "MC octree priority 1,234 / 5,000 · 45,678 triangles" (the mesh in the view)
    QString labelText() const;

    QSlider* slider() const { return slider_; }
    QLabel* label() const { return label_; }
    QPushButton* buildButton() const { return buildButton_; }
    QPushButton* cancelButton() const { return cancelButton_; }
    QSpinBox* budgetBox() const { return budget_; }
    QProgressBar* progressBar() const { return progress_; }

signals:
    void built(bool ok, const QString& message);
    // A result is in the view.
    void extracted(std::size_t priority, std::uint64_t triangles);
    void logMessage(const QString& text);

private:
    struct Built;  // the tree, its extractor and the lock that keeps one extraction at a time on it
    struct Request {
        std::size_t priority = 0;
        bool cells = false;
    };
    struct Extraction;

    std::optional<LatestJob::Run> makeBuild();
    void request();
    std::optional<LatestJob::Run> makeExtraction();
    void showExtraction(const Request& request, const Extraction& out);
    void updateUi();
    void updateLabel();

    LevelViews* views_;
    std::shared_ptr<const LoadedModel> model_;
    std::size_t resolution_ = 128;
    LatestJob* build_ = nullptr;  // the tree's build
    std::shared_ptr<Built> built_;
    LatestJob* extraction_ = nullptr;  // the newest request's extraction (coalesced, superseded ones cancelled)
    Request newest_;                   // what the next extraction extracts
    std::size_t requested_ = 0;
    std::size_t shown_ = 0;
    std::uint64_t shownTriangles_ = 0;
    std::size_t shownCells_ = 0;
    bool cellsBuilt_ = false;  // the cells overlay was on when the cut was shown
    double lastWorkMs_ = 0;
    double lastShowMs_ = 0;
    QString timing_;

    QPushButton* buildButton_ = nullptr;
    QPushButton* cancelButton_ = nullptr;
    QLabel* status_ = nullptr;
    QProgressBar* progress_ = nullptr;
    QSlider* slider_ = nullptr;
    QLabel* label_ = nullptr;
    QSpinBox* budget_ = nullptr;
};

}  // namespace lodforge::widgets
