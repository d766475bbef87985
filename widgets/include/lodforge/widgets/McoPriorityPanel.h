// The marching-cube octree's priority slider (docs/studio.md, "Marching-cube octree priority"): the
// octree is built from the loaded mesh in the background at the Parameters' resolution, then every
// priority index is one slider step. A move extracts the mesh at that index (McOctreeExtractor, table
// look-ups only) and shows it, with the input's vertex colours, in the single view, labelled with the
// index and the triangle count; the cells overlay shows the cut's nodes at that index.
#pragma once

#include "lodforge/mc_octree.h"
#include "lodforge/preset.h"

#include <QString>
#include <QWidget>

#include <cstddef>
#include <cstdint>
#include <memory>

class QLabel;
class QPushButton;
class QSlider;
class QSpinBox;

namespace lodforge::widgets {

class CoalescedUpdate;
class Job;
class LevelViews;
class MeshScene;
struct LoadedModel;

class McoPriorityPanel : public QWidget {
    Q_OBJECT

public:
    McoPriorityPanel(LevelViews* views, QWidget* parent = nullptr);
    ~McoPriorityPanel() override;

    // A new mesh: the tree of the previous one is dropped (a running build is cancelled).
    void setModel(std::shared_ptr<const LoadedModel> model);
    // Takes the marching-cube resolution of the next build.
    void setPreset(const lodforge::Preset& preset);

    // Builds the tree of the loaded mesh in the background; ends with built().
    void build();
    void cancel();
    bool isBuilding() const { return job_ != nullptr; }
    bool hasTree() const { return tree_ != nullptr; }
    const lodforge::McOctree* tree() const { return tree_.get(); }

    // Extracts and shows the mesh at `priority` (clamped to the tree's range) now, on this thread.
    void setPriority(std::size_t priority);
    // The largest priority whose mesh has at most `triangles` (the tree's cumulative table), shown now.
    void setTriangleBudget(std::uint64_t triangles);
    std::size_t priority() const { return shown_; }
    std::uint64_t triangles() const { return shownTriangles_; }
    std::size_t cutCells() const { return shownCells_; }  // 0 while the cells overlay is off
    double lastExtractMs() const;
    // Where the last update's time went: "extract 3.1 ms, cells 0.2 ms, scene 5.0 ms, cells scene 1.0 ms".
    const QString& timing() const { return timing_; }
    // "Priority 1,234 / 5,000 · 45,678 triangles"
    QString labelText() const;

    QSlider* slider() const { return slider_; }
    QLabel* label() const { return label_; }
    QPushButton* buildButton() const { return buildButton_; }
    QSpinBox* budgetBox() const { return budget_; }

signals:
    void built(bool ok, const QString& message);
    void logMessage(const QString& text);

private:
    void show();
    void updateUi();

    LevelViews* views_;
    std::shared_ptr<const LoadedModel> model_;
    std::size_t resolution_ = 128;
    Job* job_ = nullptr;
    std::shared_ptr<const lodforge::McOctree> tree_;
    std::unique_ptr<lodforge::McOctreeExtractor> extractor_;
    CoalescedUpdate* update_ = nullptr;
    std::size_t shown_ = 0;
    std::uint64_t shownTriangles_ = 0;
    std::size_t shownCells_ = 0;
    bool cellsBuilt_ = false;  // the cells overlay was on when the cut was shown
    QString timing_;

    QPushButton* buildButton_ = nullptr;
    QPushButton* cancelButton_ = nullptr;
    QLabel* status_ = nullptr;
    QSlider* slider_ = nullptr;
    QLabel* label_ = nullptr;
    QSpinBox* budget_ = nullptr;
};

}  // namespace lodforge::widgets
