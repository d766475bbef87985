// Landmark picking for the two-mesh morph (issue 8, case (b)): meshes A and B side by side, a click on
// each adds a correspondence pair (numbered markers in both views), undo and clear, and the landmarks
// file of core/include/lodforge/morph/landmarks.h (read_landmarks / write_landmarks / check_landmarks), the
// file `lodforge morph build A B --landmarks L.json` reads.
//
// Vertex indices are those of `read_mesh` with its default options, as the file format says: the picker
// reads A and B itself (not through LoadJob, whose viewer copy places every glTF instance).
#pragma once

#include "lodforge/morph/landmarks.h"
#include "lodforge/mesh.h"
#include "lodforge/widgets/LatestJob.h"

#include <QString>
#include <QWidget>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>

class QLabel;
class QListWidget;
class QProgressBar;
class QPushButton;

namespace lodforge::widgets {

class MeshScene;
class VtkView;

class LandmarkPicker : public QWidget {
    Q_OBJECT

public:
    enum class Side { a = 0, b = 1 };

    explicit LandmarkPicker(QWidget* parent = nullptr);
    ~LandmarkPicker() override;

    // Reads `path` as mesh A or B in the background; meshLoaded reports how it ended. The pairs are
    // cleared when a mesh is replaced (they name its vertices).
    void openMesh(Side side, const QString& path);
    bool isLoading() const;
    // Stops the loads running (their results dropped: the sides keep the meshes they show).
    void cancelLoads();
    // Under the views while a load runs: its progress and Cancel.
    QProgressBar* loadProgressBar() const { return loadProgress_; }
    QPushButton* cancelLoadButton() const { return cancelLoad_; }
    // The mesh of a side (null before it loaded) and the file it came from.
    std::shared_ptr<const lodforge::Mesh> mesh(Side side) const;
    QString meshPath(Side side) const;
    VtkView* view(Side side) const;

    // The picking slot: vertex `vertex` of a side's mesh was picked (a click calls it with the vertex
    // nearest to the surface point under the cursor). A pick waits for a pick on the other side; the two
    // make the next pair. A vertex already in a pair is refused (check_landmarks would reject the file);
    // picking again on the waiting side replaces the waiting pick. False (with the reason in `error`)
    // when refused.
    bool pickVertex(Side side, std::uint32_t vertex, QString* error = nullptr);
    std::optional<std::uint32_t> pendingPick(Side side) const;
    const lodforge::Landmarks& landmarks() const { return landmarks_; }
    // Drops the waiting pick if there is one, else the last pair.
    void undoLastPair();
    void clearPairs();

    // Both check the pairs against the loaded meshes (check_landmarks) first. False with the message.
    bool saveLandmarks(const QString& path, QString* error = nullptr);
    bool loadLandmarks(const QString& path, QString* error = nullptr);

    // The vertex of `mesh` nearest to `point` (model coordinates); the mesh must have vertices.
    static std::uint32_t nearestVertex(const lodforge::Mesh& mesh, const std::array<double, 3>& point);

    // The "Build supermesh" button: enabled when `available` and both meshes are loaded with at least one
    // pair; `tooltip` says what it does or why it cannot.
    void setSupermeshAvailable(bool available, const QString& tooltip);
    QPushButton* buildSupermeshButton() const { return buildButton_; }

signals:
    void meshLoaded(lodforge::widgets::LandmarkPicker::Side side, bool ok, const QString& message);
    void pairsChanged();
    void buildSupermeshRequested();
    void message(const QString& text);  // refused picks, saved and loaded files

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

private:
    struct SideState {
        VtkView* view = nullptr;
        QLabel* label = nullptr;
        std::shared_ptr<const lodforge::Mesh> mesh;
        QString path;
        std::optional<std::uint32_t> pending;
        LatestJob* load = nullptr;  // the newest mesh asked for on this side
        QString loadPath;           // what it loads
        QPoint pressPosition;
        bool pressed = false;
    };
    SideState& state(Side side) { return sides_[static_cast<int>(side)]; }
    const SideState& state(Side side) const { return sides_[static_cast<int>(side)]; }
    void showOpenDialog(Side side);
    std::optional<LatestJob::Run> makeLoad(Side side);
    void updateLoadUi();
    void showSaveDialog();
    void showLoadDialog();
    bool checkPairs(const lodforge::Landmarks& landmarks, const QString& source, QString* error) const;
    void updateMarkers();
    void updateButtons();

    std::array<SideState, 2> sides_;
    lodforge::Landmarks landmarks_;
    QListWidget* pairList_ = nullptr;
    QPushButton* undoButton_ = nullptr;
    QPushButton* clearButton_ = nullptr;
    QPushButton* saveButton_ = nullptr;
    QProgressBar* loadProgress_ = nullptr;
    QPushButton* cancelLoad_ = nullptr;
    QPushButton* buildButton_ = nullptr;
    bool supermeshAvailable_ = false;
};

}  // namespace lodforge::widgets
