#include "lodforge/widgets/StatsPanel.h"

#include <QApplication>
#include <QClipboard>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLocale>
#include <QPushButton>
#include <QStyle>
#include <QTreeWidget>
#include <QVBoxLayout>

#include <algorithm>

namespace lodforge::widgets {

namespace {

QString count(std::size_t n) { return QLocale().toString(static_cast<qulonglong>(n)); }

QString vec(const Vec3f& v) {
    return QStringLiteral("%1, %2, %3").arg(v.x, 0, 'g', 6).arg(v.y, 0, 'g', 6).arg(v.z, 0, 'g', 6);
}

QString severityName(ValidationFinding::Severity severity) {
    return severity == ValidationFinding::Severity::error ? QObject::tr("error") : QObject::tr("warning");
}

}  // namespace

StatsPanel::StatsPanel(QWidget* parent) : QWidget(parent) {
    tree_ = new QTreeWidget(this);
    tree_->setObjectName(QStringLiteral("statsTree"));
    tree_->setColumnCount(2);
    tree_->setHeaderLabels({tr("Property"), tr("Value")});
    tree_->header()->setSectionResizeMode(0, QHeaderView::ResizeToContents);
    tree_->header()->setStretchLastSection(true);
    tree_->setRootIsDecorated(true);
    tree_->setUniformRowHeights(true);
    tree_->setWordWrap(false);
    tree_->setSelectionMode(QAbstractItemView::ExtendedSelection);

    auto* copy = new QPushButton(tr("Copy as text"), this);
    copy->setObjectName(QStringLiteral("copyStats"));
    copy->setToolTip(tr("Copy the summary to the clipboard, as `lodforge info` prints it"));
    connect(copy, &QPushButton::clicked, this, [this] {
        QApplication::clipboard()->setText(summaryText_.isEmpty() ? text() : summaryText_);
    });

    auto* buttons = new QHBoxLayout;
    buttons->addStretch();
    buttons->addWidget(copy);
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->addWidget(tree_);
    layout->addLayout(buttons);
    clear();
}

QTreeWidgetItem* StatsPanel::addSection(const QString& title) {
    auto* item = new QTreeWidgetItem(tree_, {title});
    QFont font = item->font(0);
    font.setBold(true);
    item->setFont(0, font);
    return item;
}

QTreeWidgetItem* StatsPanel::addRow(QTreeWidgetItem* section, const QString& name, const QString& value) {
    auto* item = new QTreeWidgetItem(section, {name, value});
    item->setToolTip(1, value);
    return item;
}

void StatsPanel::clear() {
    tree_->clear();
    summaryText_.clear();
    auto* item = new QTreeWidgetItem(tree_, {tr("No mesh loaded"), QString()});
    item->setDisabled(true);
}

void StatsPanel::showInfo(const MeshInfo& info, qint64 loadMs, const QStringList& warnings) {
    tree_->clear();
    summaryText_ = QString::fromStdString(to_text(info));

    QTreeWidgetItem* file = addSection(tr("File"));
    const QString path = QString::fromStdString(info.path);
    addRow(file, tr("Name"), QFileInfo(path).fileName())->setToolTip(1, path);
    addRow(file, tr("Folder"), QFileInfo(path).absolutePath());
    addRow(file, tr("Format"), QString::fromStdString(info.format));
    if (loadMs >= 0) addRow(file, tr("Load time"), tr("%1 ms").arg(loadMs));

    QTreeWidgetItem* geometry = addSection(tr("Geometry"));
    addRow(geometry, tr("Vertices"), count(info.vertices))
        ->setToolTip(1, tr("Surface points (as stored; each placement of an instanced glTF mesh counts)"));
    addRow(geometry, tr("Wedges"), count(info.wedges))
        ->setToolTip(1, tr("Render vertices after splitting attribute seams"));
    addRow(geometry, tr("Triangles"), count(info.triangles));
    if (info.bounds.empty()) {
        addRow(geometry, tr("Bounds"), tr("empty"));
    } else {
        addRow(geometry, tr("Bounds min"), vec(info.bounds.min));
        addRow(geometry, tr("Bounds max"), vec(info.bounds.max));
        addRow(geometry, tr("Size"), vec(info.bounds.size()));
        addRow(geometry, tr("Diagonal"), QString::number(info.bounds.diagonal(), 'g', 6));
    }

    QTreeWidgetItem* attributes = addSection(tr("Attributes"));
    QStringList names;
    for (const std::string& a : info.attributes) names << QString::fromStdString(a);
    addRow(attributes, tr("Per vertex"), names.isEmpty() ? tr("none") : names.join(QStringLiteral(", ")));

    QTreeWidgetItem* materials = addSection(tr("Materials"));
    addRow(materials, tr("Materials"), count(info.materials));
    addRow(materials, tr("Textures"), count(info.textures.size()));
    const QIcon warningIcon = style()->standardIcon(QStyle::SP_MessageBoxWarning);
    const QIcon errorIcon = style()->standardIcon(QStyle::SP_MessageBoxCritical);
    for (const std::string& t : info.textures) {
        const bool missing =
            std::find(info.missing_textures.begin(), info.missing_textures.end(), t) != info.missing_textures.end();
        QTreeWidgetItem* row =
            addRow(materials, missing ? tr("Texture (missing)") : tr("Texture"), QString::fromStdString(t));
        if (missing) {
            row->setIcon(0, warningIcon);
            row->setForeground(1, QBrush(Qt::darkRed));
        }
    }
    for (const std::string& t : info.missing_textures) {
        if (std::find(info.textures.begin(), info.textures.end(), t) != info.textures.end()) continue;
        QTreeWidgetItem* row = addRow(materials, tr("Texture (missing)"), QString::fromStdString(t));
        row->setIcon(0, warningIcon);
        row->setForeground(1, QBrush(Qt::darkRed));
    }
    for (const QString& w : warnings) {
        QTreeWidgetItem* row = addRow(materials, tr("Not shown"), w);
        row->setIcon(0, warningIcon);
    }

    if (!info.warnings.empty()) {
        QTreeWidgetItem* notes = addSection(tr("Import notes"));
        for (const std::string& w : info.warnings) addRow(notes, tr("Note"), QString::fromStdString(w))->setIcon(0, warningIcon);
    }

    QTreeWidgetItem* validation = addSection(tr("Validation"));
    if (info.validation.findings.empty()) {
        addRow(validation, tr("Result"), tr("no problems found"));
    } else {
        for (const ValidationFinding& f : info.validation.findings) {
            const QString message = f.message.empty()
                                        ? tr("%1 × %2").arg(count(f.count), QString::fromStdString(f.code))
                                        : QString::fromStdString(f.message);
            QTreeWidgetItem* row = addRow(validation, severityName(f.severity), message);
            row->setIcon(0, f.severity == ValidationFinding::Severity::error ? errorIcon : warningIcon);
            row->setToolTip(1, QStringLiteral("%1: %2").arg(QString::fromStdString(f.code), message));
        }
    }
    tree_->expandAll();
    tree_->resizeColumnToContents(0);
}

QString StatsPanel::text() const {
    QStringList lines;
    for (int i = 0; i < tree_->topLevelItemCount(); ++i) {
        const QTreeWidgetItem* section = tree_->topLevelItem(i);
        lines << section->text(0);
        for (int j = 0; j < section->childCount(); ++j) {
            const QTreeWidgetItem* row = section->child(j);
            lines << QStringLiteral("  %1: %2").arg(row->text(0), row->text(1));
        }
    }
    return lines.join(QLatin1Char('\n'));
}

}  // namespace lodforge::widgets
