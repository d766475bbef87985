#include "lodforge/widgets/McoPriorityPanel.h"

#include "CoalescedUpdate.h"
#include "lodforge/lod_methods.h"
#include "lodforge/widgets/Job.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/MeshScene.h"

#include <QElapsedTimer>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QPushButton>
#include <QSlider>
#include <QSpinBox>
#include <QVBoxLayout>

#include <algorithm>
#include <limits>
#include <vector>

namespace lodforge::widgets {

McoPriorityPanel::McoPriorityPanel(LevelViews* views, QWidget* parent) : QWidget(parent), views_(views) {
    auto* layout = new QVBoxLayout(this);
    auto* buttons = new QHBoxLayout;
    buildButton_ = new QPushButton(tr("Build MC octree"), this);
    buildButton_->setObjectName(QStringLiteral("mcoBuild"));
    buildButton_->setToolTip(tr("Rebuild the loaded mesh's surface with marching cubes on an octree, at the "
                                "Parameters' marching-cube resolution"));
    cancelButton_ = new QPushButton(tr("Cancel"), this);
    cancelButton_->setObjectName(QStringLiteral("mcoCancel"));
    buttons->addWidget(buildButton_);
    buttons->addWidget(cancelButton_);
    buttons->addStretch(1);
    layout->addLayout(buttons);
    status_ = new QLabel(this);
    status_->setObjectName(QStringLiteral("mcoStatus"));
    status_->setWordWrap(true);
    layout->addWidget(status_);
    layout->addWidget(new QLabel(tr("Priority (0 = the root alone, right = every leaf)"), this));
    slider_ = new QSlider(Qt::Horizontal, this);
    slider_->setObjectName(QStringLiteral("mcoPrioritySlider"));
    slider_->setToolTip(tr("The first N nodes of the priority order are expanded"));
    layout->addWidget(slider_);
    label_ = new QLabel(this);
    label_->setObjectName(QStringLiteral("mcoPriorityLabel"));
    label_->setTextFormat(Qt::PlainText);
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

    update_ = new CoalescedUpdate([this] { show(); }, this);
    connect(buildButton_, &QPushButton::clicked, this, &McoPriorityPanel::build);
    connect(budget_, &QSpinBox::valueChanged, this, [this](int value) { setTriangleBudget(std::uint64_t(value)); });
    connect(cancelButton_, &QPushButton::clicked, this, &McoPriorityPanel::cancel);
    connect(slider_, &QSlider::valueChanged, this, [this](int value) {
        shown_ = std::size_t(std::max(0, value));
        update_->request();
    });
    connect(views_, &LevelViews::inspectionEnded, this, [this](const QObject* owner) {
        if (owner == this) update_->cancel();
    });
    connect(views_, &LevelViews::viewOptionsChanged, this, [this](const ViewOptions& options) {
        if (views_->inspectionOwner() == this && options.cells && !cellsBuilt_) update_->run();
    });
    updateUi();
}

McoPriorityPanel::~McoPriorityPanel() {
    delete job_;  // cancels and waits: the work writes into state this panel shares
}

void McoPriorityPanel::setModel(std::shared_ptr<const LoadedModel> model) {
    cancel();
    views_->clearInspection(this);
    update_->cancel();
    extractor_.reset();
    tree_.reset();
    model_ = std::move(model);
    status_->clear();
    updateUi();
}

void McoPriorityPanel::setPreset(const Preset& preset) {
    resolution_ = preset.mcoctree.resolution;
    updateUi();
}

void McoPriorityPanel::build() {
    if (!model_ || job_) return;
    struct Output {
        McOctreeBuildResult result;
    };
    auto out = std::make_shared<Output>();
    McOctreeParams params;
    params.resolution = resolution_;
    const std::shared_ptr<const LoadedModel> model = model_;
    job_ = new Job(
        tr("MC octree"), [out, model, params](Progress* p) { out->result = build_mc_octree(model->mesh, params, p); },
        this);
    Job* job = job_;
    connect(job, &Job::progressChanged, this, [this](double fraction, const QString& stage) {
        status_->setText(tr("%1 %2 %").arg(stage).arg(int(fraction * 100)));
    });
    connect(job, &Job::finished, this, [this, job, out, model](const JobResult& r) {
        job->deleteLater();
        if (job != job_) return;
        job_ = nullptr;
        QString message;
        const bool ok = r.ok() && model == model_;
        if (ok) {
            views_->clearInspection(this);
            extractor_.reset();
            tree_ = std::make_shared<McOctree>(std::move(out->result.tree));
            extractor_ = std::make_unique<McOctreeExtractor>(*tree_);
            message = tr("MC octree: %L1 nodes, %L2 priorities, %L3 to %L4 triangles, built in %5 ms")
                          .arg(tree_->nodes.size())
                          .arg(tree_->max_priority())
                          .arg(tree_->triangle_counts.front())
                          .arg(tree_->triangle_counts.back())
                          .arg(r.elapsedMs);
            for (const std::string& w : out->result.warnings) message += QStringLiteral("; ") + QString::fromStdString(w);
            {
                const QSignalBlocker block(slider_);
                slider_->setRange(0, int(tree_->max_priority()));
                slider_->setValue(int(tree_->max_priority()));
            }
            updateUi();
            setPriority(tree_->max_priority());
        } else {
            message = r.status == JobResult::Status::cancelled ? tr("MC octree build cancelled") : r.error;
            updateUi();
        }
        status_->setText(message);
        emit logMessage(message);
        emit built(ok, message);
    });
    updateUi();
    status_->setText(tr("Building at resolution %1…").arg(resolution_));
    job->start();
}

void McoPriorityPanel::cancel() {
    if (!job_) return;
    job_->cancel();
    job_ = nullptr;  // its result is dropped; it deletes itself when it ends
    updateUi();
}

void McoPriorityPanel::setPriority(std::size_t priority) {
    if (!tree_) return;
    shown_ = std::min(priority, tree_->max_priority());
    {
        const QSignalBlocker block(slider_);
        slider_->setValue(int(shown_));
    }
    update_->run();
}

void McoPriorityPanel::setTriangleBudget(std::uint64_t triangles) {
    if (tree_) setPriority(mc_priority_for_triangles(*tree_, triangles));
}

double McoPriorityPanel::lastExtractMs() const { return update_->lastMs(); }

QString McoPriorityPanel::labelText() const {
    if (!tree_) return {};
    return tr("MC octree priority %L1 / %L2 · %L3 triangles").arg(shown_).arg(tree_->max_priority()).arg(shownTriangles_);
}

void McoPriorityPanel::show() {
    if (!tree_ || !extractor_) return;
    QElapsedTimer clock;
    clock.start();
    const McExtraction& e = extractor_->extract(shown_);
    const qint64 extracted = clock.nsecsElapsed();
    shownTriangles_ = e.mesh.triangle_count();
    // The cut's cells only while the overlay is shown: on a fine cut they cost more than the mesh.
    std::vector<StructureCell> cells;
    cellsBuilt_ = views_->viewOptions().cells;
    if (cellsBuilt_) {
        for (const McCell& c : extractor_->cells(shown_)) {
            StructureCell cell;
            for (int k = 0; k < 3; ++k) cell.min[k] = c.min[k];
            cell.size = c.size;
            cell.depth = int(tree_->levels) - int(c.level);  // McCell counts levels from the leaves
            cell.leaf = c.level == 0;
            cells.push_back(cell);
        }
    }
    shownCells_ = cells.size();
    const qint64 celled = clock.nsecsElapsed();
    std::shared_ptr<const MeshScene> scene = buildMeshScene(e.mesh, {});
    const qint64 scened = clock.nsecsElapsed();
    std::shared_ptr<const MeshScene> cellsScene = buildCellsScene(cells);
    const qint64 done = clock.nsecsElapsed();
    timing_ = tr("extract %1 ms, cells %2 ms, scene %3 ms, cells scene %4 ms")
                  .arg(double(extracted) / 1e6, 0, 'f', 1)
                  .arg(double(celled - extracted) / 1e6, 0, 'f', 1)
                  .arg(double(scened - celled) / 1e6, 0, 'f', 1)
                  .arg(double(done - scened) / 1e6, 0, 'f', 1);
    label_->setText(labelText());
    label_->setToolTip(timing_);
    views_->setInspection(this, std::move(scene), std::move(cellsScene), labelText());
}

void McoPriorityPanel::updateUi() {
    buildButton_->setEnabled(model_ && !job_);
    buildButton_->setText(tr("Build MC octree (resolution %1)").arg(resolution_));
    cancelButton_->setEnabled(job_ != nullptr);
    slider_->setEnabled(tree_ != nullptr);
    budget_->setEnabled(tree_ != nullptr);
    if (!tree_) label_->setText(model_ ? tr("Build the octree to extract its levels") : tr("Open a mesh first"));
}

}  // namespace lodforge::widgets
