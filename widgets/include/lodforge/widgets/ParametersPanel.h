// The parameters panel: edits a lodforge::Preset (the options model the CLI reads from the same JSON
// files): method, LOD targets, attribute weights, border locking, octree and marching-cube knobs, pack
// contents. Every edit is reported as a before/after pair so the window can make it undoable.
#pragma once

#include "lodforge/pack/preset.h"

#include <QWidget>

#include <functional>
#include <vector>

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
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

    // The methods whose engines exist in this build: the others stay selectable (a preset for them can
    // be written) and the panel says plainly that they cannot be built here yet.
    static bool hasEngine(lodforge::LodMethod method);

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
    void updateMethodNote();

    lodforge::Preset preset_;
    bool updating_ = false;

    QLineEdit* name_ = nullptr;
    QComboBox* method_ = nullptr;
    QLabel* methodNote_ = nullptr;
    QTableWidget* levels_ = nullptr;
    QPushButton* addLevel_ = nullptr;
    QPushButton* removeLevel_ = nullptr;
    QDoubleSpinBox* normalWeight_ = nullptr;
    QDoubleSpinBox* colorWeight_ = nullptr;
    QDoubleSpinBox* uvWeight_ = nullptr;
    QCheckBox* lockBorder_ = nullptr;
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
