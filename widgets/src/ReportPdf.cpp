#include "ReportPdf.h"

#include <QFont>
#include <QFontMetricsF>
#include <QIODevice>
#include <QPageLayout>
#include <QPageSize>
#include <QPainter>
#include <QPdfWriter>

#include <algorithm>
#include <functional>
#include <vector>

namespace lodforge::widgets {

namespace {

constexpr int dotsPerInch = 150;
double mm(double millimetres) { return millimetres / 25.4 * dotsPerInch; }

QFont fontOf(double points, bool bold = false) {
    QFont font;
    font.setPointSizeF(points);
    font.setBold(bold);
    return font;
}

// The widest space-separated word: the narrowest a text may be squeezed to without splitting a word.
double widestWord(const QFontMetricsF& metrics, const QString& text) {
    double widest = 0;
    for (const QString& word : text.split(QLatin1Char(' '), Qt::SkipEmptyParts))
        widest = std::max(widest, metrics.horizontalAdvance(word));
    return widest;
}

double wrappedHeight(const QFontMetricsF& metrics, const QString& text, double width) {
    return metrics.boundingRect(QRectF(0, 0, width, 1e7), Qt::TextWordWrap, text).height();
}

// Pages of the writer with a vertical position: whatever is placed asks for its height first and goes to
// a new page (with the table header redrawn, when one is set) if it does not fit.
class Pages {
public:
    Pages(QPdfWriter& writer, QPainter& painter, QString footer)
        : writer_(writer), painter_(painter), footer_(std::move(footer)) {
        width_ = writer.width();
        bottom_ = writer.height() - mm(7);  // the footer's line
    }
    double width() const { return width_; }
    double y() const { return y_; }
    void advance(double height) { y_ += height; }
    // Room for `height` on this page, or a new page. False when the writer refused the page.
    bool reserve(double height) {
        if (y_ + height <= bottom_ || y_ <= 0) return true;
        drawFooter();
        if (!writer_.newPage()) return false;
        ++page_;
        y_ = 0;
        if (header_) header_();
        return true;
    }
    void setHeader(std::function<void()> header) { header_ = std::move(header); }
    void finish() { drawFooter(); }

private:
    void drawFooter() {
        painter_.save();
        painter_.setFont(fontOf(7));
        painter_.setPen(QColor(110, 110, 110));
        painter_.drawText(QRectF(0, bottom_ + mm(2), width_, mm(5)), Qt::AlignRight | Qt::AlignVCenter,
                          QStringLiteral("%1 — page %2").arg(footer_).arg(page_));
        painter_.restore();
    }

    QPdfWriter& writer_;
    QPainter& painter_;
    QString footer_;
    std::function<void()> header_;
    double width_ = 0, bottom_ = 0, y_ = 0;
    int page_ = 1;
};

// Column widths and the font that make the table fit the page width without splitting a number or a word.
struct TableLayout {
    double points = 8;
    std::vector<double> widths;  // text columns, then picture columns
    double imageWidth = 0, imageHeight = 0;
    double pad = mm(1.2);
};

TableLayout layoutTable(const ReportDocument& d, QPaintDevice* device, double pageWidth) {
    TableLayout t;
    const int textColumns = int(d.columns.size());
    const int imageColumns = int(d.imageColumns.size());
    double aspect = 0.75;
    for (const auto& images : d.rowImages)
        for (const QImage& image : images)
            if (!image.isNull()) aspect = double(image.height()) / image.width();
    t.imageWidth = imageColumns > 0 ? mm(34) : 0;
    for (t.points = 8.0;; t.points -= 0.5) {
        const QFontMetricsF cell(fontOf(t.points), device), head(fontOf(t.points, true), device);
        const auto columns = static_cast<std::size_t>(textColumns);
        // need: no number or word split; cellWant: every cell on one line; headWant: the header too.
        std::vector<double> need(columns), cellWant(columns), headWant(columns);
        for (int c = 0; c < textColumns; ++c) {
            double natural = 0, minimal = 0;
            for (const QStringList& row : d.rows) {
                const QString text = c < row.size() ? row[c] : QString();
                natural = std::max(natural, cell.horizontalAdvance(text));
                minimal = std::max(minimal, d.wraps.value(c) ? widestWord(cell, text) : cell.horizontalAdvance(text));
            }
            const double header = widestWord(head, d.columns[c]);
            // A point of slack: the painter's line breaking rounds widths that the metrics do not.
            const double slack = 2 * t.pad + 1;
            need[std::size_t(c)] = std::max(minimal, header) + slack;
            cellWant[std::size_t(c)] = std::max(natural, header) + slack;
            headWant[std::size_t(c)] = std::max(natural, head.horizontalAdvance(d.columns[c])) + slack;
        }
        double total = imageColumns * (t.imageWidth + 2 * t.pad);
        for (double w : need) total += w;
        if (total > pageWidth && t.points > 5.5) continue;
        if (total > pageWidth && imageColumns > 0)  // still too wide at the smallest font: smaller pictures
            t.imageWidth = std::max(mm(15), t.imageWidth - (total - pageWidth) / imageColumns);
        // What is left widens the columns: first towards one-line cells, then one-line headers, the
        // smallest gaps first (most columns made whole for the room).
        double spare = pageWidth - total;
        for (const std::vector<double>* want : {&cellWant, &headWant}) {
            std::vector<int> order(columns);
            for (int c = 0; c < textColumns; ++c) order[std::size_t(c)] = c;
            auto gap = [&](int c) { return (*want)[std::size_t(c)] - need[std::size_t(c)]; };
            std::sort(order.begin(), order.end(), [&](int a, int b) { return gap(a) < gap(b); });
            for (int c : order) {
                const double add = std::clamp(gap(c), 0.0, std::max(spare, 0.0));
                need[std::size_t(c)] += add;
                spare -= add;
            }
        }
        t.widths = need;
        for (int i = 0; i < imageColumns; ++i) t.widths.push_back(t.imageWidth + 2 * t.pad);
        t.imageHeight = t.imageWidth * aspect;
        return t;
    }
}

}  // namespace

bool writeReportPdf(QIODevice& out, const ReportDocument& d, const QString& pdfTitle, QString* error) {
    QPdfWriter writer(&out);
    writer.setResolution(dotsPerInch);
    writer.setPageLayout(QPageLayout(QPageSize(QPageSize::A4), QPageLayout::Landscape, QMarginsF(12, 12, 12, 12),
                                     QPageLayout::Millimeter));
    writer.setTitle(pdfTitle);
    writer.setCreator(QStringLiteral("LodForge Studio"));
    QPainter painter;
    if (!painter.begin(&writer)) {
        if (error) *error = QStringLiteral("the PDF writer did not start");
        return false;
    }
    Pages pages(writer, painter, pdfTitle);
    const double width = pages.width();
    bool ok = true;

    auto paragraph = [&](const QString& text, const QFont& font, double spaceAfter) {
        const QFontMetricsF metrics(font, &writer);
        const double height = wrappedHeight(metrics, text, width);
        ok = ok && pages.reserve(height);
        painter.setFont(font);
        painter.setPen(Qt::black);
        painter.drawText(QRectF(0, pages.y(), width, height), Qt::TextWordWrap | Qt::AlignLeft | Qt::AlignTop, text);
        pages.advance(height + spaceAfter);
    };

    paragraph(d.title, fontOf(15, true), mm(2));
    for (const QString& text : d.paragraphs) paragraph(text, fontOf(9), mm(1.5));

    // Parameters: names in one column, values wrapped beside them.
    if (!d.parameters.isEmpty()) {
        pages.advance(mm(2));
        paragraph(QStringLiteral("Parameters"), fontOf(11, true), mm(1));
        const QFont font = fontOf(8);
        const QFontMetricsF metrics(font, &writer);
        double nameWidth = 0;
        for (const auto& p : d.parameters) nameWidth = std::max(nameWidth, metrics.horizontalAdvance(p.first));
        nameWidth = std::min(nameWidth + mm(3), width * 0.4);
        painter.setFont(font);
        for (const auto& [name, value] : d.parameters) {
            const double height = std::max(wrappedHeight(metrics, name, nameWidth - mm(3)),
                                            wrappedHeight(metrics, value, width - nameWidth));
            ok = ok && pages.reserve(height);
            painter.setFont(font);
            painter.setPen(QColor(60, 60, 60));
            painter.drawText(QRectF(0, pages.y(), nameWidth - mm(3), height), Qt::TextWordWrap | Qt::AlignTop, name);
            painter.setPen(Qt::black);
            painter.drawText(QRectF(nameWidth, pages.y(), width - nameWidth, height), Qt::TextWordWrap | Qt::AlignTop,
                             value);
            pages.advance(height + mm(0.4));
        }
    }

    // The table: every row whole on one page, the header again on each page.
    if (!d.rows.isEmpty()) {
        pages.advance(mm(3));
        const TableLayout t = layoutTable(d, &writer, width);
        const QFont cellFont = fontOf(t.points), headFont = fontOf(t.points, true);
        const QFontMetricsF cell(cellFont, &writer), head(headFont, &writer);
        QStringList titles = d.columns;
        titles += d.imageColumns;
        double headerHeight = 0;
        for (int c = 0; c < int(titles.size()); ++c)
            headerHeight = std::max(headerHeight, wrappedHeight(head, titles[c], t.widths[std::size_t(c)] - 2 * t.pad));
        headerHeight += 2 * t.pad;
        const QPen grid(QColor(150, 150, 150), mm(0.15));
        auto drawHeader = [&] {
            double x = 0;
            painter.setFont(headFont);
            for (int c = 0; c < int(titles.size()); ++c) {
                const QRectF box(x, pages.y(), t.widths[std::size_t(c)], headerHeight);
                painter.fillRect(box, QColor(235, 235, 235));
                painter.setPen(grid);
                painter.drawRect(box);
                painter.setPen(Qt::black);
                painter.drawText(box.adjusted(t.pad, t.pad, -t.pad, -t.pad), Qt::TextWordWrap | Qt::AlignLeft | Qt::AlignBottom,
                                 titles[c]);
                x += t.widths[std::size_t(c)];
            }
            pages.advance(headerHeight);
        };
        auto rowHeight = [&](int r) {
            double height = cell.height();
            const QStringList& row = d.rows[r];
            for (int c = 0; c < int(d.columns.size()); ++c)
                if (d.wraps.value(c))
                    height = std::max(height, wrappedHeight(cell, row.value(c), t.widths[std::size_t(c)] - 2 * t.pad));
            const bool pictures = r < d.rowImages.size() &&
                                  std::any_of(d.rowImages[r].begin(), d.rowImages[r].end(),
                                              [](const QImage& image) { return !image.isNull(); });
            if (pictures) height = std::max(height, t.imageHeight);
            return height + 2 * t.pad;
        };
        ok = ok && pages.reserve(headerHeight + rowHeight(0));
        drawHeader();
        pages.setHeader(drawHeader);
        for (int r = 0; r < int(d.rows.size()); ++r) {
            const double height = rowHeight(r);
            ok = ok && pages.reserve(height);
            double x = 0;
            painter.setFont(cellFont);
            for (int c = 0; c < int(titles.size()); ++c) {
                const QRectF box(x, pages.y(), t.widths[std::size_t(c)], height);
                painter.setPen(grid);
                painter.drawRect(box);
                const QRectF inner = box.adjusted(t.pad, t.pad, -t.pad, -t.pad);
                if (c < int(d.columns.size())) {
                    painter.setPen(Qt::black);
                    const int align = (d.rightAligned.value(c) ? Qt::AlignRight : Qt::AlignLeft) | Qt::AlignVCenter;
                    painter.drawText(inner, align | (d.wraps.value(c) ? int(Qt::TextWordWrap) : 0), d.rows[r].value(c));
                } else if (r < d.rowImages.size() && c - d.columns.size() < d.rowImages[r].size()) {
                    const QImage& image = d.rowImages[r][c - d.columns.size()];
                    if (!image.isNull()) {
                        const QSizeF size = QSizeF(image.size()).scaled(inner.size(), Qt::KeepAspectRatio);
                        painter.drawImage(QRectF(inner.center() - QPointF(size.width(), size.height()) / 2, size), image);
                    }
                }
                x += t.widths[std::size_t(c)];
            }
            pages.advance(height);
        }
        pages.setHeader({});
    }

    // The chart, whole, with its heading.
    if (!d.chart.isNull()) {
        const QSizeF size = QSizeF(d.chart.size()).scaled(QSizeF(std::min(width, mm(180)), mm(110)), Qt::KeepAspectRatio);
        const QFont headingFont = fontOf(11, true);
        const double heading = QFontMetricsF(headingFont, &writer).height() + mm(1);
        pages.advance(mm(4));
        ok = ok && pages.reserve(heading + size.height());
        paragraph(d.chartTitle, headingFont, mm(1));
        painter.drawImage(QRectF(QPointF(0, pages.y()), size), d.chart);
        pages.advance(size.height());
    }
    pages.finish();
    if (!painter.end() || !ok) {
        if (error) *error = QStringLiteral("the PDF writer did not take every page");
        return false;
    }
    return true;
}

}  // namespace lodforge::widgets
