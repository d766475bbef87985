#include "lodforge/widgets/McoPriorityPanel.h"

#include "lodforge/error.h"
#include "lodforge/pack/preset_levels.h"
#include "lodforge/widgets/Job.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/MeshScene.h"

#include <QElapsedTimer>
#include <QFile>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QProgressBar>
#include <QPushButton>
#include <QSlider>
#include <QSpinBox>
#include <QVBoxLayout>

#include <algorithm>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

namespace lodforge::widgets {

// The extractor is not thread-safe and keeps a pointer to the tree: both live here, at a fixed address,
// shared by the panel and every extraction job. An extraction that was let go (a newer request, Cancel)
// may still be finishing when the next one starts; the lock makes the next one wait for it.
struct McoPriorityPanel::Built {
    explicit Built(McOctree t) : tree(std::move(t)), extractor(tree) {}
    const McOctree tree;
    std::mutex mutex;
    McOctreeExtractor extractor;
};

// What an extraction job hands back; written on the worker, read on the GUI thread after finished().
struct McoPriorityPanel::Extraction {
    std::uint64_t triangles = 0;
    std::size_t cells = 0;
    std::shared_ptr<const MeshScene> scene;
    std::shared_ptr<const MeshScene> cellsScene;
    double ms = 0;
    QString timing;
};

namespace {

void checkCancelled(Progress* progress) {
    if (progress && progress->cancelled()) throw Error(Error::Kind::cancelled, "MC octree extraction cancelled");
}

double msSince(const QElapsedTimer& clock, qint64 since) { return double(clock.nsecsElapsed() - since) / 1e6; }

}  // namespace

McoPriorityPanel::McoPriorityPanel(LevelViews* views, QWidget* parent) : QWidget(parent), views_(views) {
    auto* layout = new QVBoxLayout(this);
    auto* buttons = new QHBoxLayout;
    buildButton_ = new QPushButton(tr("Build MC octree"), this);
    buildButton_->setObjectName(QStringLiteral("mcoBuild"));
    buildButton_->setToolTip(tr("Rebuild the loaded mesh's surface with marching cubes on an octree, at the "
                                "Parameters' marching-cube resolution"));
    cancelButton_ = new QPushButton(tr("Cancel"), this);
    cancelButton_->setObjectName(QStringLiteral("mcoCancel"));
    cancelButton_->setToolTip(tr("Stop the build or the extraction; the view keeps the mesh it shows"));
    buttons->addWidget(buildButton_);
    buttons->addWidget(cancelButton_);
    buttons->addStretch(1);
    layout->addLayout(buttons);
    status_ = new QLabel(this);
    status_->setObjectName(QStringLiteral("mcoStatus"));
    status_->setWordWrap(true);
    layout->addWidget(status_);
    progress_ = new QProgressBar(this);
    progress_->setObjectName(QStringLiteral("mcoProgress"));
    progress_->setRange(0, 1000);
    progress_->setTextVisible(false);
    QSizePolicy keepSpace = progress_->sizePolicy();
    keepSpace.setRetainSizeWhenHidden(true);  // shown while busy without moving the slider under the mouse
    progress_->setSizePolicy(keepSpace);
    progress_->setVisible(false);
    layout->addWidget(progress_);
    layout->addWidget(new QLabel(tr("Priority (0 = the root alone, right = every leaf)"), this));
    slider_ = new QSlider(Qt::Horizontal, this);
    slider_->setObjectName(QStringLiteral("mcoPrioritySlider"));
    slider_->setToolTip(tr("The first N nodes of the priority order are expanded"));
    layout->addWidget(slider_);
    label_ = new QLabel(this);
    label_->setObjectName(QStringLiteral("mcoPriorityLabel"));
    label_->setTextFormat(Qt::PlainText);
    label_->setWordWrap(true);
    layout->addWidget(label_);
    auto* budgetRow = new QHBoxLayout;
    budgetRow->addWidget(new QLabel(tr("At most"), this));
    budget_ = new QSpinBox(this);
    budget_->setObjectName(QStringLiteral("mcoTriangleBudget"));
    budget_->setRange(1, std::numeric_limits<int>::max());
    budget_->setValue(50000);
    budget_->setGroupSeparatorShown(true);
    budget_->setSuffix(tr(" triangles"));
    budget_->setKeyboardTracking(false);
    budget_->setToolTip(tr("Move the slider to the finest priority within this triangle budget"));
    budgetRow->addWidget(budget_, 1);
    layout->addLayout(budgetRow);
    layout->addStretch(1);

    build_ = new LatestJob([this] { return makeBuild(); }, this);
    connect(build_, &LatestJob::progressChanged, this, [this](double fraction, const QString& stage) {
        status_->setText(tr("%1 %2 %").arg(stage).arg(int(fraction * 100)));
        progress_->setValue(int(fraction * 1000));
    });
    connect(build_, &LatestJob::failed, this, [this](const QString& error) {
        status_->setText(error);
        emit logMessage(error);
        emit built(false, error);
    });
    connect(build_, &LatestJob::changed, this, &McoPriorityPanel::updateUi);
    extraction_ = new LatestJob([this] { return makeExtraction(); }, this);
    connect(extraction_, &LatestJob::progressChanged, this,
            [this](double fraction, const QString&) { progress_->setValue(int(fraction * 1000)); });
    connect(extraction_, &LatestJob::failed, this, [this](const QString& error) {
        status_->setText(error);
        emit logMessage(error);
    });
    connect(extraction_, &LatestJob::changed, this, &McoPriorityPanel::updateUi);
    connect(buildButton_, &QPushButton::clicked, this, &McoPriorityPanel::build);
    connect(budget_, &QSpinBox::valueChanged, this, [this](int value) { setTriangleBudget(std::uint64_t(value)); });
    connect(cancelButton_, &QPushButton::clicked, this, &McoPriorityPanel::cancel);
    connect(slider_, &QSlider::valueChanged, this, [this](int value) {
        requested_ = std::size_t(std::max(0, value));
        request();
    });
    connect(views_, &LevelViews::inspectionEnded, this, [this](const QObject* owner) {
        if (owner != this) return;
        // Another view took the single view: nothing waits to be shown any more.
        extraction_->cancel();
    });
    connect(views_, &LevelViews::viewOptionsChanged, this, [this](const ViewOptions& options) {
        if (views_->inspectionOwner() == this && options.cells && !cellsBuilt_) request();
    });
    updateUi();
}

McoPriorityPanel::~McoPriorityPanel() {
    // Both cancelled first, so that they stop side by side; each LatestJob then waits for its jobs, also
    // those let go. The extractions hold the tree themselves, so it goes with the last of them.
    build_->cancel();
    extraction_->cancel();
}

bool McoPriorityPanel::isBuilding() const { return build_->isBusy(); }

const McOctree* McoPriorityPanel::tree() const { return built_ ? &built_->tree : nullptr; }

std::weak_ptr<const McOctree> McoPriorityPanel::treeHandle() const {
    if (!built_) return {};
    return std::shared_ptr<const McOctree>(built_, &built_->tree);
}

bool McoPriorityPanel::isExtracting() const { return extraction_->isBusy(); }

bool McoPriorityPanel::isWorkerBusy() const { return extraction_->isWorkerBusy(); }

int McoPriorityPanel::extractionsRun() const { return extraction_->shownCount(); }

int McoPriorityPanel::resultsDropped() const { return extraction_->droppedCount(); }

int McoPriorityPanel::extractionsCancelled() const { return extraction_->cancelledCount(); }

void McoPriorityPanel::setModel(std::shared_ptr<const LoadedModel> model) {
    cancel();
    views_->clearInspection(this);
    built_.reset();  // running jobs keep their own reference until they end
    model_ = std::move(model);
    shown_ = requested_ = 0;
    shownTriangles_ = 0;
    shownCells_ = 0;
    status_->clear();
    updateUi();
}

void McoPriorityPanel::setPreset(const Preset& preset) {
    resolution_ = preset.mcoctree.resolution;
    updateUi();
}

void McoPriorityPanel::build() {
    if (!model_ || build_->isBusy()) return;
    status_->setText(tr("Building at resolution %1…").arg(resolution_));
    build_->requestNow();
}

std::optional<LatestJob::Run> McoPriorityPanel::makeBuild() {
    if (!model_) return std::nullopt;
    struct Output {
        McOctreeBuildResult result;
        std::shared_ptr<Built> built;
    };
    auto out = std::make_shared<Output>();
    McOctreeParams params;
    params.resolution = resolution_;
    const std::shared_ptr<const LoadedModel> model = model_;
    return LatestJob::Run{
        tr("MC octree"),
        [out, model, params](Progress* p) {
            try {
                out->result = build_mc_octree(model->mesh, params, p);
            } catch (const Error& e) {
                // The core names its input generically; the artist knows it by its file (as the CLI says).
                std::string what = e.what();
                const std::string generic = "mcoctree input: ";
                if (what.rfind(generic, 0) == 0) what = what.substr(generic.size());
                if (e.kind() == Error::Kind::cancelled) throw;
                throw_error(e.kind(), QFile::encodeName(model->path).toStdString(), what);
            }
            // The extractor's tables are built once per tree, here rather than on the GUI thread.
            p->report(1.0, "extraction tables");
            out->built = std::make_shared<Built>(std::move(out->result.tree));
        },
        [this, out, model](const JobResult& r) {
            if (model != model_) return;
            views_->clearInspection(this);
            extraction_->cancel();  // of the previous tree
            built_ = std::move(out->built);
            const McOctree& tree = built_->tree;
            QString message = tr("MC octree: %L1 nodes, %L2 priorities, %L3 to %L4 triangles, built in %5 ms")
                          .arg(tree.nodes.size())
                          .arg(tree.max_priority())
                          .arg(mc_triangles_at(tree, 0))
                          .arg(mc_triangles_at(tree, tree.max_priority()))
                          .arg(r.elapsedMs);
            if (out->result.face_samples > 0)
                message += tr("; %L1 points added on the %L2 faces longer than two cubes")
                               .arg(qulonglong(out->result.face_samples))
                               .arg(qulonglong(out->result.sampled_faces));
            for (const std::string& w : out->result.warnings) message += QStringLiteral("; ") + QString::fromStdString(w);
            {
                const QSignalBlocker block(slider_);
                slider_->setRange(0, int(tree.max_priority()));
                slider_->setValue(int(tree.max_priority()));
            }
            shown_ = requested_ = tree.max_priority();
            shownTriangles_ = 0;
            updateUi();
            setPriority(tree.max_priority());
            status_->setText(message);
            emit logMessage(message);
            emit built(true, message);
        }};
}

void McoPriorityPanel::cancel() {
    build_->cancel();  // its result is dropped
    if (isExtracting()) {
        extraction_->cancel();
        requested_ = shown_;
        const QSignalBlocker block(slider_);
        slider_->setValue(int(shown_));
        status_->setText(tr("Extraction cancelled: the view keeps priority %L1").arg(shown_));
    }
    updateUi();
}

void McoPriorityPanel::setPriority(std::size_t priority) {
    if (!built_) return;
    requested_ = std::min(priority, built_->tree.max_priority());
    {
        const QSignalBlocker block(slider_);
        slider_->setValue(int(requested_));
    }
    request();
}

void McoPriorityPanel::setTriangleBudget(std::uint64_t triangles) {
    if (built_) setPriority(mc_priority_for_triangles(built_->tree, triangles));
}

void McoPriorityPanel::request() {
    if (!built_) return;
    newest_ = Request{requested_, views_->viewOptions().cells};
    // The moves of this turn of the event loop make one request; the same index and overlay as the
    // running extraction's is that extraction's request.
    extraction_->request(std::uint64_t(newest_.priority) << 1 | std::uint64_t(newest_.cells));
}

std::optional<LatestJob::Run> McoPriorityPanel::makeExtraction() {
    if (!built_) return std::nullopt;
    const Request request = newest_;
    const std::shared_ptr<Built> built = built_;
    auto out = std::make_shared<Extraction>();
    return LatestJob::Run{
        tr("MC octree extraction"),
        [built, request, out](Progress* p) {
            QElapsedTimer clock;
            clock.start();
            p->report(0.0, "extracting");
            const std::lock_guard<std::mutex> lock(built->mutex);
            const McExtraction& e = built->extractor.extract(request.priority);
            const double extractMs = msSince(clock, 0);
            out->triangles = e.mesh.triangle_count();
            checkCancelled(p);
            // The cut's cells only while the overlay is shown: on a fine cut they cost more than the mesh.
            const qint64 cellsStart = clock.nsecsElapsed();
            std::vector<StructureCell> cells;
            if (request.cells) {
                p->report(0.2, "cells");
                for (const McCell& c : built->extractor.cells(request.priority)) {
                    StructureCell cell;
                    for (int k = 0; k < 3; ++k) cell.min[k] = c.min[k];
                    cell.size = c.size;
                    cell.depth = int(built->tree.levels) - int(c.level);  // McCell counts levels from the leaves
                    cell.leaf = c.level == 0;
                    cells.push_back(cell);
                }
                checkCancelled(p);
            }
            out->cells = cells.size();
            const double cellsMs = msSince(clock, cellsStart);
            p->report(0.3, "scene");
            const qint64 sceneStart = clock.nsecsElapsed();
            out->scene = buildMeshScene(e.mesh, {});
            const double sceneMs = msSince(clock, sceneStart);
            checkCancelled(p);
            p->report(0.8, "cells scene");
            const qint64 cellsSceneStart = clock.nsecsElapsed();
            out->cellsScene = buildCellsScene(cells);
            const double cellsSceneMs = msSince(clock, cellsSceneStart);
            out->ms = msSince(clock, 0);
            out->timing = QStringLiteral("extract %1 ms, cells %2 ms, scene %3 ms, cells scene %4 ms")
                              .arg(extractMs, 0, 'f', 1)
                              .arg(cellsMs, 0, 'f', 1)
                              .arg(sceneMs, 0, 'f', 1)
                              .arg(cellsSceneMs, 0, 'f', 1);
        },
        [this, request, out](const JobResult&) { showExtraction(request, *out); }};
}

void McoPriorityPanel::showExtraction(const Request& request, const Extraction& out) {
    QElapsedTimer clock;
    clock.start();
    shown_ = request.priority;
    shownTriangles_ = out.triangles;
    shownCells_ = out.cells;
    cellsBuilt_ = request.cells;
    views_->setInspection(this, out.scene, out.cellsScene, labelText());
    lastWorkMs_ = out.ms;
    lastShowMs_ = double(clock.nsecsElapsed()) / 1e6;
    timing_ = out.timing + QStringLiteral(", view %1 ms").arg(lastShowMs_, 0, 'f', 1);
    label_->setToolTip(timing_);
    emit extracted(shown_, shownTriangles_);
}

QString McoPriorityPanel::labelText() const {
    if (!built_) return {};
    return tr("MC octree priority %L1 / %L2 · %L3 triangles")
        .arg(shown_)
        .arg(built_->tree.max_priority())
        .arg(shownTriangles_);
}

void McoPriorityPanel::updateLabel() {
    if (!built_) {
        label_->setText(model_ ? tr("Build the octree to extract its levels") : tr("Open a mesh first"));
        return;
    }
    if (!isExtracting()) {
        label_->setText(labelText());
        return;
    }
    // The count of the index asked for is known before its mesh is (the tree's cumulative table).
    label_->setText(tr("%1 · extracting priority %L2 (%L3 triangles)…")
                        .arg(labelText())
                        .arg(requested_)
                        .arg(mc_triangles_at(built_->tree, requested_)));
}

void McoPriorityPanel::updateUi() {
    buildButton_->setEnabled(model_ && !isBuilding());
    buildButton_->setText(tr("Build MC octree (resolution %1)").arg(resolution_));
    cancelButton_->setEnabled(isBuilding() || isExtracting());
    slider_->setEnabled(built_ != nullptr);
    budget_->setEnabled(built_ != nullptr);
    const bool busy = isBuilding() || isExtracting();
    if (busy && !progress_->isVisible()) progress_->setValue(0);
    progress_->setVisible(busy);
    updateLabel();
}

}  // namespace lodforge::widgets
