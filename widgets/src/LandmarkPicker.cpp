#include "lodforge/widgets/LandmarkPicker.h"

#include "lodforge/error.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/widgets/LatestJob.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/VtkView.h"

#include <QEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QKeySequence>
#include <QLabel>
#include <QListWidget>
#include <QLocale>
#include <QMouseEvent>
#include <QProgressBar>
#include <QPushButton>
#include <QShortcut>
#include <QVBoxLayout>

#include <limits>

namespace lodforge::widgets {

namespace {

// Pairs in yellow on both meshes; the pick that waits for its partner in orange.
const QColor pairColor(255, 214, 10);
const QColor pendingColor(255, 120, 40);

QString sideName(LandmarkPicker::Side side) { return side == LandmarkPicker::Side::a ? QStringLiteral("A") : QStringLiteral("B"); }

}  // namespace

LandmarkPicker::LandmarkPicker(QWidget* parent) : QWidget(parent) {
    auto* layout = new QVBoxLayout(this);
    auto* grid = new QGridLayout;
    for (Side side : {Side::a, Side::b}) {
        SideState& s = state(side);
        const int column = static_cast<int>(side);
        auto* open = new QPushButton(tr("Open mesh %1…").arg(sideName(side)), this);
        open->setObjectName(QStringLiteral("landmarkOpen%1").arg(sideName(side)));
        open->setToolTip(tr("Open a closed genus-0 mesh (PLY, OBJ, glTF) as mesh %1").arg(sideName(side)));
        connect(open, &QPushButton::clicked, this, [this, side] { showOpenDialog(side); });
        s.label = new QLabel(tr("Mesh %1: none").arg(sideName(side)), this);
        s.label->setObjectName(QStringLiteral("landmarkLabel%1").arg(sideName(side)));
        s.view = new VtkView(this);
        s.view->setObjectName(QStringLiteral("landmarkView%1").arg(sideName(side)));
        s.view->setMinimumSize(200, 200);
        s.view->installEventFilter(this);
        s.load = new LatestJob([this, side] { return makeLoad(side); }, this);
        connect(s.load, &LatestJob::failed, this, [this, side](const QString& error) {
            updateButtons();
            emit meshLoaded(side, false, error);
        });
        connect(s.load, &LatestJob::progressChanged, this, [this, side](double fraction, const QString& stage) {
            loadProgress_->setValue(int(fraction * 1000));
            loadProgress_->setFormat(tr("Mesh %1: %2 %p%").arg(sideName(side), stage));
        });
        connect(s.load, &LatestJob::changed, this, &LandmarkPicker::updateLoadUi);
        auto* head = new QHBoxLayout;
        head->addWidget(open);
        head->addWidget(s.label, 1);
        grid->addLayout(head, 0, column);
        grid->addWidget(s.view, 1, column);
        grid->setColumnStretch(column, 1);
    }
    grid->setRowStretch(1, 1);
    layout->addLayout(grid, 1);
    auto* loadRow = new QHBoxLayout;
    loadProgress_ = new QProgressBar(this);
    loadProgress_->setObjectName(QStringLiteral("landmarkLoadProgress"));
    loadProgress_->setRange(0, 1000);
    cancelLoad_ = new QPushButton(tr("Cancel"), this);
    cancelLoad_->setObjectName(QStringLiteral("landmarkCancelLoad"));
    cancelLoad_->setToolTip(tr("Stop loading; the views keep the meshes they show"));
    connect(cancelLoad_, &QPushButton::clicked, this, &LandmarkPicker::cancelLoads);
    loadRow->addWidget(loadProgress_, 1);
    loadRow->addWidget(cancelLoad_);
    layout->addLayout(loadRow);

    pairList_ = new QListWidget(this);
    pairList_->setObjectName(QStringLiteral("landmarkPairs"));
    pairList_->setMaximumHeight(110);
    layout->addWidget(pairList_);

    auto* buttons = new QHBoxLayout;
    auto button = [this, buttons](const QString& text, const QString& name, const QString& tip) {
        auto* b = new QPushButton(text, this);
        b->setObjectName(name);
        b->setToolTip(tip);
        buttons->addWidget(b);
        return b;
    };
    undoButton_ = button(tr("Undo pair"), QStringLiteral("landmarkUndo"),
                         tr("Drop the waiting pick, or else the last pair (Backspace)"));
    connect(undoButton_, &QPushButton::clicked, this, &LandmarkPicker::undoLastPair);
    clearButton_ = button(tr("Clear"), QStringLiteral("landmarkClear"), tr("Drop every pair"));
    connect(clearButton_, &QPushButton::clicked, this, &LandmarkPicker::clearPairs);
    QPushButton* load = button(tr("Load…"), QStringLiteral("landmarkLoad"), tr("Read a landmarks file (L.json)"));
    connect(load, &QPushButton::clicked, this, &LandmarkPicker::showLoadDialog);
    saveButton_ = button(tr("Save…"), QStringLiteral("landmarkSave"),
                         tr("Write the pairs as a landmarks file (L.json, read by lodforge morph build A B --landmarks)"));
    connect(saveButton_, &QPushButton::clicked, this, &LandmarkPicker::showSaveDialog);
    buttons->addStretch(1);
    buildButton_ = button(tr("Build supermesh"), QStringLiteral("landmarkBuildSupermesh"), QString());
    connect(buildButton_, &QPushButton::clicked, this, &LandmarkPicker::buildSupermeshRequested);
    layout->addLayout(buttons);

    auto* undoKey = new QShortcut(QKeySequence(Qt::Key_Backspace), this);
    undoKey->setContext(Qt::WidgetWithChildrenShortcut);
    connect(undoKey, &QShortcut::activated, this, &LandmarkPicker::undoLastPair);

    // Both views show the same model space from the same side; each keeps its own camera since the two
    // meshes need not share a scale.
    setSupermeshAvailable(false, QString());
    updateButtons();
    updateLoadUi();
}

LandmarkPicker::~LandmarkPicker() {
    // Both cancelled first, so that they stop side by side; each LatestJob then waits for its jobs.
    for (SideState& s : sides_) s.load->cancel();
}

VtkView* LandmarkPicker::view(Side side) const { return state(side).view; }
std::shared_ptr<const Mesh> LandmarkPicker::mesh(Side side) const { return state(side).mesh; }
QString LandmarkPicker::meshPath(Side side) const { return state(side).path; }

bool LandmarkPicker::isLoading() const {
    return sides_[0].load->isBusy() || sides_[1].load->isBusy();
}

void LandmarkPicker::cancelLoads() {
    for (SideState& s : sides_) s.load->cancel();
    emit message(tr("Landmarks: loading cancelled"));
}

void LandmarkPicker::updateLoadUi() {
    const bool loading = isLoading();
    if (loading && loadProgress_->isHidden()) {
        loadProgress_->setValue(0);
        loadProgress_->setFormat(tr("Loading %p%"));
    }
    loadProgress_->setVisible(loading);
    cancelLoad_->setVisible(loading);
}

void LandmarkPicker::openMesh(Side side, const QString& path) {
    SideState& s = state(side);
    s.loadPath = path;
    s.load->requestNow();  // a load of this side still running is cancelled; this one starts when it stopped
}

std::optional<LatestJob::Run> LandmarkPicker::makeLoad(Side side) {
    const QString path = state(side).loadPath;
    struct Output {
        std::shared_ptr<const Mesh> mesh;
        std::shared_ptr<const MeshScene> scene;
    };
    auto out = std::make_shared<Output>();
    const std::string file = path.toStdString();
    return LatestJob::Run{tr("Load mesh %1").arg(sideName(side)), [out, file](Progress* progress) {
        auto mesh = std::make_shared<Mesh>(read_mesh(file, {}, progress));
        if (mesh->vertex_count() == 0 || mesh->triangle_count() == 0)
            throw_error(Error::Kind::invalid, file, "the mesh has no triangles to pick on");
        out->scene = buildMeshScene(*mesh, {});
        out->mesh = std::move(mesh);
    }, [this, side, out, path](const JobResult&) {
        SideState& st = state(side);
        st.mesh = out->mesh;
        st.path = path;
        st.view->setScene(out->scene, true);
        st.label->setText(tr("Mesh %1: %2 · %3 vertices")
                              .arg(sideName(side), QFileInfo(path).fileName(),
                                   QLocale().toString(qulonglong(out->mesh->vertex_count()))));
        clearPairs();
        updateButtons();
        emit meshLoaded(side, true, QString());
    }};
}

std::uint32_t LandmarkPicker::nearestVertex(const Mesh& mesh, const std::array<double, 3>& point) {
    std::uint32_t best = 0;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3f& p = mesh.positions[v];
        const double dx = p.x - point[0], dy = p.y - point[1], dz = p.z - point[2];
        const double d = dx * dx + dy * dy + dz * dz;
        if (d < bestDistance) {
            bestDistance = d;
            best = static_cast<std::uint32_t>(v);
        }
    }
    return best;
}

bool LandmarkPicker::pickVertex(Side side, std::uint32_t vertex, QString* error) {
    auto refuse = [&](const QString& why) {
        if (error) *error = why;
        emit message(why);
        return false;
    };
    SideState& s = state(side);
    if (!s.mesh) return refuse(tr("Landmarks: open mesh %1 first").arg(sideName(side)));
    if (vertex >= s.mesh->vertex_count())
        return refuse(tr("Landmarks: mesh %1 has no vertex %2").arg(sideName(side)).arg(vertex));
    for (std::size_t i = 0; i < landmarks_.pairs.size(); ++i) {
        const LandmarkPair& p = landmarks_.pairs[i];
        if ((side == Side::a ? p.a : p.b) == vertex)
            return refuse(tr("Landmarks: vertex %1 of mesh %2 is already in pair %3")
                              .arg(vertex).arg(sideName(side)).arg(i + 1));
    }
    s.pending = vertex;
    SideState& a = state(Side::a);
    SideState& b = state(Side::b);
    if (a.pending && b.pending) {
        landmarks_.pairs.push_back({*a.pending, *b.pending});
        a.pending.reset();
        b.pending.reset();
        pairList_->addItem(tr("%1: A %2 ↔ B %3").arg(landmarks_.pairs.size()).arg(landmarks_.pairs.back().a)
                               .arg(landmarks_.pairs.back().b));
    }
    updateMarkers();
    updateButtons();
    emit pairsChanged();
    return true;
}

std::optional<std::uint32_t> LandmarkPicker::pendingPick(Side side) const { return state(side).pending; }

void LandmarkPicker::undoLastPair() {
    SideState& a = state(Side::a);
    SideState& b = state(Side::b);
    if (a.pending || b.pending) {
        a.pending.reset();
        b.pending.reset();
    } else if (!landmarks_.pairs.empty()) {
        landmarks_.pairs.pop_back();
        delete pairList_->takeItem(pairList_->count() - 1);
    } else {
        return;
    }
    updateMarkers();
    updateButtons();
    emit pairsChanged();
}

void LandmarkPicker::clearPairs() {
    landmarks_.pairs.clear();
    for (SideState& s : sides_) s.pending.reset();
    pairList_->clear();
    updateMarkers();
    updateButtons();
    emit pairsChanged();
}

bool LandmarkPicker::checkPairs(const Landmarks& landmarks, const QString& source, QString* error) const {
    const SideState& a = state(Side::a);
    const SideState& b = state(Side::b);
    if (!a.mesh || !b.mesh) {
        if (error) *error = tr("%1: open meshes A and B first (the pairs name their vertices)").arg(source);
        return false;
    }
    try {
        check_landmarks(landmarks, a.mesh->vertex_count(), b.mesh->vertex_count(), source.toStdString());
    } catch (const Error& e) {
        if (error) *error = QString::fromUtf8(e.what());
        return false;
    }
    return true;
}

bool LandmarkPicker::saveLandmarks(const QString& path, QString* error) {
    QString why;
    if (!checkPairs(landmarks_, path, &why)) {
        if (error) *error = why;
        return false;
    }
    try {
        write_landmarks(landmarks_, path.toStdString());
    } catch (const Error& e) {
        if (error) *error = QString::fromUtf8(e.what());
        return false;
    }
    emit message(tr("Landmarks: %1 pairs written to %2").arg(landmarks_.pairs.size()).arg(path));
    return true;
}

bool LandmarkPicker::loadLandmarks(const QString& path, QString* error) {
    Landmarks read;
    QString why;
    try {
        read = read_landmarks(path.toStdString());
    } catch (const Error& e) {
        why = QString::fromUtf8(e.what());
    }
    if (why.isEmpty()) checkPairs(read, path, &why);
    if (!why.isEmpty()) {
        if (error) *error = why;
        return false;
    }
    clearPairs();
    landmarks_ = std::move(read);
    for (std::size_t i = 0; i < landmarks_.pairs.size(); ++i)
        pairList_->addItem(tr("%1: A %2 ↔ B %3").arg(i + 1).arg(landmarks_.pairs[i].a).arg(landmarks_.pairs[i].b));
    updateMarkers();
    updateButtons();
    emit pairsChanged();
    emit message(tr("Landmarks: %1 pairs read from %2").arg(landmarks_.pairs.size()).arg(path));
    return true;
}

void LandmarkPicker::updateMarkers() {
    for (Side side : {Side::a, Side::b}) {
        SideState& s = state(side);
        std::vector<ViewMarker> markers;
        if (s.mesh) {
            auto at = [&](std::uint32_t v) {
                const Vec3f& p = s.mesh->positions[v];
                return std::array<double, 3>{p.x, p.y, p.z};
            };
            for (std::size_t i = 0; i < landmarks_.pairs.size(); ++i) {
                const std::uint32_t v = side == Side::a ? landmarks_.pairs[i].a : landmarks_.pairs[i].b;
                markers.push_back({at(v), QString::number(i + 1), pairColor});
            }
            if (s.pending) markers.push_back({at(*s.pending), QStringLiteral("%1?").arg(landmarks_.pairs.size() + 1), pendingColor});
        }
        s.view->setMarkers(markers);
    }
}

void LandmarkPicker::setSupermeshAvailable(bool available, const QString& tooltip) {
    supermeshAvailable_ = available;
    buildButton_->setToolTip(tooltip);
    updateButtons();
}

void LandmarkPicker::updateButtons() {
    const bool any = !landmarks_.pairs.empty() || sides_[0].pending || sides_[1].pending;
    undoButton_->setEnabled(any);
    clearButton_->setEnabled(any);
    saveButton_->setEnabled(!landmarks_.pairs.empty() && sides_[0].mesh && sides_[1].mesh);
    buildButton_->setEnabled(supermeshAvailable_ && sides_[0].mesh && sides_[1].mesh && !landmarks_.pairs.empty());
}

bool LandmarkPicker::eventFilter(QObject* watched, QEvent* event) {
    for (Side side : {Side::a, Side::b}) {
        SideState& s = state(side);
        if (watched != s.view) continue;
        // A click (press and release within a few pixels) picks; a drag still turns the camera: the
        // event goes on to the view either way.
        if (event->type() == QEvent::MouseButtonPress) {
            auto* e = static_cast<QMouseEvent*>(event);
            s.pressed = e->button() == Qt::LeftButton && e->modifiers() == Qt::NoModifier;
            s.pressPosition = e->position().toPoint();
        } else if (event->type() == QEvent::MouseButtonRelease && s.pressed) {
            auto* e = static_cast<QMouseEvent*>(event);
            s.pressed = false;
            const QPoint at = e->position().toPoint();
            if (e->button() == Qt::LeftButton && (at - s.pressPosition).manhattanLength() <= 3 && s.mesh) {
                if (const auto point = s.view->surfacePointAt(at)) pickVertex(side, nearestVertex(*s.mesh, *point));
            }
        }
    }
    return QWidget::eventFilter(watched, event);
}

void LandmarkPicker::showOpenDialog(Side side) {
    const QString path = QFileDialog::getOpenFileName(this, tr("Open mesh %1").arg(sideName(side)), state(side).path,
                                                      tr("Meshes (*.ply *.obj *.gltf *.glb);;All files (*)"));
    if (!path.isEmpty()) openMesh(side, path);
}

void LandmarkPicker::showSaveDialog() {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save landmarks"), QString(),
                                                      tr("Landmarks (*.json);;All files (*)"));
    if (path.isEmpty()) return;
    QString error;
    if (!saveLandmarks(path, &error)) emit message(error);
}

void LandmarkPicker::showLoadDialog() {
    const QString path = QFileDialog::getOpenFileName(this, tr("Load landmarks"), QString(),
                                                      tr("Landmarks (*.json);;All files (*)"));
    if (path.isEmpty()) return;
    QString error;
    if (!loadLandmarks(path, &error)) emit message(error);
}

}  // namespace lodforge::widgets
