#include "lodforge/widgets/ReportPanel.h"

#include "ReportPdf.h"

#include <QBuffer>
#include <QChart>
#include <QChartView>
#include <QDateTime>
#include <QFileInfo>
#include <QHeaderView>
#include <QLabel>
#include <QLineSeries>
#include <QLocale>
#include <QLogValueAxis>
#include <QPainter>
#include <QSaveFile>
#include <QScatterSeries>
#include <QSplitter>
#include <QTableWidget>
#include <QValueAxis>
#include <QVBoxLayout>

#include <algorithm>

namespace lodforge::widgets {

namespace {

const QStringList columnTitles = {QStringLiteral("Level"), QStringLiteral("Triangles"), QStringLiteral("Target"),
                                  QStringLiteral("Vertices"),
                                  QStringLiteral("Error (% diagonal)"), QStringLiteral("Error (model units)"),
                                  QStringLiteral("Time (ms)"), QStringLiteral("Stopped"),
                                  QStringLiteral("Image error (0-255, silhouette %)")};

// The stop reason with what the reader must not miss: a target not met, a level that repeats another.
QString stoppedText(const ReportRow& r) {
    QString text = r.stopReason;
    if (r.missedTarget) text += QStringLiteral(" — target missed");
    if (r.sameAs > 0) text += QStringLiteral(" — same as LOD %1").arg(r.sameAs);
    return text;
}

QStringList cellsOf(const ReportRow& r) {
    const QLocale locale;
    return {r.level == 0 ? QStringLiteral("original") : QString::number(r.level),
            locale.toString(qulonglong(r.triangles)),
            r.targetTriangles > 0 ? locale.toString(qulonglong(r.targetTriangles)) : QStringLiteral("—"),
            locale.toString(qulonglong(r.vertices)),
            // "…" until measured; "≈" marks the quick measure's sampled estimate.
            r.level > 0 && r.measured == Measured::no ? QStringLiteral("…")
            : (r.measured == Measured::sampled ? QStringLiteral("≈ ") : QString()) + QString::number(100.0 * r.errorRelative, 'f', 4),
            r.level > 0 && r.measured == Measured::no ? QStringLiteral("…") : QString::number(r.error, 'g', 4),
            r.level == 0 ? QStringLiteral("—") : QString::number(r.buildMs, 'f', 1),
            stoppedText(r),
            r.level == 0 ? QStringLiteral("—")
            : r.imageError ? QStringLiteral("%1 (%2 %)")
                                 .arg(*r.imageError, 0, 'f', 2)
                                 .arg(100.0 * r.imageSilhouette.value_or(0.0), 0, 'f', 2)
                           : QStringLiteral("…")};
}

bool isNumberColumn(int c) { return (c >= 1 && c <= 6) || c == 8; }
constexpr int stoppedColumn = 7;

QByteArray pngBytes(const QImage& image) {
    QByteArray bytes;
    QBuffer buffer(&bytes);
    buffer.open(QIODevice::WriteOnly);
    image.save(&buffer, "PNG");
    return bytes;
}

}  // namespace

ReportPanel::ReportPanel(QWidget* parent) : QWidget(parent) {
    auto* layout = new QVBoxLayout(this);
    title_ = new QLabel(tr("Build a LOD chain to see its report."), this);
    title_->setObjectName(QStringLiteral("reportTitle"));
    title_->setWordWrap(true);
    layout->addWidget(title_);
    structureLabel_ = new QLabel(this);
    structureLabel_->setObjectName(QStringLiteral("reportStructure"));
    structureLabel_->setWordWrap(true);
    structureLabel_->hide();
    layout->addWidget(structureLabel_);
    auto* splitter = new QSplitter(Qt::Vertical, this);
    table_ = new QTableWidget(0, int(columnTitles.size()), splitter);
    table_->setObjectName(QStringLiteral("reportTable"));
    table_->setHorizontalHeaderLabels(columnTitles);
    table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
    table_->verticalHeader()->hide();
    table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    chart_ = new QChartView(splitter);
    chart_->setObjectName(QStringLiteral("reportChart"));
    chart_->setRenderHint(QPainter::Antialiasing);
    chart_->setMinimumHeight(160);
    layout->addWidget(splitter, 1);
    updateChart();
}

void ReportPanel::clear() {
    rows_.clear();
    table_->setRowCount(0);
    title_->setText(tr("Build a LOD chain to see its report."));
    structure_.clear();
    structureLabel_->hide();
    updateChart();
}

void ReportPanel::setReport(const QString& meshName, const QString& presetName, const QString& method,
                            const std::vector<LevelData>& levels) {
    meshName_ = meshName;
    presetName_ = presetName;
    method_ = method;
    rows_.clear();
    for (const LevelData& l : levels)
        rows_.push_back({l.index, l.triangles, l.vertices, l.error, l.errorRelative, l.measured, l.buildMs, l.stopReason,
                         l.targetTriangles, l.missedTarget, l.sameAs, {}, {}});
    fillTable();
    title_->setText(tr("%1 — preset “%2”, %3, %n level(s) besides the original", "", int(rows_.size()) - 1)
                        .arg(meshName_, presetName_, method_));
    structure_ = levels.empty() ? QString() : levels.front().structureSummary;
    structureLabel_->setText(structure_);
    structureLabel_->setVisible(!structure_.isEmpty());
    updateChart();
}

void ReportPanel::setLevelMeasure(const LevelMeasure& measure) {
    if (measure.level <= 0 || measure.level >= int(rows_.size())) return;
    ReportRow& row = rows_[std::size_t(measure.level)];
    row.error = measure.error;
    row.errorRelative = measure.errorRelative;
    row.measured = measure.measured;
    fillTable();
    updateChart();
}

bool ReportPanel::allMeasured() const {
    return std::all_of(rows_.begin(), rows_.end(),
                       [](const ReportRow& r) { return r.level == 0 || r.measured != Measured::no; });
}

void ReportPanel::fillTable() {
    table_->setRowCount(int(rows_.size()));
    for (int r = 0; r < int(rows_.size()); ++r) {
        const QStringList cells = cellsOf(rows_[std::size_t(r)]);
        for (int c = 0; c < int(cells.size()); ++c) {
            auto* item = new QTableWidgetItem(cells[c]);
            if (isNumberColumn(c)) item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
            const ReportRow& row = rows_[std::size_t(r)];
            if (c == stoppedColumn && (row.missedTarget || row.sameAs > 0)) item->setForeground(QColor(190, 90, 0));
            table_->setItem(r, c, item);
        }
    }
}

void ReportPanel::setImageErrors(const std::vector<ImageError>& errors) {
    // With or without the original's (zero) entry.
    const std::size_t offset = errors.size() + 1 == rows_.size() ? 1 : 0;
    if (errors.size() + offset != rows_.size()) return;
    for (std::size_t i = 0; i < errors.size(); ++i) {
        rows_[i + offset].imageError = errors[i].mean_abs;
        rows_[i + offset].imageSilhouette = errors[i].silhouette;
    }
    fillTable();
}

void ReportPanel::updateChart() {
    auto* chart = new QChart;
    chart->setTitle(tr("Error against triangle count"));
    chart->legend()->hide();
    if (rows_.size() > 1) {
        auto* line = new QLineSeries(chart);
        auto* points = new QScatterSeries(chart);
        points->setMarkerSize(9);
        for (const ReportRow& r : rows_) {
            if (r.level > 0 && r.measured == Measured::no) continue;  // drawn once measured
            line->append(double(std::max<std::size_t>(r.triangles, 1)), 100.0 * r.errorRelative);
            points->append(double(std::max<std::size_t>(r.triangles, 1)), 100.0 * r.errorRelative);
        }
        chart->addSeries(line);
        chart->addSeries(points);
        auto* x = new QLogValueAxis(chart);
        x->setTitleText(tr("triangles"));
        x->setLabelFormat(QStringLiteral("%g"));
        x->setBase(10);
        auto* y = new QValueAxis(chart);
        y->setTitleText(tr("error (% of the diagonal)"));
        y->setMin(0);
        chart->addAxis(x, Qt::AlignBottom);
        chart->addAxis(y, Qt::AlignLeft);
        for (QAbstractSeries* s : chart->series()) {
            s->attachAxis(x);
            s->attachAxis(y);
        }
    }
    QChart* old = chart_->chart();
    chart_->setChart(chart);
    delete old;
}

QImage ReportPanel::chartImage(QSize size) const {
    QImage image(size, QImage::Format_RGB32);
    image.fill(Qt::white);
    QPainter painter(&image);
    painter.setRenderHint(QPainter::Antialiasing);
    chart_->chart()->resize(size);
    chart_->scene()->render(&painter, QRectF(QPointF(0, 0), size), chart_->chart()->geometry());
    painter.end();
    chart_->chart()->resize(chart_->size());
    return image;
}

QString ReportPanel::toHtml(const ReportImages& images) const { return html(images, true); }

QString ReportPanel::introduction() const {
    return QStringLiteral("Preset “%1”, method %2. Generated %3 by LodForge Studio.")
        .arg(presetName_, method_, QDateTime::currentDateTime().toString(Qt::ISODate));
}

QString ReportPanel::html(const ReportImages& images, bool embedImages) const {
    auto imageCell = [embedImages](const QList<QImage>& list, std::size_t i, const QString& name) {
        const QImage image = i < std::size_t(list.size()) ? list[qsizetype(i)] : QImage();
        if (image.isNull()) return QStringLiteral("<td></td>");
        const QString source = embedImages
                                   ? QStringLiteral("data:image/png;base64,") + QString::fromLatin1(pngBytes(image).toBase64())
                                   : name;
        return QStringLiteral("<td><img src=\"%1\" width=\"%2\" height=\"%3\"></td>")
            .arg(source)
            .arg(image.width())
            .arg(image.height());
    };
    QString out;
    out += QStringLiteral("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>LodForge report: %1</title>\n")
               .arg(meshName_.toHtmlEscaped());
    out += QStringLiteral("<style>body{font-family:sans-serif} table{border-collapse:collapse} "
                          "td,th{border:1px solid #999;padding:3px 8px} td.n{text-align:right;white-space:nowrap} "
                          "table.parameters td{border:none;padding:1px 8px}</style></head><body>\n");
    out += QStringLiteral("<h1>LOD report: %1</h1>\n").arg(meshName_.toHtmlEscaped());
    out += QStringLiteral("<p>%1</p>\n").arg(introduction().toHtmlEscaped());
    if (!structure_.isEmpty()) out += QStringLiteral("<p>%1</p>\n").arg(structure_.toHtmlEscaped());
    if (!parameters_.isEmpty()) {
        out += QStringLiteral("<h2>Parameters</h2>\n<table class=\"parameters\">\n");
        for (const auto& [name, value] : parameters_)
            out += QStringLiteral("<tr class=\"parameter\"><td>%1</td><td>%2</td></tr>\n")
                       .arg(name.toHtmlEscaped(), value.toHtmlEscaped());
        out += QStringLiteral("</table>\n<h2>Levels</h2>\n");
    }
    out += QStringLiteral("<table border=\"1\" cellpadding=\"4\" cellspacing=\"0\">\n<tr>");
    for (const QString& title : columnTitles) out += QStringLiteral("<th>%1</th>").arg(title.toHtmlEscaped());
    if (!images.shaded.isEmpty()) out += QStringLiteral("<th>Level</th>");
    if (!images.heatmap.isEmpty()) out += QStringLiteral("<th>Heat map</th>");
    out += QStringLiteral("</tr>\n");
    for (std::size_t i = 0; i < rows_.size(); ++i) {
        out += QStringLiteral("<tr class=\"level\">");
        const QStringList cells = cellsOf(rows_[i]);
        for (int c = 0; c < int(cells.size()); ++c)
            out += (isNumberColumn(c) ? QStringLiteral("<td class=\"n\" align=\"right\">%1</td>")
                                     : QStringLiteral("<td>%1</td>"))
                       .arg(cells[c].toHtmlEscaped());
        if (!images.shaded.isEmpty()) out += imageCell(images.shaded, i, QStringLiteral("shaded%1.png").arg(i));
        if (!images.heatmap.isEmpty()) out += imageCell(images.heatmap, i, QStringLiteral("heat%1.png").arg(i));
        out += QStringLiteral("</tr>\n");
    }
    out += QStringLiteral("</table>\n");
    if (rows_.size() > 1) {
        const QImage chart = chartImage(QSize(640, 360));
        out += QStringLiteral("<h2>Error against triangle count</h2>\n<p><img src=\"%1\" width=\"640\" height=\"360\"></p>\n")
                   .arg(embedImages ? QStringLiteral("data:image/png;base64,") + QString::fromLatin1(pngBytes(chart).toBase64())
                                    : QStringLiteral("chart.png"));
    }
    out += QStringLiteral("</body></html>\n");
    return out;
}

bool ReportPanel::exportTo(const QString& path, const ReportImages& images, QString* error) const {
    auto fail = [&](const QString& why) {
        if (error) *error = QStringLiteral("%1: %2").arg(path, why);
        return false;
    };
    if (rows_.empty()) return fail(tr("there is no report yet (build a LOD chain first)"));
    const bool pdf = QFileInfo(path).suffix().compare(QStringLiteral("pdf"), Qt::CaseInsensitive) == 0;
    QSaveFile file(path);
    if (!file.open(QIODevice::WriteOnly)) return fail(file.errorString());
    if (pdf) {
        ReportDocument document;
        document.title = QStringLiteral("LOD report: %1").arg(meshName_);
        document.paragraphs << introduction();
        if (!structure_.isEmpty()) document.paragraphs << structure_;
        document.parameters = parameters_;
        document.columns = columnTitles;
        for (int c = 0; c < int(columnTitles.size()); ++c) {
            document.wraps << (c == stoppedColumn);
            document.rightAligned << isNumberColumn(c);
        }
        for (const ReportRow& row : rows_) document.rows << cellsOf(row);
        if (!images.shaded.isEmpty()) document.imageColumns << QStringLiteral("Level");
        if (!images.heatmap.isEmpty()) document.imageColumns << QStringLiteral("Heat map");
        for (qsizetype i = 0; i < qsizetype(rows_.size()); ++i) {
            QList<QImage> pictures;
            if (!images.shaded.isEmpty()) pictures << images.shaded.value(i);
            if (!images.heatmap.isEmpty()) pictures << images.heatmap.value(i);
            document.rowImages << pictures;
        }
        if (rows_.size() > 1) {
            document.chartTitle = QStringLiteral("Error against triangle count");
            document.chart = chartImage(QSize(960, 540));
        }
        QString why;
        if (!writeReportPdf(file, document, QStringLiteral("LodForge report: %1").arg(meshName_), &why)) return fail(why);
    } else {
        const QByteArray bytes = toHtml(images).toUtf8();
        if (file.write(bytes) != bytes.size()) return fail(file.errorString());
    }
    if (!file.commit()) return fail(file.errorString());
    return true;
}

}  // namespace lodforge::widgets
