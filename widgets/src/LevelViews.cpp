#include "lodforge/widgets/LevelViews.h"

#include "MeshActorBuilder.h"
#include "lodforge/strips/lodstrips.h"
#include "lodforge/runtime/lodstrips_runtime.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/VtkView.h"

#include <QCheckBox>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QPushButton>
#include <QSlider>
#include <QStackedWidget>
#include <QVBoxLayout>

#include <vtkCellArray.h>
#include <vtkIdTypeArray.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace lodforge::widgets {

namespace {

QLabel* makeLabel(QWidget* parent, const QString& name) {
    auto* label = new QLabel(parent);
    label->setObjectName(name);
    label->setAlignment(Qt::AlignCenter);
    label->setTextFormat(Qt::PlainText);
    // Small side-by-side tiles: the whole truth on two lines rather than clipped.
    label->setWordWrap(true);
    QFont font = label->font();
    font.setBold(true);
    label->setFont(font);
    return label;
}

QString formatDistance(double value) { return QString::number(value, 'g', 3); }

constexpr int continuousSteps = 1000;

// The runtime's current triangles with every strip in its own colour: each strip gets its own copies of
// the vertices it uses (a vertex shared by two strips would blend their colours), as wedges of the
// original points so the computed normals stay smooth. Materials and texture coordinates are dropped so
// the view shows the colours.
Mesh stripColouredMesh(const lodstrips::LodStrips& runtime, const Mesh& current) {
    Mesh out;
    std::vector<std::uint32_t> triangles;
    std::vector<std::uint32_t> local(current.vertex_count(), UINT32_MAX);
    for (std::size_t s = 0; s < runtime.strip_count(); ++s) {
        triangles.clear();
        runtime.append_strip_triangles(s, triangles);
        if (triangles.empty()) continue;
        const QColor c = stripColor(s);
        const Vec4f colour{float(c.redF()), float(c.greenF()), float(c.blueF()), 1.f};
        const std::size_t first = out.positions.size();
        for (std::uint32_t v : triangles) {
            if (local[v] == UINT32_MAX || local[v] < first) {
                local[v] = std::uint32_t(out.positions.size());
                out.positions.push_back(current.positions[v]);
                if (current.has_normals()) out.normals.push_back(current.normals[v]);
                out.colors.push_back(colour);
                out.position_ids.push_back(current.position_ids.empty() ? v : current.position_ids[v]);
            }
            out.indices.push_back(local[v]);
        }
    }
    // position_ids must be dense: renumber the point ids in order of first use.
    std::vector<std::uint32_t> dense(current.vertex_count(), UINT32_MAX);
    std::uint32_t next = 0;
    for (std::uint32_t& id : out.position_ids) {
        if (id >= dense.size()) dense.resize(std::size_t(id) + 1, UINT32_MAX);
        if (dense[id] == UINT32_MAX) dense[id] = next++;
        id = dense[id];
    }
    return out;
}

}  // namespace

QColor stripColor(std::size_t strip) {
    // Golden-ratio steps around the hue circle: consecutive strips land far apart.
    const double hue = std::fmod(double(strip) * 0.6180339887498949, 1.0);
    return QColor::fromHsvF(float(hue), 0.8f, 0.95f);
}

LevelViews::LevelViews(QWidget* parent) : QWidget(parent) {
    auto* outer = new QVBoxLayout(this);
    outer->setContentsMargins(0, 0, 0, 0);
    outer->setSpacing(0);
    staleBar_ = new QWidget(this);
    staleBar_->setObjectName(QStringLiteral("staleBar"));
    // Amber, as a warning: the levels below no longer follow the parameters.
    staleBar_->setStyleSheet(QStringLiteral("#staleBar { background: #f0a020; } #staleBar QLabel { color: black; }"));
    staleBar_->setAttribute(Qt::WA_StyledBackground);
    auto* staleRow = new QHBoxLayout(staleBar_);
    staleRow->setContentsMargins(8, 3, 8, 3);
    auto* staleText = new QLabel(tr("Stale: the parameters changed since these levels were built."), staleBar_);
    staleText->setObjectName(QStringLiteral("staleText"));
    auto* rebuild = new QPushButton(tr("Rebuild"), staleBar_);
    rebuild->setObjectName(QStringLiteral("rebuildButton"));
    rebuild->setToolTip(tr("Build the levels again with the current parameters (Ctrl+B)"));
    connect(rebuild, &QPushButton::clicked, this, &LevelViews::rebuildRequested);
    staleRow->addWidget(staleText, 1);
    staleRow->addWidget(rebuild);
    staleBar_->hide();
    outer->addWidget(staleBar_);
    stack_ = new QStackedWidget(this);
    outer->addWidget(stack_);

    singlePage_ = new QWidget(stack_);
    auto* singleLayout = new QVBoxLayout(singlePage_);
    singleLayout->setContentsMargins(0, 0, 0, 0);
    singleLayout->setSpacing(2);
    singleLabel_ = makeLabel(singlePage_, QStringLiteral("levelLabel"));
    single_ = new VtkView(singlePage_);
    single_->setObjectName(QStringLiteral("view"));
    auto* sliderRow = new QHBoxLayout;
    sliderRow->setContentsMargins(6, 0, 6, 2);
    auto* sliderCaption = new QLabel(tr("Level"), singlePage_);
    slider_ = new QSlider(Qt::Horizontal, singlePage_);
    slider_->setObjectName(QStringLiteral("levelSlider"));
    slider_->setRange(0, 0);
    slider_->setPageStep(1);
    slider_->setTickPosition(QSlider::TicksBelow);
    slider_->setTickInterval(1);
    slider_->setToolTip(tr("Level of detail shown (Page Up / Page Down)"));
    sliderRow->addWidget(sliderCaption);
    sliderRow->addWidget(slider_, 1);
    singleLayout->addWidget(singleLabel_);
    singleLayout->addWidget(single_, 1);
    singleLayout->addLayout(sliderRow);
    setupContinuous();
    singleLayout->addWidget(continuousRow_);
    stack_->addWidget(singlePage_);
    connect(slider_, &QSlider::valueChanged, this, &LevelViews::setCurrentLevel);
    connectView(single_, -1);

    tilesPage_ = new QWidget(stack_);
    grid_ = new QGridLayout(tilesPage_);
    grid_->setContentsMargins(0, 0, 0, 0);
    grid_->setSpacing(3);
    stack_->addWidget(tilesPage_);
    stack_->setCurrentWidget(singlePage_);
    refreshSingle();
}

LevelViews::~LevelViews() = default;

void LevelViews::setupContinuous() {
    continuousRow_ = new QWidget(singlePage_);
    continuousRow_->setObjectName(QStringLiteral("continuousRow"));
    auto* row = new QHBoxLayout(continuousRow_);
    row->setContentsMargins(6, 0, 6, 2);
    auto* caption = new QLabel(tr("Continuous LOD"), continuousRow_);
    continuousSlider_ = new QSlider(Qt::Horizontal, continuousRow_);
    continuousSlider_->setObjectName(QStringLiteral("continuousSlider"));
    continuousSlider_->setRange(0, continuousSteps);
    continuousSlider_->setValue(continuousSteps);
    continuousSlider_->setPageStep(50);
    continuousSlider_->setToolTip(tr("LODStrips runtime: 0 = the coarsest stored level, 1 = full detail"));
    continuousLabel_ = new QLabel(continuousRow_);
    continuousLabel_->setObjectName(QStringLiteral("continuousLabel"));
    continuousLabel_->setMinimumWidth(170);
    stripColors_ = new QCheckBox(tr("Colour strips"), continuousRow_);
    stripColors_->setObjectName(QStringLiteral("stripColors"));
    stripColors_->setToolTip(tr("Every triangle strip in its own colour"));
    row->addWidget(caption);
    row->addWidget(continuousSlider_, 1);
    row->addWidget(continuousLabel_);
    row->addWidget(stripColors_);
    continuousRow_->setVisible(false);
    connect(continuousSlider_, &QSlider::valueChanged, this,
            [this](int value) { setContinuousFactor(double(value) / continuousSteps); });
    connect(stripColors_, &QCheckBox::toggled, this, &LevelViews::setStripColors);
}

void LevelViews::setContinuousFactor(double factor) {
    if (!runtime_) return;
    factor = std::clamp(std::isfinite(factor) ? factor : 1.0, 0.0, 1.0);
    {
        const QSignalBlocker block(continuousSlider_);
        continuousSlider_->setValue(int(std::lround(factor * continuousSteps)));
    }
    if (!fullStrips_) {
        // The full-detail strips once, with every vertex the runtime has (level 0 uses them all); later
        // moves only replace this scene's triangles.
        runtime_->go_to_level(0);
        fullStrips_ = continuousData_->fullScene ? continuousData_->fullScene
                                                 : buildMeshScene(lodstrips_mesh(*runtime_), continuousData_->images);
        patchable_ = fullStrips_->parts.size() == 1 &&
                     std::size_t(fullStrips_->parts.front().polyData->GetNumberOfPoints()) == runtime_->vertex_count();
    }
    runtime_->go_to_lod(factor);
    runtime_->clear_changes();
    continuousActive_ = true;
    showContinuous();
}

// A heat map shows the stored level's error field; the continuous view resumes when it is switched off.
bool LevelViews::showsContinuous() const {
    return continuousActive_ && runtime_ && continuousScene_ && !heatmapVisible_;
}

double LevelViews::continuousFactor() const { return double(continuousSlider_->value()) / continuousSteps; }

std::size_t LevelViews::continuousTriangles() const { return runtime_ ? runtime_->triangle_count() : 0; }

void LevelViews::setStripColors(bool on) {
    {
        const QSignalBlocker block(stripColors_);
        stripColors_->setChecked(on);
    }
    if (!runtime_) return;
    // Colouring shows the strips of the runtime: switching it on enters the continuous view.
    continuousActive_ = continuousActive_ || on;
    if (continuousActive_) showContinuous();
}

bool LevelViews::stripColors() const { return stripColors_->isChecked(); }

// The vertex arrays are fixed: unless the strips are coloured (own vertices per strip) or the mesh has
// several materials (parts with their own vertex subsets), only the triangles of the full-detail scene
// are replaced, which on the bunny takes well under a drag's frame. Otherwise the scene is rebuilt.
void LevelViews::showContinuous() {
    if (stripColors_->isChecked()) {
        continuousScene_ = buildMeshScene(stripColouredMesh(*runtime_, lodstrips_mesh(*runtime_)), {});
    } else if (patchable_) {
        std::vector<std::uint32_t> triangles;
        runtime_->triangles(triangles);
        const auto n = static_cast<vtkIdType>(triangles.size() / 3);
        vtkNew<vtkIdTypeArray> offsets, connectivity;
        offsets->SetNumberOfValues(n + 1);
        connectivity->SetNumberOfValues(3 * n);
        vtkIdType* o = offsets->GetPointer(0);
        vtkIdType* c = connectivity->GetPointer(0);
        for (vtkIdType t = 0; t <= n; ++t) o[t] = 3 * t;
        for (std::size_t i = 0; i < triangles.size(); ++i) c[i] = static_cast<vtkIdType>(triangles[i]);
        vtkNew<vtkCellArray> polys;
        polys->SetData(offsets, connectivity);
        fullStrips_->parts.front().polyData->SetPolys(polys);
        continuousScene_ = fullStrips_;
    } else {
        continuousScene_ = buildMeshScene(lodstrips_mesh(*runtime_), continuousData_->images);
    }
    continuousLabel_->setText(tr("%1 triangles").arg(QLocale().toString(qulonglong(runtime_->triangle_count()))));
    refreshSingle();
    single_->update();  // the same scene with new triangles: the view would not notice on its own
}

void LevelViews::connectView(VtkView* view, int level) {
    // One camera for all: whichever view the user drags, the others repaint.
    connect(view, &VtkView::cameraChanged, this, [this, view] {
        if (view != single_) single_->update();
        for (const Tile& t : tiles_)
            if (t.view != view) t.view->update();
    });
    connect(view, &VtkView::scalarHovered, this, [this, view, level](double value) {
        const int shown = level < 0 ? current_ : level;
        QString text = tr("Distance to the original at the cursor: %1").arg(formatDistance(value));
        if (!levels_.empty() && levels_.front().mesh) {
            const double diagonal = levels_.front().mesh->bounds().diagonal();
            if (diagonal > 0) text += tr(" (%1 % of the diagonal)").arg(100.0 * value / diagonal, 0, 'f', 3);
        }
        emit hoverText(tr("LOD %1: %2").arg(shown).arg(text));
        Q_UNUSED(view);
    });
    connect(view, &VtkView::hoverLeft, this, [this] { emit hoverText(QString()); });
}

// Where `level` takes over from the level before it, once it and every finer level are measured.
QString LevelViews::takeOverText(int level) const {
    if (level < 1 || !levels_[0].mesh) return {};
    std::vector<double> errors;
    for (int k = 0; k <= level; ++k) {
        const LevelData& l = levels_[std::size_t(k)];
        if (k > 0 && l.measured == Measured::no) return {};
        errors.push_back(k == 0 ? 0.0 : l.errorRelative);
    }
    const lodforge::SwitchPoints s = lodforge::switch_points(errors, levels_[0].mesh->bounds(), switching_);
    if (s.levels.size() <= std::size_t(level)) return {};
    const lodforge::LevelSwitch& before = s.levels[std::size_t(level) - 1];
    return tr(" · takes over at %1 px (distance %2)")
        .arg(before.screen_size * switching_.height, 0, 'f', 0)
        .arg(formatDistance(before.godot.range_end));
}

void LevelViews::setSwitchParams(const lodforge::SwitchParams& params) {
    if (params == switching_) return;
    switching_ = params;
    refreshLabels();
}

QString LevelViews::levelLabelText(int level) const {
    if (level < 0 || level >= levelCount()) return {};
    const LevelData& l = levels_[std::size_t(level)];
    const QLocale locale;
    if (level == 0) return tr("Original · %1 triangles").arg(locale.toString(qulonglong(l.triangles)));
    QString count = locale.toString(qulonglong(l.triangles));
    if (l.targetTriangles > 0) count += QStringLiteral(" / ") + locale.toString(qulonglong(l.targetTriangles));
    QString text = tr("LOD %1 · %2 triangles").arg(level).arg(count);
    if (l.missedTarget) {
        text += tr(" · target missed: %1").arg(l.stopReason);
    } else if (l.stopReason == QStringLiteral("topology limit")) {
        text += tr(" · %1").arg(l.stopReason);  // an error target the simplifier could not reach
    }
    if (l.sameAs > 0) text += tr(" · same as LOD %1").arg(l.sameAs);
    if (l.measured == Measured::no) {
        text += measuring_ ? tr(" · error measuring…") : tr(" · error not measured");
    } else {
        text += tr(" · error %1%2 % (%3)")
                    .arg(l.measured == Measured::sampled ? QStringLiteral("≈ ") : QString())
                    .arg(100.0 * l.errorRelative, 0, 'f', 3)
                    .arg(formatDistance(l.error));
        text += takeOverText(level);
    }
    return stale_ ? tr("Stale · %1").arg(text) : text;
}

void LevelViews::setStale(bool stale) {
    stale = stale && levelCount() > 1;  // the original alone is never stale
    if (stale == stale_) return;
    stale_ = stale;
    staleBar_->setVisible(stale);
    // The labels carry the mark too, in amber, so a screenshot of any view still tells.
    const QString style = stale ? QStringLiteral("color: #c07000;") : QString();
    singleLabel_->setStyleSheet(style);
    for (const Tile& t : tiles_) t.label->setStyleSheet(style);
    refreshSingle();
    refreshTiles();
}

std::shared_ptr<const MeshScene> LevelViews::sceneOf(int level) const {
    if (level < 0 || level >= levelCount()) return nullptr;
    if (heatmapVisible_ && std::size_t(level) < heatmaps_.scenes.size()) return heatmaps_.scenes[std::size_t(level)];
    return levels_[std::size_t(level)].scene;
}

void LevelViews::setInspection(const QObject* owner, std::shared_ptr<const MeshScene> scene,
                               std::shared_ptr<const MeshScene> cells, const QString& label) {
    if (inspection_.owner && inspection_.owner != owner) endInspection();
    inspection_ = {owner, std::move(scene), std::move(cells), label};
    refreshSingle();
}

void LevelViews::clearInspection(const QObject* owner) {
    if (!owner || inspection_.owner != owner) return;
    inspection_ = {};
    refreshSingle();
}

void LevelViews::endInspection() {
    const QObject* owner = inspection_.owner;
    if (!owner) return;
    inspection_ = {};
    emit inspectionEnded(owner);
}

void LevelViews::showLevelIn(VtkView* view, int level) {
    if (view == single_ && inspection_.owner && !heatmapVisible_) {
        if (view->scene() != inspection_.scene) view->setScene(inspection_.scene, false);
        view->setOverlayScene(inspection_.cells);
        return;
    }
    std::shared_ptr<const MeshScene> scene =
        view == single_ && showsContinuous() ? continuousScene_ : sceneOf(level);
    if (view->scene() != scene) view->setScene(std::move(scene), false);
    view->setOverlayScene(level >= 0 && level < levelCount() ? levels_[std::size_t(level)].cells : nullptr);
}

bool LevelViews::hasCells() const {
    return std::any_of(levels_.begin(), levels_.end(), [](const LevelData& l) { return l.cells != nullptr; });
}

void LevelViews::setLevels(std::vector<LevelData> levels, bool resetCamera) {
    const bool sameCount = levels.size() == levels_.size();
    endInspection();
    levels_ = std::move(levels);
    stale_ = false;  // new levels follow the parameters they were built with
    staleBar_->hide();
    singleLabel_->setStyleSheet(QString());
    heatmaps_ = {};
    heatmapVisible_ = false;
    continuousActive_ = false;
    continuousScene_ = nullptr;
    fullStrips_ = nullptr;
    patchable_ = false;
    runtime_.reset();
    continuousData_ = levels_.empty() ? nullptr : levels_.front().continuous;
    if (continuousData_) {
        auto runtime = std::make_unique<lodstrips::LodStrips>();
        const std::vector<std::uint8_t>& file = continuousData_->lodstripsFile;
        if (runtime->load_memory(file.data(), file.size())) runtime_ = std::move(runtime);
    }
    {
        const QSignalBlocker block(continuousSlider_);
        continuousSlider_->setValue(continuousSteps);
    }
    continuousLabel_->setText(runtime_ ? tr("%1 triangles").arg(QLocale().toString(qulonglong(runtime_->triangle_count())))
                                       : QString());
    continuousRow_->setVisible(runtime_ != nullptr);
    if (!sameCount || current_ >= levelCount()) current_ = std::max(0, levelCount() - 1);
    {
        const QSignalBlocker block(slider_);
        slider_->setRange(0, std::max(0, levelCount() - 1));
        slider_->setValue(current_);
        slider_->setEnabled(levelCount() > 1);
    }
    rebuildTiles();
    refreshSingle();
    if (resetCamera) resetView();
    emit currentLevelChanged(current_);
}

void LevelViews::rebuildTiles() {
    for (const Tile& t : tiles_) {
        grid_->removeWidget(t.box);
        delete t.box;
    }
    tiles_.clear();
    const int n = levelCount();
    if (n == 0) return;
    const int columns = std::max(1, int(std::ceil(std::sqrt(double(n)))));
    for (int i = 0; i < n; ++i) {
        Tile t;
        t.box = new QWidget(tilesPage_);
        t.box->setObjectName(QStringLiteral("tile%1").arg(i));
        auto* layout = new QVBoxLayout(t.box);
        layout->setContentsMargins(0, 0, 0, 0);
        layout->setSpacing(1);
        t.label = makeLabel(t.box, QStringLiteral("tileLabel%1").arg(i));
        t.view = new VtkView(t.box);
        t.view->setObjectName(QStringLiteral("tileView%1").arg(i));
        t.view->setMinimumSize(120, 90);
        t.view->setSharedCamera(single_);
        t.view->setViewOptions(options_);
        t.view->setSplitPosition(split_);
        layout->addWidget(t.label);
        layout->addWidget(t.view, 1);
        grid_->addWidget(t.box, i / columns, i % columns);
        connectView(t.view, i);
        tiles_.push_back(t);
    }
    refreshTiles();
}

void LevelViews::refreshSingle() {
    showLevelIn(single_, current_);
    // The original as loaded (textured), also beside a heat map: the swipe shows what the error field covers.
    single_->setCompareScene(compareVisible_ && current_ > 0 ? levels_.front().scene : nullptr);
    single_->setOutlineScene(outlineFor(current_));
    refreshSingleLabel();
}

void LevelViews::setLevelMeasure(const LevelMeasure& measure) {
    if (measure.level <= 0 || measure.level >= levelCount()) return;
    LevelData& l = levels_[std::size_t(measure.level)];
    l.error = measure.error;
    l.errorRelative = measure.errorRelative;
    l.measured = measure.measured;
    if (measure.level < int(tiles_.size())) tiles_[measure.level].label->setText(levelLabelText(measure.level));
    if (measure.level == current_) refreshSingleLabel();
}

void LevelViews::setMeasuring(bool measuring) {
    if (measuring == measuring_) return;
    measuring_ = measuring;
    refreshLabels();
}

void LevelViews::refreshLabels() {
    for (int i = 0; i < int(tiles_.size()); ++i) tiles_[i].label->setText(levelLabelText(i));
    refreshSingleLabel();
}

void LevelViews::refreshSingleLabel() {
    if (inspection_.owner && !heatmapVisible_) {
        singleLabel_->setText(inspection_.label);
        return;
    }
    if (showsContinuous()) {
        singleLabel_->setText(tr("Continuous LOD %1 · %2 triangles")
                                  .arg(continuousFactor(), 0, 'f', 3)
                                  .arg(QLocale().toString(qulonglong(runtime_->triangle_count()))));
        return;
    }
    singleLabel_->setText(levelCount() ? levelLabelText(current_) : tr("No mesh"));
}

void LevelViews::refreshTiles() {
    for (int i = 0; i < int(tiles_.size()); ++i) {
        showLevelIn(tiles_[i].view, i);
        // Split compare in every tile but the original's: the original left of the split, the level right.
        std::shared_ptr<const MeshScene> reference = compareVisible_ && i > 0 ? levels_.front().scene : nullptr;
        if (tiles_[i].view->compareScene() != reference) tiles_[i].view->setCompareScene(std::move(reference));
        tiles_[i].view->setOutlineScene(outlineFor(i));
        tiles_[i].label->setText(levelLabelText(i));
    }
}

void LevelViews::setArrangement(Arrangement arrangement) {
    arrangement_ = arrangement;
    stack_->setCurrentWidget(arrangement == Arrangement::sideBySide ? tilesPage_ : singlePage_);
    single_->update();
    for (const Tile& t : tiles_) t.view->update();
}

void LevelViews::setCurrentLevel(int level) {
    level = std::clamp(level, 0, std::max(0, levelCount() - 1));
    continuousActive_ = false;  // choosing a stored level leaves the continuous view
    const bool inspecting = inspection_.owner != nullptr;
    endInspection();
    if (level == current_ && single_->scene() == sceneOf(level) && !inspecting) return;
    current_ = level;
    {
        const QSignalBlocker block(slider_);
        slider_->setValue(level);
    }
    refreshSingle();
    emit currentLevelChanged(level);
}

void LevelViews::setHeatmaps(HeatmapData heatmaps) {
    heatmaps_ = std::move(heatmaps);
    setHeatmapRange(heatmapRange_);
    refreshSingle();
    refreshTiles();
}

void LevelViews::setHeatmapVisible(bool visible) {
    heatmapVisible_ = visible && hasHeatmaps();
    refreshSingle();
    refreshTiles();
    setHeatmapRange(heatmapRange_);
}

void LevelViews::setHeatmapRange(double maximum) {
    heatmapRange_ = std::isfinite(maximum) && maximum > 0 ? maximum : 0.0;
    const double range = heatmapRange();
    single_->setScalarRange(range);
    for (const Tile& t : tiles_) t.view->setScalarRange(range);
}

double LevelViews::heatmapRange() const {
    if (heatmapRange_ > 0) return heatmapRange_;
    return heatmaps_.autoRange > 0 ? heatmaps_.autoRange : 0.0;
}

void LevelViews::setCompareVisible(bool visible) {
    compareVisible_ = visible;
    refreshSingle();
    refreshTiles();
}

void LevelViews::setSplitPosition(double fraction) {
    split_ = fraction;
    single_->setSplitPosition(fraction);
    for (const Tile& t : tiles_) t.view->setSplitPosition(fraction);
}

void LevelViews::setViewOptions(const ViewOptions& options) {
    const bool outline = options.heatmapOutline != options_.heatmapOutline;
    options_ = options;
    single_->setViewOptions(options);
    for (const Tile& t : tiles_) t.view->setViewOptions(options);
    if (outline) {
        single_->setOutlineScene(outlineFor(current_));
        for (int i = 0; i < int(tiles_.size()); ++i) tiles_[i].view->setOutlineScene(outlineFor(i));
    }
    emit viewOptionsChanged(options);
}

std::shared_ptr<const MeshScene> LevelViews::outlineFor(int level) const {
    if (!heatmapVisible_ || !options_.heatmapOutline || level <= 0 || levels_.empty()) return nullptr;
    return levels_.front().scene;
}

void LevelViews::resetView() {
    single_->resetView();  // the camera every tile shares
}

QList<VtkView*> LevelViews::tileViews() const {
    QList<VtkView*> views;
    for (const Tile& t : tiles_) views << t.view;
    return views;
}

QList<QLabel*> LevelViews::tileLabels() const {
    QList<QLabel*> labels;
    for (const Tile& t : tiles_) labels << t.label;
    return labels;
}

QImage LevelViews::levelImage(int level, QSize size) {
    if (level < 0 || level >= levelCount()) return {};
    QImage image;
    if (arrangement_ == Arrangement::sideBySide && level < int(tiles_.size())) {
        image = tiles_[level].view->grabFramebuffer();
    } else {
        const int previous = current_;
        const bool compare = compareVisible_;
        const bool continuous = continuousActive_;
        const Inspection inspection = std::exchange(inspection_, {});
        compareVisible_ = false;
        setCurrentLevel(level);
        image = single_->grabFramebuffer();
        compareVisible_ = compare;
        setCurrentLevel(previous);
        continuousActive_ = continuous;
        inspection_ = inspection;
        refreshSingle();
    }
    if (image.isNull()) return image;
    return image.convertToFormat(QImage::Format_RGB32).scaled(size, Qt::KeepAspectRatio, Qt::SmoothTransformation);
}

}  // namespace lodforge::widgets
