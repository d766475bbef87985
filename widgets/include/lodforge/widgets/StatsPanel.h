// The statistics side panel: what lodforge::mesh_info says about the loaded mesh, as a tree of
// properties (file, geometry, attributes, materials and textures, validation findings).
#pragma once

#include "lodforge/io/mesh_info.h"

#include <QStringList>
#include <QWidget>

class QTreeWidget;
class QTreeWidgetItem;

namespace lodforge::widgets {

class StatsPanel : public QWidget {
    Q_OBJECT

public:
    explicit StatsPanel(QWidget* parent = nullptr);

    // `warnings`: problems met while loading that the summary does not know about (undecodable textures).
    void showInfo(const lodforge::MeshInfo& info, qint64 loadMs = -1, const QStringList& warnings = {});
    void clear();

    // The panel's content as plain text, one "name: value" line per row (copied by "Copy", read by tests).
    QString text() const;

private:
    QTreeWidgetItem* addSection(const QString& title);
    QTreeWidgetItem* addRow(QTreeWidgetItem* section, const QString& name, const QString& value);

    QTreeWidget* tree_ = nullptr;
    QString summaryText_;  // lodforge::to_text of the current info, for the clipboard
};

}  // namespace lodforge::widgets
