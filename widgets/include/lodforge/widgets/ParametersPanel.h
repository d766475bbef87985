// The parameters panel: edits a lodforge::Preset (the options model the CLI reads from the same JSON
// files): a shipped preset to start from (mobile, console, ...), method, LOD targets, attribute weights, border locking, octree and marching-cube knobs, pack
// contents. Every edit is reported as a before/after pair so the window can make it undoable. Only the
// knobs the chosen method and the loaded mesh use are shown; each target previews its triangle count.
#pragma once

#include "lodforge/pack/preset.h"

#include <QWidget>

#include <cstddef>
#include <functional>
#include <vector>

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QFormLayout;
class QGroupBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QSpinBox;
class QTableWidget;

namespace lodforge::widgets {

class ParametersPanel : public QWidget {
    Q_OBJECT

public:
    explicit ParametersPanel(QWidget* parent = nullptr);

    // Shows `preset` without emitting presetEdited (used by undo/redo and when a preset is loaded).
    void setPreset(const lodforge::Preset& preset);
    const lodforge::Preset& preset() const { return preset_; }

    // The loaded mesh (0 triangles: none): the colour and UV weights show only for a mesh with colours or
    // texture coordinates, and the targets' "Triangles" column previews each level's count (ratios
    // resolved as the build resolves them; "—" for error targets and without a mesh).
    void setMesh(std::size_t triangles, bool hasColors, bool hasTexcoords);
    // A target's previewed triangle count as the column shows it ("1,464", "—").
    QString previewText(int row) const;

    // Level rows (tests and the window's "add level" action).
    void addLevel();
    void removeSelectedLevel();

signals:
    // The user changed something: `before` was shown, `after` is shown now.
    void presetEdited(const lodforge::Preset& before, const lodforge::Preset& after);

private:
    void buildUi();
    void addLevelRow(const lodforge::LodTarget& target);
    void configureValueBox(QDoubleSpinBox* box, lodforge::LodTarget::Kind kind);
    std::vector<lodforge::LodTarget> readLevels() const;
    // Applies `change` to a copy of the preset; emits presetEdited when that changed anything. Each widget
    // changes only its own field, so values the widgets would round (a weight of 0.12345) stay exact.
    void edit(const std::function<void(lodforge::Preset&)>& change);
    // Replaces every option by the shipped preset chosen in the library box (one undoable edit).
    void applyShippedPreset(int index);
    // Shows the rows the method and the mesh use, hides the others (and a group left empty).
    void updateRelevance();
    void updatePreview();

    lodforge::Preset preset_;
    bool updating_ = false;
    std::size_t meshTriangles_ = 0;
    bool meshColors_ = false, meshTexcoords_ = false;

    QLineEdit* name_ = nullptr;
    QComboBox* library_ = nullptr;  // the shipped presets (lodforge/pack/preset_library.h)
    QComboBox* method_ = nullptr;
    QTableWidget* levels_ = nullptr;
    QCheckBox* autoLevels_ = nullptr;  // Preset::auto_levels (collapse only)
    QLabel* autoNote_ = nullptr;       // what the automatic choice does, with the preset's values
    QPushButton* addLevel_ = nullptr;
    QPushButton* removeLevel_ = nullptr;
    QDoubleSpinBox* normalWeight_ = nullptr;
    QDoubleSpinBox* colorWeight_ = nullptr;
    QDoubleSpinBox* uvWeight_ = nullptr;
    QCheckBox* lockBorder_ = nullptr;
    QComboBox* placement_ = nullptr;   // Preset::placement (collapse only)
    QGroupBox* weightsBox_ = nullptr;
    QFormLayout* weightsForm_ = nullptr;
    QGroupBox* structureBox_ = nullptr;
    QFormLayout* structureForm_ = nullptr;
    QSpinBox* maxTrianglesPerNode_ = nullptr;
    QSpinBox* maxDepth_ = nullptr;
    QSpinBox* memoryMb_ = nullptr;
    QSpinBox* mcResolution_ = nullptr;
    QCheckBox* primitiveRestart_ = nullptr;
    QCheckBox* exportGlb_ = nullptr;
    QCheckBox* exportPly_ = nullptr;
    QCheckBox* exportObj_ = nullptr;
    QCheckBox* exportLodstrips_ = nullptr;
};

}  // namespace lodforge::widgets
