#include "lodforge/widgets/OctreeTuningPanel.h"

#include "lodforge/error.h"
#include "lodforge/pack/preset_levels.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/octree/octree_select.h"
#include "lodforge/widgets/Job.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/VtkView.h"

#include <QAction>
#include <QCheckBox>
#include <QEvent>
#include <QFile>
#include <QFileInfo>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLocale>
#include <QPushButton>
#include <QSlider>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTimer>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace lodforge::widgets {

namespace {

constexpr double pixelsPerStep = 0.5;  // the screen error slider: step k = k / 2 pixels

// Level of a cut node: 0 = the leaf's input triangles, h + 1 = the simplified mesh of a node of height h.
int cutLevel(const OctreeStore& store, const CutNode& c) { return c.raw ? 0 : store.node(c.node).height + 1; }

bool isUnder(const OctreeStore& store, std::uint32_t node, std::uint32_t ancestor) {
    for (std::uint32_t n = node; n != UINT32_MAX && n < store.nodes().size(); n = store.node(n).parent)
        if (n == ancestor) return true;
    return false;
}

// `node`'s subtree at level `level` (level_cut's rule, restricted to the subtree).
void subtreeCut(const OctreeStore& store, std::uint32_t node, int level, Cut& out) {
    const OctreeNode& n = store.node(node);
    if (level == 0 && n.is_leaf()) {
        out.push_back({node, true});
        return;
    }
    if (level >= 1 && n.height < level) {
        out.push_back({node, false});
        return;
    }
    for (std::uint32_t c : store.children(node)) subtreeCut(store, c, level, out);
}

// The view's cut with the pinned node's subtree at the pinned level: cut nodes inside the subtree are
// replaced by it; a cut node above the pinned node is replaced by the subtrees beside the path down to
// it (simplified), so every root-to-leaf path still crosses the cut exactly once.
Cut pinnedCut(const OctreeStore& store, const Cut& viewCut, std::uint32_t pin, int pinLevel) {
    if (pin == UINT32_MAX) return viewCut;
    Cut out;
    std::vector<std::uint32_t> path;  // the pinned node's strict ancestors, root first
    for (std::uint32_t n = store.node(pin).parent; n != UINT32_MAX && n < store.nodes().size();
         n = store.node(n).parent)
        path.insert(path.begin(), n);
    for (const CutNode& c : viewCut) {
        if (isUnder(store, c.node, pin)) continue;
        const auto above = std::find(path.begin(), path.end(), c.node);
        if (above == path.end()) {
            out.push_back(c);
            continue;
        }
        for (auto p = above; p != path.end(); ++p) {
            const std::uint32_t next = p + 1 != path.end() ? *(p + 1) : pin;
            for (std::uint32_t child : store.children(*p))
                if (child != next) out.push_back({child, false});
        }
    }
    subtreeCut(store, pin, pinLevel, out);
    return out;
}

void checkCancelled(Progress* progress) {
    if (progress && progress->cancelled()) throw Error(Error::Kind::cancelled, "octree cut cancelled");
}

}  // namespace

OctreeTuningPanel::OctreeTuningPanel(LevelViews* views, QWidget* parent) : QWidget(parent), views_(views) {
    auto* layout = new QVBoxLayout(this);
    auto* buttons = new QHBoxLayout;
    buildButton_ = new QPushButton(tr("Build octree"), this);
    buildButton_->setObjectName(QStringLiteral("octreeBuild"));
    buildButton_->setToolTip(tr("Build the out-of-core octree of the loaded mesh with the Parameters' knobs; "
                                "later knob changes rebuild it"));
    cancelButton_ = new QPushButton(tr("Cancel"), this);
    cancelButton_->setObjectName(QStringLiteral("octreeCancel"));
    buttons->addWidget(buildButton_);
    buttons->addWidget(cancelButton_);
    buttons->addStretch(1);
    layout->addLayout(buttons);
    status_ = new QLabel(this);
    status_->setObjectName(QStringLiteral("octreeStatus"));
    status_->setWordWrap(true);
    layout->addWidget(status_);
    statsLabel_ = new QLabel(this);
    statsLabel_->setObjectName(QStringLiteral("octreeStats"));
    statsLabel_->setWordWrap(true);
    statsLabel_->setTextFormat(Qt::PlainText);
    layout->addWidget(statsLabel_);
    levels_ = new QTableWidget(0, 2, this);
    levels_->setObjectName(QStringLiteral("octreeLevels"));
    levels_->setHorizontalHeaderLabels({tr("Level"), tr("Triangles")});
    levels_->verticalHeader()->setVisible(false);
    levels_->horizontalHeader()->setStretchLastSection(true);
    levels_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    levels_->setMinimumHeight(120);
    layout->addWidget(levels_, 1);

    treeBox_ = new QCheckBox(tr("Tree cells over the mesh (O shows them)"), this);
    treeBox_->setObjectName(QStringLiteral("octreeShowTree"));
    treeBox_->setChecked(true);
    treeBox_->setToolTip(tr("After each build, the original with every node of the tree as the cells overlay"));
    layout->addWidget(treeBox_);
    viewDependentBox_ = new QCheckBox(tr("View-dependent cut in the view"), this);
    viewDependentBox_->setObjectName(QStringLiteral("octreeViewDependent"));
    viewDependentBox_->setToolTip(tr("Each node's level from its projected error at the current camera"));
    layout->addWidget(viewDependentBox_);
    auto* screenRow = new QHBoxLayout;
    screenRow->addWidget(new QLabel(tr("Screen error (px)"), this));
    screenSlider_ = new QSlider(Qt::Horizontal, this);
    screenSlider_->setObjectName(QStringLiteral("octreeScreenError"));
    screenSlider_->setRange(1, 100);
    screenSlider_->setValue(4);
    screenSlider_->setToolTip(tr("Refine a node while its error projects to more pixels than this"));
    screenValue_ = new QLabel(this);
    screenValue_->setMinimumWidth(50);
    screenRow->addWidget(screenSlider_, 1);
    screenRow->addWidget(screenValue_);
    layout->addLayout(screenRow);
    cullingBox_ = new QCheckBox(tr("Frustum culling"), this);
    cullingBox_->setObjectName(QStringLiteral("octreeCulling"));
    cullingBox_->setChecked(true);
    layout->addWidget(cullingBox_);
    auto* scrubRow = new QHBoxLayout;
    pickButton_ = new QPushButton(tr("Pick node"), this);
    pickButton_->setObjectName(QStringLiteral("octreePickNode"));
    pickButton_->setCheckable(true);
    pickButton_->setToolTip(tr("Click a node of the cut in the view to scrub its level"));
    coarserButton_ = new QPushButton(tr("Coarser ]"), this);
    coarserButton_->setObjectName(QStringLiteral("octreeCoarser"));
    finerButton_ = new QPushButton(tr("Finer ["), this);
    finerButton_->setObjectName(QStringLiteral("octreeFiner"));
    scrubRow->addWidget(pickButton_);
    scrubRow->addWidget(finerButton_);
    scrubRow->addWidget(coarserButton_);
    layout->addLayout(scrubRow);
    cutLabel_ = new QLabel(this);
    cutLabel_->setObjectName(QStringLiteral("octreeCutLabel"));
    cutLabel_->setWordWrap(true);
    cutLabel_->setTextFormat(Qt::PlainText);
    layout->addWidget(cutLabel_);

    auto* coarserAction = new QAction(tr("Coarser node level"), this);
    coarserAction->setShortcut(QKeySequence(Qt::Key_BracketRight));
    coarserAction->setShortcutContext(Qt::WindowShortcut);
    connect(coarserAction, &QAction::triggered, this, &OctreeTuningPanel::coarser);
    auto* finerAction = new QAction(tr("Finer node level"), this);
    finerAction->setShortcut(QKeySequence(Qt::Key_BracketLeft));
    finerAction->setShortcutContext(Qt::WindowShortcut);
    connect(finerAction, &QAction::triggered, this, &OctreeTuningPanel::finer);
    // On the views (always shown), not on this panel: a window shortcut needs its widget visible, and the
    // dock may sit behind another tab.
    views_->addAction(coarserAction);
    views_->addAction(finerAction);

    debounce_ = new QTimer(this);
    debounce_->setSingleShot(true);
    debounce_->setInterval(debounceMs);
    connect(debounce_, &QTimer::timeout, this, &OctreeTuningPanel::startBuild);
    build_ = new LatestJob([this] { return makeBuild(); }, this);
    connect(build_, &LatestJob::progressChanged, this, [this](double fraction, const QString& stage) {
        status_->setText(tr("%1 %2 %").arg(stage).arg(int(fraction * 100)));
    });
    connect(build_, &LatestJob::failed, this, [this](const QString& error) {
        status_->setText(error);
        showStats();
        updateUi();
        emit logMessage(error);
        emit built(false, error);
    });
    connect(build_, &LatestJob::changed, this, &OctreeTuningPanel::updateUi);
    cutJob_ = new LatestJob([this] { return makeCut(); }, this);
    // In steps of 10 %: every repaint of the dock is a composition of the window on the GUI thread.
    connect(cutJob_, &LatestJob::progressChanged, this, [this](double fraction, const QString& stage) {
        const int step = int(fraction * 10);
        if (step == cutProgressStep_) return;
        cutProgressStep_ = step;
        status_->setText(tr("Cut: %1 %2 %").arg(stage).arg(step * 10));
    });
    connect(cutJob_, &LatestJob::failed, this, [this](const QString& error) {
        status_->setText(error);
        emit logMessage(error);
    });
    connect(cutJob_, &LatestJob::changed, this, &OctreeTuningPanel::updateUi);

    connect(buildButton_, &QPushButton::clicked, this, &OctreeTuningPanel::build);
    connect(cancelButton_, &QPushButton::clicked, this, &OctreeTuningPanel::cancel);
    connect(viewDependentBox_, &QCheckBox::toggled, this, &OctreeTuningPanel::setViewDependent);
    connect(treeBox_, &QCheckBox::toggled, this, &OctreeTuningPanel::setShowTree);
    connect(cullingBox_, &QCheckBox::toggled, this, &OctreeTuningPanel::setFrustumCulling);
    connect(screenSlider_, &QSlider::valueChanged, this, [this] {
        screenValue_->setText(QStringLiteral("%1 px").arg(screenError(), 0, 'f', 1));
        if (viewDependent_ && store_) cutJob_->request();
    });
    connect(coarserButton_, &QPushButton::clicked, this, &OctreeTuningPanel::coarser);
    connect(finerButton_, &QPushButton::clicked, this, &OctreeTuningPanel::finer);
    connect(views_->singleView(), &VtkView::cameraChanged, this, [this] {
        if (viewDependent_ && store_) cutJob_->request();
    });
    views_->singleView()->installEventFilter(this);  // a resize changes the viewport the cut is for
    connect(views_->singleView(), &VtkView::clicked, this, [this](QPoint position) {
        if (!pickButton_->isChecked()) return;
        pickButton_->setChecked(false);
        if (!pickNodeAt(position)) emit logMessage(tr("Octree: no node of the cut under the cursor"));
    });
    connect(views_, &LevelViews::inspectionEnded, this, [this](const QObject* owner) {
        if (owner != this) return;
        viewDependent_ = false;
        cutJob_->cancel();
        const QSignalBlocker block(viewDependentBox_);
        viewDependentBox_->setChecked(false);
        updateUi();
    });
    screenValue_->setText(QStringLiteral("%1 px").arg(screenError(), 0, 'f', 1));
    updateUi();
}

bool OctreeTuningPanel::eventFilter(QObject* watched, QEvent* event) {
    if (watched == views_->singleView() && event->type() == QEvent::Resize && viewDependent_ && store_)
        cutJob_->request();
    return QWidget::eventFilter(watched, event);
}

OctreeTuningPanel::~OctreeTuningPanel() {
    // Both cancelled first, so that they stop side by side; each LatestJob then waits for its jobs, also
    // those let go. They hold the store and its directory themselves.
    build_->cancel();
    cutJob_->cancel();
}

void OctreeTuningPanel::setModel(std::shared_ptr<const LoadedModel> model) {
    cancel();
    cutJob_->cancel();
    views_->clearInspection(this);
    viewDependent_ = false;
    {
        const QSignalBlocker block(viewDependentBox_);
        viewDependentBox_->setChecked(false);
    }
    store_.reset();
    storeLock_.reset();
    dir_.reset();
    stats_ = {};
    cut_.clear();
    cutMesh_ = {};
    pin_ = UINT32_MAX;
    wanted_ = false;
    model_ = std::move(model);
    status_->clear();
    showStats();
    updateUi();
}

void OctreeTuningPanel::setPreset(const Preset& preset) {
    OctreeBuildParams p;
    p.max_triangles = preset.octree.max_triangles_per_node;
    p.max_depth = static_cast<int>(preset.octree.max_depth);
    p.memory_bytes = std::size_t{preset.octree.memory_mb} << 20;
    p.weights = preset.weights;
    const bool knobsChanged = p.max_triangles != params_.max_triangles || p.max_depth != params_.max_depth ||
                              p.memory_bytes != params_.memory_bytes;
    params_ = p;
    if (knobsChanged && wanted_ && model_) {
        status_->setText(tr("Knobs changed: rebuilding…"));
        debounce_->start();
    }
    updateUi();
}

bool OctreeTuningPanel::rebuildPending() const { return debounce_->isActive(); }

void OctreeTuningPanel::build() {
    wanted_ = true;
    startBuild();
}

void OctreeTuningPanel::cancel() {
    debounce_->stop();
    if (isCutting()) {
        cutJob_->cancel();
        status_->setText(tr("Cut cancelled: the view keeps the cut it shows"));
    }
    if (isBuilding()) {
        build_->cancel();  // its result is dropped
        status_->setText(tr("Octree build cancelled"));
    }
    updateUi();
}

bool OctreeTuningPanel::isBuilding() const { return build_->isBusy(); }

void OctreeTuningPanel::startBuild() {
    debounce_->stop();
    // A build still running is superseded by the newer knob setting: it is cancelled, and this one starts
    // once it has stopped (one build at a time keeps the memory budget).
    if (model_) build_->requestNow();
}

std::optional<LatestJob::Run> OctreeTuningPanel::makeBuild() {
    if (!model_) return std::nullopt;
    struct Output {
        std::unique_ptr<OctreeStore> store;
        OctreeBuildResult result;
    };
    auto out = std::make_shared<Output>();
    auto dir = std::make_shared<QTemporaryDir>();
    if (!dir->isValid()) {
        status_->setText(tr("Octree: no temporary directory: %1").arg(dir->errorString()));
        return std::nullopt;
    }
    const std::shared_ptr<const LoadedModel> model = model_;
    const OctreeBuildParams params = params_;
    const bool isPly = QFileInfo(model->path).suffix().compare(QStringLiteral("ply"), Qt::CaseInsensitive) == 0;
    const std::string source = QFile::encodeName(model->path).toStdString();
    const std::string folder = QFile::encodeName(dir->path()).toStdString();
    status_->setText(tr("Building the octree (max %L1 triangles per leaf, max depth %2)…")
                         .arg(params.max_triangles)
                         .arg(params.max_depth));
    return LatestJob::Run{
        tr("Octree"),
        [out, model, params, isPly, source, folder](Progress* p) {
            // The octree streams a PLY from disk; other formats (in memory here) are written as one.
            std::string ply = source;
            if (!isPly) {
                ply = folder + "/input.ply";
                write_mesh(model->mesh, ply);
            }
            const std::string asset = folder + "/asset.lfoct";
            out->result = build_octree(ply, asset, params, p);
            out->store = std::make_unique<OctreeStore>(asset);
        },
        [this, out, dir, model, params](const JobResult& r) {
            if (model != model_) return;
            cutJob_->cancel();  // of the previous asset
            store_ = std::move(out->store);
            storeLock_ = std::make_shared<std::mutex>();
            dir_ = dir;
            stats_ = store_->stats();
            builtParams_ = params;
            pin_ = UINT32_MAX;
            QString warnings;
            for (const std::string& w : out->result.warnings) warnings += QStringLiteral("; ") + QString::fromStdString(w);
            status_->setText(tr("Built in %1 ms%2").arg(r.elapsedMs).arg(warnings));
            const QString message = tr("Octree built in %1 ms: %2%3").arg(r.elapsedMs).arg(statsText(), warnings);
            showStats();
            updateUi();
            if (viewDependent_) updateCut();
            if (!viewDependent_) showTreeCells();
            emit logMessage(message);
            emit built(true, message);
        }};
}

QString OctreeTuningPanel::statsText() const {
    if (!store_) return {};
    return tr("%L1 nodes · %L2 leaves · depth %3 reached (max %4) · at most %L5 triangles per leaf (knob %L6)")
        .arg(stats_.nodes)
        .arg(stats_.leaves)
        .arg(stats_.depth_reached)
        .arg(builtParams_.max_depth)
        .arg(stats_.max_leaf_triangles)
        .arg(builtParams_.max_triangles);
}

void OctreeTuningPanel::showStats() {
    statsLabel_->setText(store_ ? statsText() : tr("No octree built"));
    levels_->setRowCount(0);
    if (!store_) return;
    const QLocale locale;
    levels_->setRowCount(int(stats_.triangles_per_level.size()));
    for (std::size_t l = 0; l < stats_.triangles_per_level.size(); ++l) {
        const QString name = l == 0 ? tr("0 (input)") : QString::number(l);
        levels_->setItem(int(l), 0, new QTableWidgetItem(name));
        auto* count = new QTableWidgetItem(locale.toString(qulonglong(stats_.triangles_per_level[l])));
        count->setData(Qt::UserRole, qulonglong(stats_.triangles_per_level[l]));
        count->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
        levels_->setItem(int(l), 1, count);
    }
}

void OctreeTuningPanel::setViewDependent(bool on) {
    {
        const QSignalBlocker block(viewDependentBox_);
        viewDependentBox_->setChecked(on);
    }
    viewDependent_ = on;
    if (on) {
        updateCut();
    } else {
        cutJob_->cancel();
        views_->clearInspection(this);
        showTreeCells();
    }
    updateUi();
}

void OctreeTuningPanel::setShowTree(bool on) {
    {
        const QSignalBlocker block(treeBox_);
        treeBox_->setChecked(on);
    }
    if (viewDependent_) return;
    if (on) {
        showTreeCells();
    } else {
        views_->clearInspection(this);
    }
}

bool OctreeTuningPanel::showTree() const { return treeBox_->isChecked(); }

void OctreeTuningPanel::showTreeCells() {
    if (!store_ || !model_ || viewDependent_ || !treeBox_->isChecked()) return;
    std::vector<StructureCell> cells;
    for (const OctreeCell& c : store_->cells())
        cells.push_back({{c.min[0], c.min[1], c.min[2]}, c.size, c.depth, c.leaf, c.triangles});
    const QLocale locale;
    views_->setInspection(this, model_->scene, buildCellsScene(cells),
                          tr("Octree · %1 nodes · %2 leaves · depth %3 · the tree's cells over the original")
                              .arg(locale.toString(qulonglong(stats_.nodes)))
                              .arg(locale.toString(qulonglong(stats_.leaves)))
                              .arg(stats_.depth_reached));
}

double OctreeTuningPanel::screenError() const { return screenSlider_->value() * pixelsPerStep; }

void OctreeTuningPanel::setScreenError(double pixels) {
    screenSlider_->setValue(int(std::lround(pixels / pixelsPerStep)));
    if (viewDependent_) updateCut();
}

void OctreeTuningPanel::setFrustumCulling(bool on) {
    culling_ = on;
    {
        const QSignalBlocker block(cullingBox_);
        cullingBox_->setChecked(on);
    }
    if (viewDependent_) updateCut();
}

bool OctreeTuningPanel::isCutting() const { return cutJob_->isBusy(); }

bool OctreeTuningPanel::isCutWorkerBusy() const { return cutJob_->isWorkerBusy(); }

int OctreeTuningPanel::cutsShown() const { return cutJob_->shownCount(); }

// Superseded (cancelled for a newer request, or arrived after it) or let go (Cancel, another asset).
int OctreeTuningPanel::cutsDropped() const {
    return cutJob_->droppedCount() + cutJob_->cancelledCount() + cutJob_->letGoCount();
}

void OctreeTuningPanel::updateCut() {
    if (!store_ || !viewDependent_ || !model_) return;
    cutJob_->requestNow();  // the running cut's result would arrive superseded: it is cancelled
}

std::optional<LatestJob::Run> OctreeTuningPanel::makeCut() {
    if (!store_ || !model_ || !viewDependent_) return std::nullopt;
    // The camera, viewport and pin of now: a request made while this runs asks for a newer one.
    VtkView* view = views_->singleView();
    const VtkView::ViewCamera c = view->viewCamera();
    Camera camera;
    camera.eye = {float(c.position[0]), float(c.position[1]), float(c.position[2])};
    camera.target = {float(c.focalPoint[0]), float(c.focalPoint[1]), float(c.focalPoint[2])};
    camera.up = {float(c.viewUp[0]), float(c.viewUp[1]), float(c.viewUp[2])};
    camera.fov_y_degrees = float(c.viewAngle);
    const qreal ratio = view->devicePixelRatioF();
    camera.viewport_width = std::max(1, int(view->width() * ratio));
    camera.viewport_height = std::max(1, int(view->height() * ratio));
    SelectParams select;
    select.screen_error_pixels = float(screenError());
    select.frustum_culling = culling_;
    struct Output {
        Cut cut;
        Mesh mesh;
        std::size_t culled = 0;
        std::shared_ptr<const MeshScene> scene;
        std::shared_ptr<const MeshScene> cells;
    };
    auto out = std::make_shared<Output>();
    const std::shared_ptr<QTemporaryDir> dir = dir_;  // the store reads its files from there
    const std::shared_ptr<OctreeStore> store = store_;
    const std::shared_ptr<std::mutex> lock = storeLock_;
    const std::shared_ptr<const LoadedModel> model = model_;
    const std::uint32_t pin = pin_;
    const int pinLevel = pinLevel_;
    cutProgressStep_ = -1;
    return LatestJob::Run{
        tr("Octree cut"),
        [out, dir, store, lock, model, camera, select, pin, pinLevel](Progress* p) {
            const std::lock_guard<std::mutex> guard(*lock);
            const SelectResult s = select_cut(*store, camera, select);
            out->culled = s.culled_nodes;
            out->cut = pinnedCut(*store, s.cut, pin, pinLevel);
            checkCancelled(p);
            out->mesh = extract_mesh(*store, out->cut, p);
            out->mesh.materials = model->mesh.materials;
            out->mesh.source_dir = model->mesh.source_dir;
            checkCancelled(p);
            std::vector<StructureCell> cells;
            cells.reserve(out->cut.size());
            for (const CutNode& n : out->cut) {
                const OctreeNode& node = store->node(n.node);
                StructureCell cell;
                std::copy(node.cell_min, node.cell_min + 3, cell.min);
                cell.size = node.cell_size;
                cell.depth = cutLevel(*store, n);  // the overlay's depth colours show the level here
                cell.leaf = node.is_leaf();
                cell.triangles = n.raw ? node.raw_triangles : node.mesh_triangles;
                cells.push_back(cell);
            }
            out->scene = buildMeshScene(out->mesh, model->images);
            checkCancelled(p);
            out->cells = buildCellsScene(cells);
        },
        [this, out, select](const JobResult& r) {
            cut_ = std::move(out->cut);
            cutMesh_ = std::move(out->mesh);
            const QLocale locale;
            QString text = tr("Octree cut · %1 px · %2 triangles · %3 nodes, %4 culled")
                               .arg(double(select.screen_error_pixels), 0, 'f', 1)
                               .arg(locale.toString(qulonglong(cutMesh_.triangle_count())))
                               .arg(locale.toString(qulonglong(cut_.size())))
                               .arg(locale.toString(qulonglong(out->culled)));
            if (pin_ != UINT32_MAX) text += tr(" · node %1 at level %2").arg(pin_).arg(pinLevel_);
            cutLabel_->setText(text);
            status_->setText(tr("Cut made in %1 ms").arg(r.elapsedMs));
            views_->setInspection(this, out->scene, out->cells, text);
            emit cutUpdated();
        }};
}

bool OctreeTuningPanel::pickNodeAt(QPoint position) {
    if (!store_ || cut_.empty()) return false;
    const std::optional<std::array<double, 3>> p = views_->singleView()->surfacePointAt(position);
    if (!p) return false;
    // The smallest cut node whose triangles' bounds hold the point (triangles go by centroid, so bounds,
    // not cells); tolerance for the picker's rounding.
    const double tolerance = 1e-4 * double(store_->node(0).cell_size);
    std::uint32_t best = UINT32_MAX;
    int bestLevel = 0;
    double bestVolume = std::numeric_limits<double>::infinity();
    for (const CutNode& c : cut_) {
        const OctreeNode& n = store_->node(c.node);
        bool inside = true;
        double volume = 1;
        for (int k = 0; k < 3; ++k) {
            inside = inside && (*p)[k] >= n.bounds_min[k] - tolerance && (*p)[k] <= n.bounds_max[k] + tolerance;
            volume *= double(n.bounds_max[k] - n.bounds_min[k]);
        }
        if (inside && volume < bestVolume) {
            bestVolume = volume;
            best = c.node;
            bestLevel = cutLevel(*store_, c);
        }
    }
    if (best == UINT32_MAX) return false;
    return pinNode(best, bestLevel);
}

bool OctreeTuningPanel::pinNode(std::uint32_t node, int level) {
    if (!store_ || node >= store_->nodes().size()) return false;
    const OctreeNode& n = store_->node(node);
    pin_ = node;
    pinLevel_ = std::clamp(level, 0, n.height + 1);
    emit logMessage(tr("Octree: node %1 (depth %2) pinned at level %3").arg(node).arg(n.depth).arg(pinLevel_));
    updateCut();
    updateUi();
    return true;
}

void OctreeTuningPanel::coarser() {
    if (!store_ || pin_ == UINT32_MAX) return;
    const OctreeNode& n = store_->node(pin_);
    if (pinLevel_ < n.height + 1) {
        ++pinLevel_;
    } else if (n.parent != UINT32_MAX && n.parent < store_->nodes().size()) {
        pin_ = n.parent;
        pinLevel_ = store_->node(pin_).height + 1;
    } else {
        return;  // the root's simplified mesh: nothing coarser
    }
    updateCut();
    updateUi();
}

void OctreeTuningPanel::finer() {
    if (!store_ || pin_ == UINT32_MAX || pinLevel_ == 0) return;
    --pinLevel_;
    updateCut();
    updateUi();
}

void OctreeTuningPanel::unpin() {
    pin_ = UINT32_MAX;
    updateCut();
    updateUi();
}

std::optional<std::uint32_t> OctreeTuningPanel::pinnedNode() const {
    if (pin_ == UINT32_MAX) return std::nullopt;
    return pin_;
}

void OctreeTuningPanel::updateUi() {
    buildButton_->setEnabled(model_ != nullptr);
    cancelButton_->setEnabled(isBuilding() || debounce_->isActive() || isCutting());
    viewDependentBox_->setEnabled(store_ != nullptr);
    const bool cutShown = store_ && viewDependent_;
    pickButton_->setEnabled(cutShown);
    coarserButton_->setEnabled(cutShown && pin_ != UINT32_MAX);
    finerButton_->setEnabled(cutShown && pin_ != UINT32_MAX && pinLevel_ > 0);
    if (!cutShown) cutLabel_->setText(store_ ? tr("Tick the view-dependent cut to see it in the view") : QString());
}

}  // namespace lodforge::widgets
