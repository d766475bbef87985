// The report of a LOD chain: a table per level (triangles against the target, vertices, error, time,
// why it stopped, flagged when the target was missed or the level repeats an earlier one) and a plot of error
// against triangle count (Qt Charts); exported as one self-contained HTML file or a PDF, with the
// parameters and thumbnails of every level (shaded, and its heat map when there is one).
#pragma once

#include "lodforge/metrics/image_error.h"
#include "lodforge/widgets/LodLevels.h"

#include <QImage>
#include <QList>
#include <QPair>
#include <QString>
#include <QWidget>

#include <optional>
#include <vector>

class QChartView;
class QLabel;
class QTableWidget;

namespace lodforge::widgets {

struct ReportRow {
    int level = 0;
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    double error = 0;          // model units
    double errorRelative = 0;  // of the bounding-box diagonal
    Measured measured = Measured::no;  // LevelData::measured
    double buildMs = 0;
    QString stopReason;
    std::size_t targetTriangles = 0;  // 0: an error target (LevelData::targetTriangles)
    bool missedTarget = false;
    int sameAs = -1;                  // an earlier identical level, or -1
    // Image-space error against the original (docs/image-compare.md), filled in by setImageErrors once
    // the background render is done: mean absolute colour difference (0-255) and silhouette mismatch.
    std::optional<double> imageError;
    std::optional<double> imageSilhouette;
};

// Pictures of the levels for an exported report, index = level; either list may be empty or shorter.
struct ReportImages {
    QList<QImage> shaded;
    QList<QImage> heatmap;
};

class ReportPanel : public QWidget {
    Q_OBJECT

public:
    explicit ReportPanel(QWidget* parent = nullptr);

    void setReport(const QString& meshName, const QString& presetName, const QString& method,
                   const std::vector<LevelData>& levels);
    void clear();
    // The parameters that made the levels (name, value), listed in exported reports.
    void setParameters(QList<QPair<QString, QString>> parameters) { parameters_ = std::move(parameters); }
    const QList<QPair<QString, QString>>& parameters() const { return parameters_; }
    // A level's error measured after setReport (measureLevels): its row and the chart follow.
    void setLevelMeasure(const LevelMeasure& measure);
    // Every level besides the original is measured (at least with the quick budget).
    bool allMeasured() const;
    // Per level (index = level; level 0, the original itself, included or not): the image-space errors
    // computed after setReport. The column shows "…" until then. Ignored when the sizes do not fit.
    void setImageErrors(const std::vector<lodforge::ImageError>& errors);
    bool isEmpty() const { return rows_.empty(); }
    const std::vector<ReportRow>& rows() const { return rows_; }
    QTableWidget* table() const { return table_; }
    // The structure's summary (LevelData::structureSummary of the original; octree statistics), shown
    // under the title; empty for the methods without one.
    const QString& structureSummary() const { return structure_; }

    // The chart as an image (for the exported report).
    QImage chartImage(QSize size) const;

    // HTML with the thumbnails and the chart embedded (data: URLs), so the file stands alone.
    QString toHtml(const ReportImages& images) const;
    // By the suffix of `path`: .pdf writes a PDF (landscape A4, laid out so that no number, word or table
    // row is split), anything else HTML. Atomic (temporary, then rename); on failure returns false with the
    // reason in `error` (naming the file).
    bool exportTo(const QString& path, const ReportImages& images, QString* error) const;

private:
    QString html(const ReportImages& images, bool embedImages) const;
    QString introduction() const;  // the line under the title
    void updateChart();
    void fillTable();

    QLabel* title_ = nullptr;
    QLabel* structureLabel_ = nullptr;
    QString structure_;
    QTableWidget* table_ = nullptr;
    QChartView* chart_ = nullptr;
    QString meshName_, presetName_, method_;
    QList<QPair<QString, QString>> parameters_;
    std::vector<ReportRow> rows_;
};

}  // namespace lodforge::widgets
