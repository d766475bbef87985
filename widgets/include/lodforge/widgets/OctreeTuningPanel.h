// The out-of-core octree's tuning and view-dependent cut (docs/studio.md, "Octree tuning"):
//  - the tree's cells over the original (every node; the cells overlay's depth / triangle colours);
//  - statistics (nodes, leaves, depth reached, triangles per level) of the octree the Parameters' knobs
//    give, rebuilt in the background, debounced and cancellable, whenever max triangles per leaf or max
//    depth change (once a first build was asked for);
//  - a view-dependent cut of that asset in the single view: each node's level chosen by its projected
//    screen-space error from the current camera (select_cut), updated when the camera moves, its nodes
//    drawn as the cells overlay coloured by their level. The cut, its mesh and its scene are made on a
//    worker (on the dragon a fine cut reads and draws 870 k triangles); requests made meanwhile coalesce
//    into one for the newest camera, and a result that is not the newest request when it arrives is
//    dropped;
//  - one picked node's level scrubbed coarser or finer, the rest of the cut adjusted so that it stays a
//    valid (crack-free) cut.
#pragma once

#include "lodforge/mesh.h"
#include "lodforge/octree/octree_build.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/pack/preset.h"
#include "lodforge/widgets/LatestJob.h"

#include <QPoint>
#include <QWidget>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>

class QCheckBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QSlider;
class QTableWidget;
class QTemporaryDir;
class QTimer;

namespace lodforge::widgets {

class LevelViews;
struct LoadedModel;

class OctreeTuningPanel : public QWidget {
    Q_OBJECT

public:
    static constexpr int debounceMs = 400;  // knob changes closer than this make one rebuild

    OctreeTuningPanel(LevelViews* views, QWidget* parent = nullptr);
    ~OctreeTuningPanel() override;

    // A new mesh: the asset of the previous one is dropped (a running build is cancelled).
    void setModel(std::shared_ptr<const LoadedModel> model);
    // The Parameters' octree knobs; a change schedules a rebuild (debounced) once an asset was built or
    // asked for.
    void setPreset(const lodforge::Preset& preset);

    // Builds now with the current knobs (cancelling a running build); ends with built().
    void build();
    void cancel();
    bool isBuilding() const;
    bool rebuildPending() const;
    bool hasAsset() const { return store_ != nullptr; }
    // Of the asset shown (valid when hasAsset()). The store's node table may be read on this thread while
    // a cut reads node meshes on the worker; node meshes are read only there.
    const lodforge::OctreeStats& stats() const { return stats_; }
    const lodforge::OctreeBuildParams& builtParams() const { return builtParams_; }
    lodforge::OctreeStore* store() const { return store_.get(); }
    // "1,234 nodes · 1,000 leaves · depth 6 reached (max 8) · ≤ 300 triangles per leaf"
    QString statsText() const;

    // The whole tree's cells (every node, coloured by depth or by the triangles under it) over the
    // original in the single view, after every build while the view-dependent cut is off (on by default).
    void setShowTree(bool on);
    bool showTree() const;

    // The view-dependent cut in the single view.
    void setViewDependent(bool on);
    bool viewDependent() const { return viewDependent_; }
    void setScreenError(double pixels);
    double screenError() const;
    void setFrustumCulling(bool on);
    // Asks for the cut of the current camera (the camera signal does it coalesced); it is made on the
    // worker and shown when it arrives (cutUpdated()). A running cut is cancelled: its result would be
    // superseded.
    void updateCut();
    // A cut is asked for and not shown yet.
    bool isCutting() const;
    // A cut job is on the worker now (started, its end not handled yet).
    bool isCutWorkerBusy() const;
    // The store shared with the workers: expires once the panel and every worker have let it go.
    std::weak_ptr<const lodforge::OctreeStore> storeHandle() const { return store_; }
    // Cuts shown, and those dropped (superseded or cancelled) since the panel was made.
    int cutsShown() const;
    int cutsDropped() const;
    const lodforge::Cut& cut() const { return cut_; }
    std::uint64_t cutTriangles() const { return cutMesh_.triangle_count(); }
    const lodforge::Mesh& cutMesh() const { return cutMesh_; }

    // Scrubbing one node: pin the cut's node under `position` of the single view (false when no surface
    // or node is there), or a node by index; then coarser / finer. A node's level: 0 = its input
    // triangles (leaves), h + 1 = its simplified mesh (h its height); coarser than its own simplified
    // mesh moves the pin to its parent.
    bool pickNodeAt(QPoint position);
    bool pinNode(std::uint32_t node, int level);
    void coarser();
    void finer();
    void unpin();
    std::optional<std::uint32_t> pinnedNode() const;
    int pinnedLevel() const { return pinLevel_; }

    QTableWidget* levelTable() const { return levels_; }
    QLabel* statsLabel() const { return statsLabel_; }
    QLabel* cutLabel() const { return cutLabel_; }
    QSlider* screenErrorSlider() const { return screenSlider_; }

signals:
    void built(bool ok, const QString& message);
    void cutUpdated();
    void logMessage(const QString& text);

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

private:
    void startBuild();
    std::optional<LatestJob::Run> makeBuild();
    void showStats();
    void updateUi();
    std::optional<LatestJob::Run> makeCut();
    void showTreeCells();

    LevelViews* views_;
    std::shared_ptr<const LoadedModel> model_;
    lodforge::OctreeBuildParams params_;       // of the next build
    lodforge::OctreeBuildParams builtParams_;  // of the asset shown
    bool wanted_ = false;                      // a build was asked for: knob changes rebuild
    LatestJob* build_ = nullptr;
    QTimer* debounce_ = nullptr;
    std::shared_ptr<QTemporaryDir> dir_;  // holds the asset while the store reads it
    std::shared_ptr<lodforge::OctreeStore> store_;  // shared with the cut's worker
    std::shared_ptr<std::mutex> storeLock_;          // one cut at a time reads node meshes (the cache)
    lodforge::OctreeStats stats_;

    bool viewDependent_ = false;
    bool culling_ = true;
    LatestJob* cutJob_ = nullptr;  // the newest camera's cut (coalesced, superseded ones cancelled)
    int cutProgressStep_ = -1;     // of the running cut, in tenths
    lodforge::Cut cut_;
    lodforge::Mesh cutMesh_;
    std::uint32_t pin_ = UINT32_MAX;
    int pinLevel_ = 0;

    QPushButton* buildButton_ = nullptr;
    QPushButton* cancelButton_ = nullptr;
    QLabel* status_ = nullptr;
    QLabel* statsLabel_ = nullptr;
    QTableWidget* levels_ = nullptr;
    QCheckBox* treeBox_ = nullptr;
    QCheckBox* viewDependentBox_ = nullptr;
    QCheckBox* cullingBox_ = nullptr;
    QSlider* screenSlider_ = nullptr;
    QLabel* screenValue_ = nullptr;
    QPushButton* pickButton_ = nullptr;
    QPushButton* coarserButton_ = nullptr;
    QPushButton* finerButton_ = nullptr;
    QLabel* cutLabel_ = nullptr;
};

}  // namespace lodforge::widgets
