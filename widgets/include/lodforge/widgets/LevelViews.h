// The studio's central area: the levels of detail of one mesh, either one at a time with a level slider
// or side by side in synchronised views (one camera: moving one moves all), each labelled with its
// triangle count and error; optionally as error heat maps, or split between the original and a level.
#pragma once

#include "lodforge/pack/switch_points.h"
#include "lodforge/widgets/LodLevels.h"
#include "lodforge/widgets/ViewOptions.h"

#include <QImage>
#include <QList>
#include <QWidget>

#include <memory>
#include <vector>

class QCheckBox;
class QGridLayout;
class QLabel;
class QSlider;
class QStackedWidget;

namespace lodstrips {
class LodStrips;
}

namespace lodforge::widgets {

class VtkView;

class LevelViews : public QWidget {
    Q_OBJECT

public:
    enum class Arrangement { single, sideBySide };

    explicit LevelViews(QWidget* parent = nullptr);
    ~LevelViews() override;

    // Levels 0..N, level 0 the original. Only the original: the slider has nothing to choose. Drops the
    // heat maps; the current level becomes the last one (or stays when the count is unchanged).
    void setLevels(std::vector<LevelData> levels, bool resetCamera = true);
    // A level's error, measured after the levels showed (measureLevels): its labels follow.
    void setLevelMeasure(const LevelMeasure& measure);
    // A measure runs: levels not measured yet read "error measuring…" rather than "error not measured".
    void setMeasuring(bool measuring);
    const std::vector<LevelData>& levels() const { return levels_; }
    int levelCount() const { return int(levels_.size()); }

    void setArrangement(Arrangement arrangement);
    Arrangement arrangement() const { return arrangement_; }

    void setCurrentLevel(int level);
    int currentLevel() const { return current_; }

    // Heat maps of the current levels (computeHeatmaps); shown while heatmapVisible.
    void setHeatmaps(HeatmapData heatmaps);
    bool hasHeatmaps() const { return !heatmaps_.scenes.empty(); }
    // Whether some level carries a structure's cells (LevelData::cells) for the cells overlay.
    bool hasCells() const;
    const HeatmapData& heatmaps() const { return heatmaps_; }
    void setHeatmapVisible(bool visible);
    bool heatmapVisible() const { return heatmapVisible_; }
    // The distance mapped to the top of the colour map, model units; <= 0: automatic (HeatmapData::autoRange).
    void setHeatmapRange(double maximum);
    double heatmapRange() const;

    // The views split: the original (as loaded, textured) left of the split position, the level (or its
    // heat map) right of it; in the single view, and side by side in every level's tile.
    void setCompareVisible(bool visible);
    bool compareVisible() const { return compareVisible_; }
    void setSplitPosition(double fraction);

    void setViewOptions(const ViewOptions& options);
    const ViewOptions& viewOptions() const { return options_; }
    void resetView();

    VtkView* singleView() const { return single_; }
    QLabel* singleLabel() const { return singleLabel_; }
    QSlider* levelSlider() const { return slider_; }
    // Side by side: tile i shows level i.
    QList<VtkView*> tileViews() const;
    QList<QLabel*> tileLabels() const;

    // Continuous LOD (LODStrips levels only; the row under the single view is hidden otherwise): the
    // slider (0..1000 = factor 0..1, 0 the coarsest stored level) moves the LODStrips runtime and the
    // single view draws its current strips until a stored level is chosen again.
    bool hasContinuousLod() const { return runtime_ != nullptr; }
    bool continuousActive() const { return continuousActive_; }
    void setContinuousFactor(double factor);
    double continuousFactor() const;
    std::size_t continuousTriangles() const;  // the runtime's current count; 0 without a runtime
    // Whether moves only replace the triangles of one full-detail scene (one material, no strip colours
    // needed) rather than rebuilding the scene; known after the first move.
    bool continuousPatchesTriangles() const { return patchable_; }
    // Every strip in its own colour (stripColor) instead of the materials, in the continuous view.
    void setStripColors(bool on);
    bool stripColors() const;
    QSlider* continuousSlider() const { return continuousSlider_; }
    QLabel* continuousLabel() const { return continuousLabel_; }
    QCheckBox* stripColorsBox() const { return stripColors_; }

    // An inspection view in the single view, owned by a panel (the MC octree's priority slider, the
    // octree's view-dependent cut): `scene` with `cells` as its overlay and `label` above it, until its
    // owner clears it, a stored level is chosen or new levels arrive (then inspectionEnded). Side by side
    // and the heat map show the stored levels.
    void setInspection(const QObject* owner, std::shared_ptr<const MeshScene> scene,
                       std::shared_ptr<const MeshScene> cells, const QString& label);
    void clearInspection(const QObject* owner);
    const QObject* inspectionOwner() const { return inspection_.owner; }

    // "LOD 2 · 1,464 / 1,464 triangles · error 0.420 % (0.0061)" (reached / target); a missed target
    // adds "target missed: <stop reason>", an identical earlier level "same as LOD 1", stale levels
    // start with "Stale ·"; "Original · 5,856 triangles". Until measured the error reads "error
    // measuring…" (or "error not measured" when no measure runs), "error ≈ 0.420 % (0.0061)" when
    // measured with the quick sample budget. Once it and every finer level are measured, a level after
    // the original adds where it takes over on the switch screen (setSwitchParams; docs/pack.md, "Switch
    // points"): "takes over at 26 px (distance 90.7)", the sphere's projected diameter and the camera
    // distance.
    QString levelLabelText(int level) const;
    // The screen the switch points in the labels are for (the preset's `switch` block).
    void setSwitchParams(const lodforge::SwitchParams& params);

    // The levels no longer match the parameters (they changed since the build): every label says so
    // and a bar above the views offers Rebuild (rebuildRequested). New levels (setLevels) are fresh.
    void setStale(bool stale);
    bool isStale() const { return stale_; }
    QWidget* staleBar() const { return staleBar_; }

    // Level `level` as the views draw it now (heat map or not), `size` at most; for report thumbnails.
    QImage levelImage(int level, QSize size);

signals:
    void currentLevelChanged(int level);
    // The heat map value under the cursor, as text for the status bar; empty when it left the surface.
    void hoverText(const QString& text);
    void inspectionEnded(const QObject* owner);
    void viewOptionsChanged(const lodforge::widgets::ViewOptions& options);
    void rebuildRequested();  // the stale bar's Rebuild button

private:
    struct Tile {
        QWidget* box = nullptr;
        QLabel* label = nullptr;
        VtkView* view = nullptr;
    };

    std::shared_ptr<const MeshScene> sceneOf(int level) const;
    // The original, for a level's heat map with ViewOptions::heatmapOutline; nullptr otherwise.
    std::shared_ptr<const MeshScene> outlineFor(int level) const;
    void showLevelIn(VtkView* view, int level);
    void rebuildTiles();
    void refreshSingle();
    void refreshSingleLabel();
    void refreshLabels();
    QString takeOverText(int level) const;
    void refreshTiles();
    void connectView(VtkView* view, int levelOrCurrent);
    void setupContinuous();
    void showContinuous();
    bool showsContinuous() const;
    void endInspection();

    struct Inspection {
        const QObject* owner = nullptr;
        std::shared_ptr<const MeshScene> scene, cells;
        QString label;
    };
    Inspection inspection_;

    QStackedWidget* stack_ = nullptr;
    QWidget* staleBar_ = nullptr;
    bool stale_ = false;
    bool measuring_ = false;
    lodforge::SwitchParams switching_;
    QWidget* singlePage_ = nullptr;
    QWidget* tilesPage_ = nullptr;
    QGridLayout* grid_ = nullptr;
    VtkView* single_ = nullptr;
    QLabel* singleLabel_ = nullptr;
    QSlider* slider_ = nullptr;
    QList<Tile> tiles_;
    QWidget* continuousRow_ = nullptr;
    QSlider* continuousSlider_ = nullptr;
    QLabel* continuousLabel_ = nullptr;
    QCheckBox* stripColors_ = nullptr;
    std::unique_ptr<lodstrips::LodStrips> runtime_;
    std::shared_ptr<const ContinuousLodData> continuousData_;
    std::shared_ptr<const MeshScene> continuousScene_;
    std::shared_ptr<const MeshScene> fullStrips_;  // every runtime vertex; its triangles follow the runtime
    bool patchable_ = false;
    bool continuousActive_ = false;

    std::vector<LevelData> levels_;
    HeatmapData heatmaps_;
    Arrangement arrangement_ = Arrangement::single;
    int current_ = 0;
    bool heatmapVisible_ = false;
    double heatmapRange_ = 0;
    bool compareVisible_ = false;
    double split_ = 0.5;
    ViewOptions options_;
};

}  // namespace lodforge::widgets
