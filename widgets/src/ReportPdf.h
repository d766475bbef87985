// The report laid out for paper. Private to the widgets library (ReportPanel::exportTo uses it).
//
// Laid out by hand on QPdfWriter pages rather than through QTextDocument's HTML tables, whose layout
// broke numbers and words across lines ("2, / 928") and rows across pages: here numbers never wrap,
// text wraps only at spaces, a row never straddles a page and the table's header repeats on every page.
#pragma once

#include <QImage>
#include <QList>
#include <QPair>
#include <QString>
#include <QStringList>

class QIODevice;

namespace lodforge::widgets {

struct ReportDocument {
    QString title;
    QStringList paragraphs;                       // under the title, wrapped at spaces
    QList<QPair<QString, QString>> parameters;    // name, value; listed under "Parameters"
    QStringList columns;                          // the table's text columns
    QList<bool> wraps;                            // per text column: may wrap at spaces (else one line)
    QList<bool> rightAligned;                     // per text column
    QList<QStringList> rows;                      // one text per column
    QStringList imageColumns;                     // titles of the picture columns after the text
    QList<QList<QImage>> rowImages;               // per row, one image per picture column (null: empty)
    QString chartTitle;
    QImage chart;                                 // null: no chart
};

// Writes `document` as a landscape A4 PDF to `out` (opened for writing). Returns false with the reason in
// `error` when the device does not take the pages.
bool writeReportPdf(QIODevice& out, const ReportDocument& document, const QString& pdfTitle, QString* error);

}  // namespace lodforge::widgets
