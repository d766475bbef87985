#include "lodforge/widgets/MorphPanel.h"

#include "lodforge/error.h"
#include "lodforge/metrics/metrics.h"
#include "lodforge/morph/morph_file.h"
#include "lodforge/morph/supermesh.h"
#include "lodforge/widgets/Job.h"
#include "lodforge/widgets/LandmarkPicker.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/VtkView.h"

#include <QCheckBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QKeySequence>
#include <QLabel>
#include <QLocale>
#include <QProgressBar>
#include <QPushButton>
#include <QShortcut>
#include <QSignalBlocker>
#include <QSlider>
#include <QTabWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

namespace lodforge::widgets {

namespace {

double clamp01(double v) { return std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 0.0; }
int toSteps(double v) { return static_cast<int>(std::lround(v * MorphPanel::sliderSteps)); }

}  // namespace

// --- Case (b): the core supermesh builder (supermesh.h) behind the landmark picker. ------------------
bool MorphPanel::supermeshBuilderConnected() { return true; }

MorphMesh MorphPanel::build_supermesh(const Mesh& a, const Mesh& b, const Landmarks& landmarks,
                                      const std::string& sourceA, const std::string& sourceB, Progress* progress) {
    // The same builder and defaults as `lodforge morph build A B --landmarks L.json`.
    SupermeshResult r = lodforge::build_supermesh(a, b, landmarks, {}, sourceA, sourceB, "the picked landmarks", progress);
    r.morph.frame_names = {sourceA, sourceB};
    return std::move(r.morph);
}

QString MorphPanel::supermeshUnavailableReason() {
    return tr("Open mesh A and mesh B and pick at least one landmark pair first.");
}
// ------------------------------------------------------------------------------------------------

MorphPanel::MorphPanel(QWidget* parent) : QWidget(parent) {
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(4, 4, 4, 4);
    tabs_ = new QTabWidget(this);
    tabs_->setObjectName(QStringLiteral("morphTabs"));
    layout->addWidget(tabs_);

    // Animation tab.
    auto* animation = new QWidget(this);
    auto* a = new QVBoxLayout(animation);
    auto* head = new QHBoxLayout;
    auto* openDir = new QPushButton(tr("Open sequence…"), animation);
    openDir->setObjectName(QStringLiteral("morphOpenSequence"));
    openDir->setToolTip(tr("A directory of OBJ/PLY keyframes with identical connectivity"));
    connect(openDir, &QPushButton::clicked, this, [this] { showOpenDialog(true); });
    auto* openFile = new QPushButton(tr("Open file…"), animation);
    openFile->setObjectName(QStringLiteral("morphOpenFile"));
    openFile->setToolTip(tr("A glTF with morph targets or a .lfmorph file (lodforge morph build)"));
    connect(openFile, &QPushButton::clicked, this, [this] { showOpenDialog(false); });
    closeSeamsBox_ = new QCheckBox(tr("Close seams"), animation);
    closeSeamsBox_->setObjectName(QStringLiteral("morphCloseSeams"));
    closeSeamsBox_->setToolTip(tr("Let attribute seams close when building the LOD (--close-seams; flat-shaded "
                                  "inputs simplify only with it)"));
    sourceLabel_ = new QLabel(tr("No morph"), animation);
    sourceLabel_->setObjectName(QStringLiteral("morphSource"));
    progress_ = new QProgressBar(animation);
    progress_->setObjectName(QStringLiteral("morphProgress"));
    progress_->setRange(0, 1000);
    progress_->setMaximumWidth(220);
    progress_->setVisible(false);
    cancelButton_ = new QPushButton(tr("Cancel"), animation);
    cancelButton_->setObjectName(QStringLiteral("morphCancel"));
    cancelButton_->setVisible(false);
    connect(cancelButton_, &QPushButton::clicked, this, &MorphPanel::cancel);
    head->addWidget(openDir);
    head->addWidget(openFile);
    head->addWidget(closeSeamsBox_);
    head->addWidget(sourceLabel_, 1);
    head->addWidget(progress_);
    head->addWidget(cancelButton_);
    a->addLayout(head);

    view_ = new VtkView(animation);
    view_->setObjectName(QStringLiteral("morphView"));
    view_->setMinimumSize(240, 200);
    a->addWidget(view_, 1);

    auto* timeRow = new QHBoxLayout;
    playButton_ = new QPushButton(tr("Play"), animation);
    playButton_->setObjectName(QStringLiteral("morphPlay"));
    playButton_->setCheckable(true);
    playButton_->setToolTip(tr("Play or pause t, looping (Space)"));
    connect(playButton_, &QPushButton::toggled, this, &MorphPanel::setPlaying);
    timeSlider_ = new QSlider(Qt::Horizontal, animation);
    timeSlider_->setObjectName(QStringLiteral("morphTime"));
    timeSlider_->setRange(0, sliderSteps);
    timeSlider_->setToolTip(tr("Time t across the whole sequence"));
    connect(timeSlider_, &QSlider::valueChanged, this, [this](int v) { setTime(double(v) / sliderSteps); });
    timeLabel_ = new QLabel(animation);
    timeLabel_->setObjectName(QStringLiteral("morphTimeLabel"));
    timeLabel_->setMinimumWidth(230);
    timeRow->addWidget(playButton_);
    timeRow->addWidget(timeSlider_, 1);
    timeRow->addWidget(timeLabel_);
    a->addLayout(timeRow);

    auto* lodRow = new QHBoxLayout;
    auto* lodName = new QLabel(tr("LOD"), animation);
    lodSlider_ = new QSlider(Qt::Horizontal, animation);
    lodSlider_->setObjectName(QStringLiteral("morphLod"));
    lodSlider_->setRange(0, sliderSteps);
    lodSlider_->setValue(sliderSteps);
    lodSlider_->setToolTip(tr("LOD factor F: 0 the coarsest stored level, 1 full detail"));
    connect(lodSlider_, &QSlider::valueChanged, this, [this](int v) { setLodFactor(double(v) / sliderSteps); });
    lodLabel_ = new QLabel(animation);
    lodLabel_->setObjectName(QStringLiteral("morphLodLabel"));
    lodLabel_->setMinimumWidth(230);
    lodRow->addWidget(lodName);
    lodRow->addWidget(lodSlider_, 1);
    lodRow->addWidget(lodLabel_);
    a->addLayout(lodRow);

    auto* heatRow = new QHBoxLayout;
    heatBox_ = new QCheckBox(tr("Heat map of the frame's error"), animation);
    heatBox_->setObjectName(QStringLiteral("morphHeatmap"));
    heatBox_->setToolTip(tr("Distance of the full-detail mesh at t to the LOD mesh at t, on the full mesh"));
    connect(heatBox_, &QCheckBox::toggled, this, &MorphPanel::setHeatmapVisible);
    heatLabel_ = new QLabel(animation);
    heatLabel_->setObjectName(QStringLiteral("morphHeatLabel"));
    heatRow->addWidget(heatBox_);
    heatRow->addWidget(heatLabel_, 1);
    a->addLayout(heatRow);
    tabs_->addTab(animation, tr("Animation"));

    picker_ = new LandmarkPicker(this);
    picker_->setObjectName(QStringLiteral("landmarkPicker"));
    picker_->setSupermeshAvailable(supermeshBuilderConnected(),
                                   tr("Build the supermesh of A and B from the pairs and play it (both must be "
                                      "closed genus-0 meshes)"));
    connect(picker_, &LandmarkPicker::buildSupermeshRequested, this, &MorphPanel::buildSupermeshFromPicks);
    connect(picker_, &LandmarkPicker::message, this, &MorphPanel::logMessage);
    connect(picker_, &LandmarkPicker::meshLoaded, this, [this](LandmarkPicker::Side side, bool ok, const QString& m) {
        const QString name = side == LandmarkPicker::Side::a ? QStringLiteral("A") : QStringLiteral("B");
        emit logMessage(ok ? tr("Landmarks: mesh %1 is %2").arg(name, picker_->meshPath(side)) : m);
        if (!ok) emit landmarkMeshFailed(m);
    });
    tabs_->addTab(picker_, tr("Landmarks"));

    auto* playKey = new QShortcut(QKeySequence(Qt::Key_Space), animation);
    playKey->setContext(Qt::WidgetWithChildrenShortcut);
    connect(playKey, &QShortcut::activated, this, [this] { setPlaying(!isPlaying()); });

    playTimer_.setInterval(playIntervalMs);
    connect(&playTimer_, &QTimer::timeout, this, &MorphPanel::advancePlay);
    // Heat maps measure the whole mesh: at most one per interval, and one at a time (startHeatmap).
    heatDebounce_.setSingleShot(true);
    heatDebounce_.setInterval(60);
    connect(&heatDebounce_, &QTimer::timeout, this, &MorphPanel::startHeatmap);
    // While playing, a newer (t, F) lets the running heat map finish and show, then the newest runs: the
    // heat map lags t by one computation instead of never showing.
    heatJob_ = new LatestJob([this] { return makeHeatmap(); }, this, LatestJob::Superseded::show);
    morphJob_ = new LatestJob([this] { return makeMorphJob(); }, this);
    connect(morphJob_, &LatestJob::progressChanged, this, [this](double fraction, const QString& stage) {
        progress_->setValue(static_cast<int>(std::lround(fraction * 1000)));
        progress_->setFormat(stage.isEmpty() ? QStringLiteral("%p%") : stage + QStringLiteral(" %p%"));
    });
    connect(morphJob_, &LatestJob::failed, this, [this](const QString& error) {
        emit logMessage(error);
        updateControls();
        emit morphLoaded(false, error);
    });
    connect(morphJob_, &LatestJob::cancelled, this, [this](const JobResult& result) {
        emit logMessage(tr("%1: cancelled").arg(result.name));
        updateControls();
        emit morphLoaded(false, QString());
    });
    connect(morphJob_, &LatestJob::changed, this, &MorphPanel::updateControls);
    connect(heatJob_, &LatestJob::failed, this, &MorphPanel::logMessage);

    updateLabels();
    updateControls();
}

MorphPanel::~MorphPanel() {
    // Both cancelled first, so that they stop side by side; each LatestJob then waits for its jobs.
    heatJob_->cancel();
    morphJob_->cancel();
}

void MorphPanel::setViewOptions(const ViewOptions& options) {
    for (VtkView* v : {view_, picker_->view(LandmarkPicker::Side::a), picker_->view(LandmarkPicker::Side::b)})
        v->setViewOptions(options);
}

void MorphPanel::showLandmarks() { tabs_->setCurrentWidget(picker_); }
void MorphPanel::showAnimation() { tabs_->setCurrentIndex(0); }

void MorphPanel::setCloseSeams(bool close) { closeSeamsBox_->setChecked(close); }

bool MorphPanel::isBusy() const { return morphJob_->isBusy(); }

void MorphPanel::cancel() { morphJob_->stop(); }  // its end reports "cancelled" (morphLoaded)

void MorphPanel::openMorph(const QString& path) {
    const std::string file = path.toStdString();
    if (QFileInfo(path).suffix().compare(QStringLiteral("lfmorph"), Qt::CaseInsensitive) == 0) {
        startMorphJob(tr("Open morph"), path, [file](MorphData& d, Progress* progress) {
            MorphLodFile f = read_morph_lod(file, progress);
            d.morph = std::move(f.morph);
            d.lod = std::move(f.lod);
        });
        return;
    }
    const bool closeSeams = closeSeamsBox_->isChecked();
    startMorphJob(tr("Build morph LOD"), path, [file, closeSeams](MorphData& d, Progress* progress) {
        // The defaults of `lodforge morph build` (MorphLodParams), so the studio shows the CLI's file.
        MorphLodParams params;
        params.simplify.preserve_seams = !closeSeams;
        d.morph = load_morph(file, {}, progress);
        d.lod = build_morph_lod(d.morph, params, progress);
    });
}

void MorphPanel::buildSupermeshFromPicks() {
    const auto a = picker_->mesh(LandmarkPicker::Side::a);
    const auto b = picker_->mesh(LandmarkPicker::Side::b);
    if (!supermeshBuilderConnected() || !a || !b) return;
    const Landmarks landmarks = picker_->landmarks();
    const bool closeSeams = closeSeamsBox_->isChecked();
    const QString source = tr("supermesh of %1 and %2").arg(QFileInfo(picker_->meshPath(LandmarkPicker::Side::a)).fileName(),
                                                            QFileInfo(picker_->meshPath(LandmarkPicker::Side::b)).fileName());
    const std::string sourceA = picker_->meshPath(LandmarkPicker::Side::a).toStdString();
    const std::string sourceB = picker_->meshPath(LandmarkPicker::Side::b).toStdString();
    startMorphJob(tr("Build supermesh"), source, [a, b, landmarks, closeSeams, sourceA, sourceB](MorphData& d, Progress* progress) {
        MorphLodParams params;
        params.simplify.preserve_seams = !closeSeams;
        d.morph = build_supermesh(*a, *b, landmarks, sourceA, sourceB, progress);
        d.lod = build_morph_lod(d.morph, params, progress);
    });
    showAnimation();
}

void MorphPanel::startMorphJob(const QString& name, const QString& source, Fill fill) {
    // One running is cancelled (its result would belong to another morph) and this one starts once it
    // has stopped, without the GUI thread waiting for it.
    morphRequest_ = {name, source, std::move(fill)};
    morphJob_->requestNow();
}

std::optional<LatestJob::Run> MorphPanel::makeMorphJob() {
    auto out = std::make_shared<MorphData>();
    out->source = morphRequest_.source;
    return LatestJob::Run{
        morphRequest_.name, [out, fill = morphRequest_.fill](Progress* progress) { fill(*out, progress); },
        [this, out](const JobResult& result) {
            data_ = out;
            const MorphData& d = *data_;
            sourceLabel_->setText(tr("%1 · %2 keyframes · %3 triangles · order %4")
                                      .arg(QFileInfo(d.source).fileName().isEmpty() ? d.source : QFileInfo(d.source).fileName())
                                      .arg(d.morph.frame_count())
                                      .arg(QLocale().toString(qulonglong(d.lod.triangles)))
                                      .arg(QString::fromUtf8(morph_order_name(d.lod.order))));
            emit logMessage(tr("%1: %2 (%3 keyframes, %4 vertices, %5 levels) in %6 ms")
                                .arg(result.name, d.source)
                                .arg(d.morph.frame_count())
                                .arg(d.morph.vertex_count())
                                .arg(d.lod.levels.size())
                                .arg(result.elapsedMs));
            const auto& levels = d.lod.sequences.front().level_triangles;
            if (!levels.empty() && levels.back() >= d.lod.triangles)
                emit logMessage(tr("%1: the LOD removes no triangles (every edge a seam, as in flat-shaded "
                                   "files?); open it again with Close seams").arg(d.source));
            heatT_ = heatF_ = -1;
            showFrame(true);
            if (heat_) startHeatmap();
            updateControls();
            emit morphLoaded(true, QString());
        }};
}

void MorphPanel::setTime(double t) {
    t = clamp01(t);
    const bool changed = t != t_;
    t_ = t;
    {
        const QSignalBlocker block(timeSlider_);
        timeSlider_->setValue(toSteps(t_));
    }
    if (!changed) return;
    showFrame();
    emit timeChanged(t_);
}

void MorphPanel::setLodFactor(double f) {
    f = clamp01(f);
    const bool changed = f != f_;
    f_ = f;
    {
        const QSignalBlocker block(lodSlider_);
        lodSlider_->setValue(toSteps(f_));
    }
    if (changed) showFrame();
}

bool MorphPanel::isPlaying() const { return playTimer_.isActive(); }

void MorphPanel::setPlaying(bool playing) {
    if (playing && data_) {
        playTimer_.start();
    } else {
        playTimer_.stop();
    }
    const QSignalBlocker block(playButton_);
    playButton_->setChecked(playTimer_.isActive());
    playButton_->setText(playTimer_.isActive() ? tr("Pause") : tr("Play"));
}

void MorphPanel::advancePlay() {
    double t = t_ + playIntervalMs / 1000.0 / playLoopSeconds;
    if (t > 1.0) t -= 1.0;  // loop
    setTime(t);
}

void MorphPanel::setHeatmapVisible(bool visible) {
    {
        const QSignalBlocker block(heatBox_);
        heatBox_->setChecked(visible);
    }
    if (visible == heat_) return;
    heat_ = visible;
    heatT_ = heatF_ = -1;
    if (heat_) {
        startHeatmap();
    } else {
        heatDebounce_.stop();
        showFrame();
    }
    updateLabels();
}

bool MorphPanel::heatmapCurrent() const { return heat_ && heatT_ == t_ && heatF_ == f_; }

void MorphPanel::showFrame(bool resetCamera) {
    if (!data_) {
        updateLabels();
        return;
    }
    // The LOD mesh is cheap (a collapse replay and a blend): always made here, for its triangle count and,
    // without the heat map, for the view.
    const Mesh mesh = extract_morph(data_->morph, data_->lod, t_, f_);
    triangles_ = mesh.triangle_count();
    if (!heat_ || resetCamera) {
        view_->setScene(buildMeshScene(mesh, {}), resetCamera);
        if (!heat_) emit frameShown();
    }
    // A throttle rather than a debounce: while playing, t changes every tick and a restarted timer would
    // never fire.
    if (heat_ && !heatDebounce_.isActive()) heatDebounce_.start();
    updateLabels();
}

void MorphPanel::startHeatmap() {
    if (heat_ && data_) heatJob_->requestNow();  // runs when the one running has ended
}

std::optional<LatestJob::Run> MorphPanel::makeHeatmap() {
    if (!heat_ || !data_) return std::nullopt;
    struct Output {
        std::shared_ptr<const MeshScene> scene;
        double max = 0;
    };
    auto out = std::make_shared<Output>();
    const auto data = data_;
    const double t = t_, f = f_;
    return LatestJob::Run{tr("Morph heat map"), [out, data, t, f](Progress* progress) {
        const Mesh level = extract_morph(data->morph, data->lod, t, f);
        const Mesh full = morph_mesh_at(data->morph, t);
        // The field is per vertex of the full mesh (half-edge collapses keep the level's vertices on the
        // full surface, so the level's own vertices would all read zero); the sampled part of compare()
        // is not shown, so a few samples do.
        DistanceParams params;
        params.samples = 1000;
        const DistanceResult r = compare(level, full, params, progress);
        for (float e : r.vertex_errors) out->max = std::max(out->max, double(e));
        out->scene = buildScalarScene(full, r.vertex_errors);
    }, [this, out, data, t, f](const JobResult&) {
        if (!heat_ || data != data_) return;
        view_->setScene(out->scene, false);
        view_->setScalarRange(0);  // this frame's own largest error is yellow
        heatT_ = t;
        heatF_ = f;
        heatMax_ = out->max;
        updateLabels();
        if (heatmapCurrent()) {
            emit heatmapShown();
        } else if (!heatJob_->isBusy()) {
            startHeatmap();  // (t, F) moved on and the throttle has not asked yet
        }
    }};
}

QString MorphPanel::timeText() const {
    if (!data_) return tr("t %1").arg(t_, 0, 'f', 3);
    const std::size_t k = data_->morph.frame_count();
    // The fractional keyframe position t·(K−1): "frame 23.50 of 0–47".
    return tr("t %1 · frame %2 of 0–%3").arg(t_, 0, 'f', 3).arg(t_ * double(k - 1), 0, 'f', 2).arg(k - 1);
}

QString MorphPanel::lodText() const {
    return tr("F %1 · %2 triangles").arg(f_, 0, 'f', 3).arg(QLocale().toString(qulonglong(triangles_)));
}

void MorphPanel::updateLabels() {
    timeLabel_->setText(timeText());
    lodLabel_->setText(lodText());
    if (!heat_) {
        heatLabel_->clear();
    } else if (heatT_ < 0) {
        heatLabel_->setText(tr("computing…"));
    } else {
        const double diagonal = data_ ? [this] {
            Vec3f lo = data_->morph.base.positions.front(), hi = lo;
            for (const Vec3f& p : data_->morph.base.positions) {
                lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
                hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
            }
            const double dx = hi.x - lo.x, dy = hi.y - lo.y, dz = hi.z - lo.z;
            return std::sqrt(dx * dx + dy * dy + dz * dz);
        }() : 0.0;
        heatLabel_->setText(tr("largest error %1 (%2 % of the diagonal) at t %3, F %4")
                                .arg(heatMax_, 0, 'g', 3)
                                .arg(diagonal > 0 ? 100.0 * heatMax_ / diagonal : 0.0, 0, 'g', 3)
                                .arg(heatT_, 0, 'f', 3)
                                .arg(heatF_, 0, 'f', 3));
    }
}

void MorphPanel::updateControls() {
    const bool busy = isBusy();
    const bool ready = data_ != nullptr;
    progress_->setVisible(busy);
    cancelButton_->setVisible(busy);
    if (busy) progress_->setValue(0);
    for (QWidget* w : std::initializer_list<QWidget*>{timeSlider_, lodSlider_, playButton_, heatBox_}) w->setEnabled(ready);
    if (!ready) setPlaying(false);
}

void MorphPanel::showOpenDialog(bool directory) {
    const QString path = directory
                             ? QFileDialog::getExistingDirectory(this, tr("Open keyframe sequence"))
                             : QFileDialog::getOpenFileName(this, tr("Open morph"), QString(),
                                                            tr("Morphs (*.gltf *.glb *.lfmorph);;All files (*)"));
    if (!path.isEmpty()) openMorph(path);
}

}  // namespace lodforge::widgets
