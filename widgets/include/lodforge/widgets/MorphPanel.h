// The studio's morph workspace (issue 8; docs/studio.md, "Morph"): a morphing mesh played and scrubbed
// in time t and LOD factor F independently, a heat map of each frame's LOD error, and the landmark
// picking of the two-mesh case (LandmarkPicker).
//
// Everything it shows comes from the core functions `lodforge morph` uses: load_morph + build_morph_lod
// (the CLI's `morph build` defaults) or read_morph_lod for a .lfmorph file, then extract_morph(t, F) —
// the view draws what `lodforge morph extract IN --t T --lod F` writes.
#pragma once

#include "lodforge/morph/landmarks.h"
#include "lodforge/mesh.h"
#include "lodforge/morph/morph.h"
#include "lodforge/morph/morph_lod.h"
#include "lodforge/progress.h"
#include "lodforge/widgets/LatestJob.h"
#include "lodforge/widgets/ViewOptions.h"

#include <QString>
#include <QTimer>
#include <QWidget>

#include <cstddef>
#include <functional>
#include <memory>

class QCheckBox;
class QLabel;
class QProgressBar;
class QPushButton;
class QSlider;
class QTabWidget;

namespace lodforge::widgets {

class LandmarkPicker;
class VtkView;

// A loaded morph with its LOD, shared read-only with the background jobs.
struct MorphData {
    lodforge::MorphMesh morph;
    lodforge::MorphLod lod;
    QString source;
};

class MorphPanel : public QWidget {
    Q_OBJECT

public:
    static constexpr int sliderSteps = 1000;  // t and F sliders: 0..1000 = 0..1
    static constexpr int playIntervalMs = 40;
    static constexpr double playLoopSeconds = 4.0;  // Play runs t from 0 to 1 in this time, then loops

    explicit MorphPanel(QWidget* parent = nullptr);
    ~MorphPanel() override;

    // Opens a keyframe sequence directory, a glTF with morph targets or a .lfmorph file in the
    // background and builds its LOD (not for .lfmorph, which stores it), with progress and Cancel.
    // Ends with morphLoaded. A morph job already running is cancelled.
    void openMorph(const QString& path);
    // The CLI's --close-seams for the LOD build (flat-shaded glTF samples need it to simplify at all).
    void setCloseSeams(bool close);
    void cancel();
    bool isBusy() const;
    std::shared_ptr<const MorphData> data() const { return data_; }

    // Time in [0, 1] across the whole sequence and LOD factor in [0, 1] (0 the coarsest stored level,
    // 1 full detail); clamped. The view shows extract_morph(t, F) at once; the heat map follows in the
    // background.
    void setTime(double t);
    double time() const { return t_; }
    void setLodFactor(double f);
    double lodFactor() const { return f_; }
    void setPlaying(bool playing);
    bool isPlaying() const;
    // Per-vertex distance of the full-detail mesh at t to the LOD mesh at t, on the full mesh (viridis).
    void setHeatmapVisible(bool visible);
    bool heatmapVisible() const { return heat_; }
    // The heat map shown is of the current (t, F) (false while one is being computed).
    bool heatmapCurrent() const;
    double heatmapMaxError() const { return heatMax_; }  // model units, of the heat map shown
    double heatmapTime() const { return heatT_; }         // t of the heat map shown (-1: none)

    std::size_t triangleCount() const { return triangles_; }  // of the LOD mesh at (t, F)
    QString timeText() const;
    QString lodText() const;
    VtkView* view() const { return view_; }
    LandmarkPicker* landmarkPicker() const { return picker_; }
    // The main View menu's toggles (wireframe, edges, flat shading, ...) for the morph and landmark views.
    void setViewOptions(const ViewOptions& options);
    void showLandmarks();  // the Landmarks tab
    void showAnimation();  // the Animation tab

    // --- Case (b) ----------------------------------------------------------------------------------
    // The supermesh of two genus-0 meshes aligned by landmark pairs (issue 8, case (b); supermesh.h), as
    // a MorphMesh with two keyframes, built with the CLI's defaults; sources name the files in errors.
    // The Build supermesh button then builds its LOD and plays it like any other morph.
    static bool supermeshBuilderConnected();
    static lodforge::MorphMesh build_supermesh(const lodforge::Mesh& a, const lodforge::Mesh& b,
                                               const lodforge::Landmarks& landmarks, const std::string& sourceA,
                                               const std::string& sourceB, lodforge::Progress* progress);
    static QString supermeshUnavailableReason();

signals:
    // After every openMorph: ok, or the error (empty when cancelled).
    void morphLoaded(bool ok, const QString& message);
    // A landmark mesh (A or B) could not be read; the message names the file.
    void landmarkMeshFailed(const QString& message);
    void frameShown();    // the view shows the mesh at the current (t, F) (heat map off)
    void heatmapShown();  // the heat map of the current (t, F) is shown
    void timeChanged(double t);
    void logMessage(const QString& text);

private:
    using Fill = std::function<void(MorphData&, lodforge::Progress*)>;
    void startMorphJob(const QString& name, const QString& source, Fill fill);
    std::optional<LatestJob::Run> makeMorphJob();
    struct MorphRequest {
        QString name;
        QString source;
        Fill fill;
    };
    std::optional<LatestJob::Run> makeHeatmap();
    void buildSupermeshFromPicks();
    void showOpenDialog(bool directory);
    void showFrame(bool resetCamera = false);
    void startHeatmap();
    void updateLabels();
    void updateControls();
    void advancePlay();

    QTabWidget* tabs_ = nullptr;
    VtkView* view_ = nullptr;
    LandmarkPicker* picker_ = nullptr;
    QLabel* sourceLabel_ = nullptr;
    QLabel* timeLabel_ = nullptr;
    QLabel* lodLabel_ = nullptr;
    QLabel* heatLabel_ = nullptr;
    QSlider* timeSlider_ = nullptr;
    QSlider* lodSlider_ = nullptr;
    QPushButton* playButton_ = nullptr;
    QCheckBox* heatBox_ = nullptr;
    QCheckBox* closeSeamsBox_ = nullptr;
    QProgressBar* progress_ = nullptr;
    QPushButton* cancelButton_ = nullptr;

    LatestJob* morphJob_ = nullptr;  // open / build: a newer one supersedes the one running
    MorphRequest morphRequest_;      // what the next open or build does
    LatestJob* heatJob_ = nullptr;  // the heat maps, one at a time (a throttle: Superseded::show)
    QTimer playTimer_;
    QTimer heatDebounce_;
    std::shared_ptr<const MorphData> data_;
    double t_ = 0, f_ = 1;
    bool heat_ = false;
    double heatT_ = -1, heatF_ = -1;  // of the heat map shown
    double heatMax_ = 0;
    std::size_t triangles_ = 0;
};

}  // namespace lodforge::widgets
