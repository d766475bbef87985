#include "lodforge/widgets/ParametersPanel.h"

#include "lodforge/error.h"
#include "lodforge/pack/preset_library.h"
#include "lodforge/widgets/LodLevels.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QLocale>
#include <QPushButton>
#include <QSpinBox>
#include <QTableWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

namespace lodforge::widgets {

namespace {

constexpr LodMethod allMethods[] = {LodMethod::collapse, LodMethod::cluster, LodMethod::octree, LodMethod::lodstrips,
                                    LodMethod::mcoctree};

QDoubleSpinBox* weightBox(QWidget* parent, const QString& name, const QString& tip) {
    auto* box = new QDoubleSpinBox(parent);
    box->setObjectName(name);
    box->setRange(0.0, 1000.0);
    box->setDecimals(4);
    box->setSingleStep(0.01);
    box->setKeyboardTracking(false);  // one edit (and one undo step) per typed value, not per keystroke
    box->setToolTip(tip);
    return box;
}

QSpinBox* countBox(QWidget* parent, const QString& name, int minimum, int maximum, const QString& suffix = {}) {
    auto* box = new QSpinBox(parent);
    box->setObjectName(name);
    box->setRange(minimum, maximum);
    box->setKeyboardTracking(false);
    box->setSuffix(suffix);
    box->setGroupSeparatorShown(true);
    return box;
}

int kindIndex(LodTarget::Kind kind) { return static_cast<int>(kind); }
LodTarget::Kind kindAt(int index) { return static_cast<LodTarget::Kind>(std::clamp(index, 0, 2)); }

}  // namespace

ParametersPanel::ParametersPanel(QWidget* parent) : QWidget(parent) {
    buildUi();
    setPreset(Preset{});
}

void ParametersPanel::buildUi() {
    auto* layout = new QVBoxLayout(this);

    auto* general = new QFormLayout;
    name_ = new QLineEdit(this);
    name_->setObjectName(QStringLiteral("presetName"));
    library_ = new QComboBox(this);
    library_->setObjectName(QStringLiteral("presetLibrary"));
    library_->setToolTip(tr("Start from a preset shipped with LodForge (docs/presets.md)"));
    library_->addItem(tr("Shipped presets…"));
    for (const std::string& n : shipped_preset_names()) library_->addItem(QString::fromStdString(n));
    general->addRow(tr("Start from"), library_);
    general->addRow(tr("Preset name"), name_);
    method_ = new QComboBox(this);
    method_->setObjectName(QStringLiteral("method"));
    for (LodMethod m : allMethods)
        method_->addItem(methodDisplayName(m), QString::fromUtf8(to_string(m).data(), qsizetype(to_string(m).size())));
    general->addRow(tr("Method"), method_);
    layout->addLayout(general);

    auto* levelsBox = new QGroupBox(tr("LOD targets (level 1 onwards)"), this);
    auto* levelsLayout = new QVBoxLayout(levelsBox);
    levels_ = new QTableWidget(0, 3, levelsBox);
    levels_->setObjectName(QStringLiteral("levels"));
    levels_->setHorizontalHeaderLabels({tr("Target"), tr("Value"), tr("Triangles")});
    levels_->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
    levels_->verticalHeader()->setDefaultSectionSize(28);
    levels_->setSelectionBehavior(QAbstractItemView::SelectRows);
    levels_->setSelectionMode(QAbstractItemView::SingleSelection);
    levels_->setMinimumHeight(150);
    autoLevels_ = new QCheckBox(tr("Choose the levels automatically"), levelsBox);
    autoLevels_->setObjectName(QStringLiteral("autoLevels"));
    autoLevels_->setToolTip(tr("The number of levels and their targets from the pixel tolerance and the smallest "
                               "on-screen size (preset \"levels\": \"auto\", docs/pack.md)"));
    levelsLayout->addWidget(autoLevels_);
    autoNote_ = new QLabel(levelsBox);
    autoNote_->setObjectName(QStringLiteral("autoLevelsNote"));
    autoNote_->setWordWrap(true);
    levelsLayout->addWidget(autoNote_);
    levelsLayout->addWidget(levels_);
    auto* levelButtons = new QHBoxLayout;
    addLevel_ = new QPushButton(tr("Add level"), levelsBox);
    addLevel_->setObjectName(QStringLiteral("addLevel"));
    removeLevel_ = new QPushButton(tr("Remove level"), levelsBox);
    removeLevel_->setObjectName(QStringLiteral("removeLevel"));
    levelButtons->addWidget(addLevel_);
    levelButtons->addWidget(removeLevel_);
    levelsLayout->addLayout(levelButtons);
    layout->addWidget(levelsBox);
    connect(addLevel_, &QPushButton::clicked, this, &ParametersPanel::addLevel);
    connect(removeLevel_, &QPushButton::clicked, this, &ParametersPanel::removeSelectedLevel);

    auto* weightsBox = new QGroupBox(tr("Simplification"), this);
    auto* weights = new QFormLayout(weightsBox);
    weightsBox_ = weightsBox;
    weightsForm_ = weights;
    normalWeight_ = weightBox(weightsBox, QStringLiteral("normalWeight"), tr("Cost of a unit normal change, in diagonals"));
    colorWeight_ = weightBox(weightsBox, QStringLiteral("colorWeight"), tr("Cost of a unit colour change, in diagonals"));
    uvWeight_ = weightBox(weightsBox, QStringLiteral("uvWeight"), tr("Cost of a unit UV change, in diagonals"));
    lockBorder_ = new QCheckBox(tr("Lock border"), weightsBox);
    lockBorder_->setObjectName(QStringLiteral("lockBorder"));
    placement_ = new QComboBox(weightsBox);
    placement_->setObjectName(QStringLiteral("placement"));
    for (Placement pl : {Placement::optimal, Placement::half_edge})
        placement_->addItem(QString::fromUtf8(to_string(pl).data(), qsizetype(to_string(pl).size())), int(pl));
    placement_->setToolTip(tr("optimal: each level's vertices move to the quadric optimum (lower error, larger "
                              "GLB); half-edge: levels keep input vertices and share one vertex buffer"));
    weights->addRow(tr("Normal weight"), normalWeight_);
    weights->addRow(tr("Colour weight"), colorWeight_);
    weights->addRow(tr("UV weight"), uvWeight_);
    weights->addRow(lockBorder_);
    weights->addRow(tr("Placement"), placement_);
    layout->addWidget(weightsBox);

    auto* octreeBox = new QGroupBox(tr("Structure"), this);
    octreeBox->setObjectName(QStringLiteral("structureBox"));
    auto* octree = new QFormLayout(octreeBox);
    structureBox_ = octreeBox;
    structureForm_ = octree;
    maxTrianglesPerNode_ = countBox(octreeBox, QStringLiteral("maxTrianglesPerNode"), 16, 100'000'000);
    maxDepth_ = countBox(octreeBox, QStringLiteral("maxDepth"), 1, 21);
    memoryMb_ = countBox(octreeBox, QStringLiteral("memoryMb"), 16, 1'048'576, tr(" MB"));
    mcResolution_ = countBox(octreeBox, QStringLiteral("mcResolution"), 4, 4096);
    primitiveRestart_ = new QCheckBox(tr("Strips joined by primitive restart"), octreeBox);
    primitiveRestart_->setObjectName(QStringLiteral("primitiveRestart"));
    octree->addRow(tr("Max triangles per node"), maxTrianglesPerNode_);
    octree->addRow(tr("Max depth"), maxDepth_);
    octree->addRow(tr("Memory budget"), memoryMb_);
    octree->addRow(tr("MC resolution"), mcResolution_);
    octree->addRow(primitiveRestart_);
    layout->addWidget(octreeBox);

    auto* exportBox = new QGroupBox(tr("Pack contents"), this);
    auto* exports = new QHBoxLayout(exportBox);
    exportGlb_ = new QCheckBox(tr("GLB"), exportBox);
    exportPly_ = new QCheckBox(tr("PLY"), exportBox);
    exportObj_ = new QCheckBox(tr("OBJ"), exportBox);
    exportLodstrips_ = new QCheckBox(tr(".lodstrips"), exportBox);
    exportGlb_->setObjectName(QStringLiteral("exportGlb"));
    exportPly_->setObjectName(QStringLiteral("exportPly"));
    exportObj_->setObjectName(QStringLiteral("exportObj"));
    exportLodstrips_->setObjectName(QStringLiteral("exportLodstrips"));
    for (QCheckBox* box : {exportGlb_, exportPly_, exportObj_, exportLodstrips_}) exports->addWidget(box);
    layout->addWidget(exportBox);
    layout->addStretch(1);

    connect(name_, &QLineEdit::editingFinished, this, [this] {
        const std::string name = name_->text().toStdString();
        edit([&](Preset& p) { p.name = name; });
    });
    connect(library_, &QComboBox::activated, this, &ParametersPanel::applyShippedPreset);
    connect(method_, &QComboBox::currentIndexChanged, this, [this](int index) {
        if (index < 0) return;
        edit([&](Preset& p) { p.method = allMethods[index]; });
        updateRelevance();
    });
    auto weight = [this](QDoubleSpinBox* box, float SimplifyWeights::*field) {
        connect(box, &QDoubleSpinBox::valueChanged, this,
                [this, field](double v) { edit([&](Preset& p) { p.weights.*field = static_cast<float>(v); }); });
    };
    weight(normalWeight_, &SimplifyWeights::normal);
    weight(colorWeight_, &SimplifyWeights::color);
    weight(uvWeight_, &SimplifyWeights::texcoord);
    connect(lockBorder_, &QCheckBox::toggled, this, [this](bool on) { edit([&](Preset& p) { p.lock_border = on; }); });
    connect(autoLevels_, &QCheckBox::toggled, this, [this](bool on) {
        edit([&](Preset& p) { p.auto_levels = on; });
        updateRelevance();
    });
    connect(placement_, &QComboBox::currentIndexChanged, this, [this](int index) {
        if (index < 0) return;
        edit([&](Preset& p) { p.placement = Placement(placement_->itemData(index).toInt()); });
    });
    connect(maxTrianglesPerNode_, &QSpinBox::valueChanged, this,
            [this](int v) { edit([&](Preset& p) { p.octree.max_triangles_per_node = std::uint32_t(v); }); });
    connect(maxDepth_, &QSpinBox::valueChanged, this,
            [this](int v) { edit([&](Preset& p) { p.octree.max_depth = std::uint32_t(v); }); });
    connect(memoryMb_, &QSpinBox::valueChanged, this,
            [this](int v) { edit([&](Preset& p) { p.octree.memory_mb = std::uint32_t(v); }); });
    connect(mcResolution_, &QSpinBox::valueChanged, this,
            [this](int v) { edit([&](Preset& p) { p.mcoctree.resolution = std::uint32_t(v); }); });
    connect(primitiveRestart_, &QCheckBox::toggled, this,
            [this](bool on) { edit([&](Preset& p) { p.strips.primitive_restart = on; }); });
    auto exportToggle = [this](QCheckBox* box, bool ExportOptions::*field) {
        connect(box, &QCheckBox::toggled, this, [this, field](bool on) { edit([&](Preset& p) { p.exports.*field = on; }); });
    };
    exportToggle(exportGlb_, &ExportOptions::glb);
    exportToggle(exportPly_, &ExportOptions::ply);
    exportToggle(exportObj_, &ExportOptions::obj);
    exportToggle(exportLodstrips_, &ExportOptions::lodstrips);
}

void ParametersPanel::edit(const std::function<void(Preset&)>& change) {
    if (updating_) return;
    Preset after = preset_;
    change(after);
    if (after == preset_) return;
    const Preset before = preset_;
    preset_ = after;
    updatePreview();
    emit presetEdited(before, after);
}

void ParametersPanel::setMesh(std::size_t triangles, bool hasColors, bool hasTexcoords) {
    meshTriangles_ = triangles;
    meshColors_ = hasColors;
    meshTexcoords_ = hasTexcoords;
    updateRelevance();
    updatePreview();
}

// Which knobs each method reads: build_preset_levels (core/src/pack/preset_levels.cpp).
void ParametersPanel::updateRelevance() {
    const LodMethod m = preset_.method;
    const bool weighted = m != LodMethod::mcoctree;
    weightsForm_->setRowVisible(normalWeight_, weighted);
    weightsForm_->setRowVisible(colorWeight_, weighted && meshColors_);
    weightsForm_->setRowVisible(uvWeight_, weighted && meshTexcoords_);
    weightsForm_->setRowVisible(lockBorder_, m == LodMethod::collapse || m == LodMethod::lodstrips);
    weightsForm_->setRowVisible(placement_, m == LodMethod::collapse);  // lodstrips needs half-edge
    weightsBox_->setVisible(weighted);
    const bool octree = m == LodMethod::octree;
    structureForm_->setRowVisible(maxTrianglesPerNode_, octree);
    structureForm_->setRowVisible(maxDepth_, octree);
    structureForm_->setRowVisible(memoryMb_, octree);
    structureForm_->setRowVisible(mcResolution_, m == LodMethod::mcoctree);
    structureForm_->setRowVisible(primitiveRestart_, m == LodMethod::lodstrips);
    structureBox_->setVisible(octree || m == LodMethod::mcoctree || m == LodMethod::lodstrips);
    // Only the lodstrips method writes a .lodstrips; a box ticked for another stays, to be unticked.
    exportLodstrips_->setVisible(m == LodMethod::lodstrips || preset_.exports.lodstrips);
    // Automatic levels need the collapse method (their targets come from its errors); a box ticked for
    // another method stays, to be unticked. The list is kept, unused, so unticking restores it.
    const bool automatic = m == LodMethod::collapse && preset_.auto_levels;
    autoLevels_->setVisible(m == LodMethod::collapse || preset_.auto_levels);
    levels_->setEnabled(!automatic);
    addLevel_->setEnabled(!automatic);
    removeLevel_->setEnabled(!automatic);
    autoNote_->setVisible(preset_.auto_levels);
    const SwitchParams& s = preset_.switching;
    autoNote_->setText(m == LodMethod::collapse
                           ? tr("Chosen when built: each level at least halves the triangles of the one before, "
                                "switching at %1 px of error on %2×%3, down to %4 px on screen. The list below is "
                                "kept for when this is off.")
                                 .arg(s.pixels)
                                 .arg(s.width)
                                 .arg(s.height)
                                 .arg(preset_.min_screen_pixels)
                           : tr("Automatic levels need the Edge collapse method."));
}

QString ParametersPanel::previewText(int row) const {
    if (row < 0 || std::size_t(row) >= preset_.levels.size() || meshTriangles_ == 0) return QStringLiteral("—");
    const LodTarget& t = preset_.levels[std::size_t(row)];
    double n = 0;
    // As the build resolves a target (floor); an error target's count is known only once built.
    switch (t.kind) {
    case LodTarget::Kind::ratio: n = std::floor(t.value * double(meshTriangles_)); break;
    case LodTarget::Kind::triangles: n = std::min(std::floor(t.value), double(meshTriangles_)); break;
    case LodTarget::Kind::error: return QStringLiteral("—");
    }
    return QLocale().toString(qulonglong(std::max(0.0, n)));
}

void ParametersPanel::updatePreview() {
    for (int row = 0; row < levels_->rowCount(); ++row) {
        auto* item = levels_->item(row, 2);
        if (!item) {
            item = new QTableWidgetItem;
            item->setFlags(Qt::ItemIsEnabled);
            item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
            levels_->setItem(row, 2, item);
        }
        item->setText(previewText(row));
    }
}

void ParametersPanel::configureValueBox(QDoubleSpinBox* box, LodTarget::Kind kind) {
    switch (kind) {
    case LodTarget::Kind::ratio:
        box->setDecimals(4);
        box->setRange(0.0001, 0.9999);  // 1 would copy level 0 (build_lod_chain refuses it)
        box->setSingleStep(0.05);
        box->setToolTip(tr("Fraction of the original's triangles"));
        break;
    case LodTarget::Kind::triangles:
        box->setDecimals(0);
        box->setRange(1, 1e9);
        box->setSingleStep(100);
        box->setToolTip(tr("Triangle count"));
        break;
    case LodTarget::Kind::error:
        box->setDecimals(6);
        box->setRange(0.000001, 1.0);
        box->setSingleStep(0.001);
        box->setToolTip(tr("Largest error, relative to the bounding-box diagonal"));
        break;
    }
}

void ParametersPanel::addLevelRow(const LodTarget& target) {
    const int row = levels_->rowCount();
    levels_->insertRow(row);
    auto* kind = new QComboBox(levels_);
    kind->addItems({tr("Ratio"), tr("Triangles"), tr("Error")});
    kind->setCurrentIndex(kindIndex(target.kind));
    auto* value = new QDoubleSpinBox(levels_);
    value->setKeyboardTracking(false);
    configureValueBox(value, target.kind);
    value->setValue(target.value);
    levels_->setCellWidget(row, 0, kind);
    levels_->setCellWidget(row, 1, value);
    connect(kind, &QComboBox::currentIndexChanged, this, [this, value](int index) {
        const QSignalBlocker block(value);
        const LodTarget::Kind k = kindAt(index);
        configureValueBox(value, k);
        // A sensible value of the new kind, derived from the row's position.
        int r = 0;
        while (r < levels_->rowCount() && levels_->cellWidget(r, 1) != value) ++r;
        const double defaults[] = {std::pow(0.5, r + 1), 1000.0 / (r + 1), 0.001 * (r + 1)};
        value->setValue(defaults[static_cast<int>(k)]);
        edit([this](Preset& p) { p.levels = readLevels(); });
    });
    connect(value, &QDoubleSpinBox::valueChanged, this, [this] { edit([this](Preset& p) { p.levels = readLevels(); }); });
}

std::vector<LodTarget> ParametersPanel::readLevels() const {
    std::vector<LodTarget> levels;
    for (int row = 0; row < levels_->rowCount(); ++row) {
        auto* kind = qobject_cast<QComboBox*>(levels_->cellWidget(row, 0));
        auto* value = qobject_cast<QDoubleSpinBox*>(levels_->cellWidget(row, 1));
        if (!kind || !value) continue;
        LodTarget t;
        t.kind = kindAt(kind->currentIndex());
        t.value = value->value();
        levels.push_back(t);
    }
    return levels;
}

void ParametersPanel::addLevel() {
    // Half of the last level's target (or one more step of the same kind).
    LodTarget next;
    if (!preset_.levels.empty()) {
        next = preset_.levels.back();
        switch (next.kind) {
        case LodTarget::Kind::ratio: next.value = std::max(0.0001, next.value * 0.5); break;
        case LodTarget::Kind::triangles: next.value = std::max(1.0, std::floor(next.value * 0.5)); break;
        case LodTarget::Kind::error: next.value = std::min(1.0, next.value * 2.0); break;
        }
    } else {
        next.value = 0.5;
    }
    updating_ = true;
    addLevelRow(next);
    updating_ = false;
    edit([this](Preset& p) { p.levels = readLevels(); });
}

void ParametersPanel::removeSelectedLevel() {
    if (levels_->rowCount() <= 1) return;  // a preset has at least one level
    int row = levels_->currentRow();
    if (row < 0) row = levels_->rowCount() - 1;
    levels_->removeRow(row);
    edit([this](Preset& p) { p.levels = readLevels(); });
}

void ParametersPanel::setPreset(const Preset& preset) {
    updating_ = true;
    preset_ = preset;
    name_->setText(QString::fromStdString(preset.name));
    for (int i = 0; i < int(std::size(allMethods)); ++i)
        if (allMethods[i] == preset.method) method_->setCurrentIndex(i);
    levels_->setRowCount(0);
    for (const LodTarget& t : preset.levels) addLevelRow(t);
    normalWeight_->setValue(preset.weights.normal);
    colorWeight_->setValue(preset.weights.color);
    uvWeight_->setValue(preset.weights.texcoord);
    lockBorder_->setChecked(preset.lock_border);
    autoLevels_->setChecked(preset.auto_levels);
    placement_->setCurrentIndex(placement_->findData(int(preset.placement)));
    maxTrianglesPerNode_->setValue(int(preset.octree.max_triangles_per_node));
    maxDepth_->setValue(int(preset.octree.max_depth));
    memoryMb_->setValue(int(preset.octree.memory_mb));
    mcResolution_->setValue(int(preset.mcoctree.resolution));
    primitiveRestart_->setChecked(preset.strips.primitive_restart);
    exportGlb_->setChecked(preset.exports.glb);
    exportPly_->setChecked(preset.exports.ply);
    exportObj_->setChecked(preset.exports.obj);
    exportLodstrips_->setChecked(preset.exports.lodstrips);
    library_->setCurrentIndex(std::max(0, library_->findText(QString::fromStdString(preset.name))));
    updating_ = false;
    updateRelevance();
    updatePreview();
}

void ParametersPanel::applyShippedPreset(int index) {
    if (updating_ || index <= 0) return;
    Preset shipped;
    try {
        shipped = load_shipped_preset(library_->itemText(index).toStdString());
    } catch (const Error& e) {
        library_->setToolTip(QString::fromUtf8(e.what()));
        return;
    }
    edit([&](Preset& p) { p = shipped; });
    setPreset(preset_);
}

}  // namespace lodforge::widgets
