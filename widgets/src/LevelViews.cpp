#include "lodforge/widgets/LevelViews.h"

#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/VtkView.h"

#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QSlider>
#include <QStackedWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

namespace lodforge::widgets {

namespace {

QLabel* makeLabel(QWidget* parent, const QString& name) {
    auto* label = new QLabel(parent);
    label->setObjectName(name);
    label->setAlignment(Qt::AlignCenter);
    label->setTextFormat(Qt::PlainText);
    QFont font = label->font();
    font.setBold(true);
    label->setFont(font);
    return label;
}

QString formatDistance(double value) { return QString::number(value, 'g', 3); }

}  // namespace

LevelViews::LevelViews(QWidget* parent) : QWidget(parent) {
    auto* outer = new QVBoxLayout(this);
    outer->setContentsMargins(0, 0, 0, 0);
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

QString LevelViews::levelLabelText(int level) const {
    if (level < 0 || level >= levelCount()) return {};
    const LevelData& l = levels_[std::size_t(level)];
    const QLocale locale;
    if (level == 0) return tr("Original · %1 triangles").arg(locale.toString(qulonglong(l.triangles)));
    return tr("LOD %1 · %2 triangles · error %3 % (%4)")
        .arg(level)
        .arg(locale.toString(qulonglong(l.triangles)))
        .arg(100.0 * l.errorRelative, 0, 'f', 3)
        .arg(formatDistance(l.error));
}

std::shared_ptr<const MeshScene> LevelViews::sceneOf(int level) const {
    if (level < 0 || level >= levelCount()) return nullptr;
    if (heatmapVisible_ && std::size_t(level) < heatmaps_.scenes.size()) return heatmaps_.scenes[std::size_t(level)];
    return levels_[std::size_t(level)].scene;
}

void LevelViews::showLevelIn(VtkView* view, int level) {
    std::shared_ptr<const MeshScene> scene = sceneOf(level);
    if (view->scene() != scene) view->setScene(std::move(scene), false);
    view->setOverlayScene(level >= 0 && level < levelCount() ? levels_[std::size_t(level)].cells : nullptr);
}

bool LevelViews::hasCells() const {
    return std::any_of(levels_.begin(), levels_.end(), [](const LevelData& l) { return l.cells != nullptr; });
}

void LevelViews::setLevels(std::vector<LevelData> levels, bool resetCamera) {
    const bool sameCount = levels.size() == levels_.size();
    levels_ = std::move(levels);
    heatmaps_ = {};
    heatmapVisible_ = false;
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
    singleLabel_->setText(levelCount() ? levelLabelText(current_) : tr("No mesh"));
}

void LevelViews::refreshTiles() {
    for (int i = 0; i < int(tiles_.size()); ++i) {
        showLevelIn(tiles_[i].view, i);
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
    if (level == current_ && single_->scene() == sceneOf(level)) return;
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
    return heatmaps_.maxError > 0 ? heatmaps_.maxError : 0.0;
}

void LevelViews::setCompareVisible(bool visible) {
    compareVisible_ = visible;
    refreshSingle();
}

void LevelViews::setSplitPosition(double fraction) {
    split_ = fraction;
    single_->setSplitPosition(fraction);
}

void LevelViews::setViewOptions(const ViewOptions& options) {
    options_ = options;
    single_->setViewOptions(options);
    for (const Tile& t : tiles_) t.view->setViewOptions(options);
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
        compareVisible_ = false;
        setCurrentLevel(level);
        image = single_->grabFramebuffer();
        compareVisible_ = compare;
        setCurrentLevel(previous);
        refreshSingle();
    }
    if (image.isNull()) return image;
    return image.convertToFormat(QImage::Format_RGB32).scaled(size, Qt::KeepAspectRatio, Qt::SmoothTransformation);
}

}  // namespace lodforge::widgets
