// Honest status and keyboard in the studio, driven by real key and mouse events under Xvfb: level
// labels and the report state the reached count against the target, a missed target with its reason and
// levels identical to an earlier one; a parameter edit marks the built levels stale (amber bar and
// labels) with one click to rebuild, or a rebuild by itself with the preference on; single-letter
// shortcuts work from a spin box but type into a text field (with the status bar's hint); Help lists the
// keys and links the documentation; the export dialogs create folders, ask before writing into a
// non-empty one and remember where the last export went.
#include "OutputFolderDialog.h"
#include "PixelStats.h"
#include "StudioSession.h"

#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/ParametersPanel.h"
#include "lodforge/widgets/ReportPanel.h"

#include <QAbstractItemView>
#include <QAction>
#include <QApplication>
#include <QCompleter>
#include <QDesktopServices>
#include <QDialog>
#include <QDir>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFile>
#include <QFileDialog>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QPlainTextEdit>
#include <QLabel>
#include <QLineEdit>
#include <QLocale>
#include <QMessageBox>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QMainWindow>
#include <QTabBar>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QUrl>

#include <cmath>
#include <memory>

using lodforge::studio::MainWindow;
using lodforge::widgets::LevelViews;

namespace {

const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");

QString count(std::size_t n) { return QLocale().toString(qulonglong(n)); }

// Amber pixels (the stale bar's #f0a020) in `image`.
qint64 amberPixels(const QImage& image) {
    qint64 n = 0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            const QColor c = image.pixelColor(x, y);
            if (std::abs(c.red() - 0xf0) < 12 && std::abs(c.green() - 0xa0) < 12 && c.blue() < 60) ++n;
        }
    return n;
}

// Receives Help > Documentation's URL instead of a browser.
class UrlCatcher : public QObject {
    Q_OBJECT
public:
    QUrl last;
public slots:
    void open(const QUrl& url) { last = url; }
};

}  // namespace

class StudioStatusTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase() {
        QVERIFY2(QFile::exists(spotPath), qPrintable(spotPath));
        QSettings().clear();
    }
    void init() {
        window_ = lodforge::testing::openStudioWindow();
        QVERIFY(window_);
        window_->activateWindow();
        QVERIFY(QTest::qWaitForWindowActive(window_.get()));
        QVERIFY(lodforge::testing::loadInStudio(*window_, spotPath));
    }
    void cleanup() {
        while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
        window_.reset();
        QSettings().clear();
    }

    void labelsAndReportTellTargetsMissesAndDuplicates();
    void parameterEditMarksLevelsStaleAndRebuilds();
    void singleKeysWorkFromSpinBoxesButTypeInTextFields();
    void helpListsTheKeysAndLinksTheDocs();
    void exportDialogsCreateFoldersAskAndRemember();
    void heatmapRangeIsPerMesh();
    void dockTabsReadableAt1280x800();

private:
    // Ctrl+B, as a user starts a build; waits for the job.
    bool buildByKey(QString* message) {
        QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
        QTest::keyClick(window_.get(), Qt::Key_B, Qt::ControlModifier);
        if (finished.isEmpty() && !finished.wait(60000)) return false;
        *message = finished.at(0).at(2).toString();
        return finished.at(0).at(1).toBool();
    }
    QDoubleSpinBox* normalWeightBox() const {
        return window_->parametersPanel()->findChild<QDoubleSpinBox*>(QStringLiteral("normalWeight"));
    }

    std::unique_ptr<MainWindow> window_;
};

void StudioStatusTest::labelsAndReportTellTargetsMissesAndDuplicates() {
    // The octree cut at close ratios: the structure has few whole-model levels, so several targets land
    // on the same one, far from some of them.
    lodforge::Preset preset = window_->preset();
    preset.method = lodforge::LodMethod::octree;
    preset.octree.max_triangles_per_node = 1500;
    preset.levels = lodforge::lod_targets_from_ratios({0.5, 0.45, 0.4, 0.1});
    window_->setPreset(preset);
    QString message;
    QVERIFY2(buildByKey(&message), qPrintable(message));
    LevelViews* levels = window_->levelViews();
    QCOMPARE(levels->levelCount(), 5);
    window_->setSideBySide(true);
    const QList<QLabel*> labels = levels->tileLabels();
    QCOMPARE(labels.size(), 5);

    int duplicates = 0, misses = 0;
    for (int i = 1; i < levels->levelCount(); ++i) {
        const auto& l = levels->levels()[std::size_t(i)];
        const QString text = labels[i]->text();
        qInfo("LOD %d: %s", i, qPrintable(text));
        // Reached against the target, both as counts.
        const std::size_t target = std::size_t(std::llround(5856 * preset.levels[std::size_t(i - 1)].value));
        QVERIFY2(std::abs(double(l.targetTriangles) - double(target)) <= 1.0, qPrintable(count(l.targetTriangles)));
        QVERIFY2(text.contains(count(l.triangles) + QStringLiteral(" / ") + count(l.targetTriangles) +
                               QStringLiteral(" triangles")),
                 qPrintable(text));
        // A miss is said on the label with the reason, exactly when the count is more than 10 % off.
        const bool missed = std::abs(double(l.triangles) - double(target)) > 0.1 * double(target);
        QCOMPARE(l.missedTarget, missed);
        QCOMPARE(text.contains(QStringLiteral("target missed: ") + l.stopReason), missed);
        if (missed) QVERIFY2(l.stopReason != QStringLiteral("target reached"), qPrintable(text));
        misses += missed;
        // Identical to an earlier level: flagged with that level, and only then.
        int earlier = -1;
        for (int j = 1; j < i && earlier < 0; ++j) {
            const auto& e = levels->levels()[std::size_t(j)];
            if (e.mesh->indices == l.mesh->indices && e.mesh->positions == l.mesh->positions) earlier = j;
        }
        QCOMPARE(l.sameAs, earlier);
        QCOMPARE(text.contains(QStringLiteral("same as LOD %1").arg(earlier)), earlier > 0);
        duplicates += earlier > 0;

        // The report's row says the same.
        QTableWidget* table = window_->reportPanel()->table();
        QCOMPARE(table->item(i, 1)->text(), count(l.triangles));
        QCOMPARE(table->item(i, 2)->text(), count(l.targetTriangles));
        const QString stopped = table->item(i, 7)->text();
        QCOMPARE(stopped.contains(QStringLiteral("target missed")), missed);
        QCOMPARE(stopped.contains(QStringLiteral("same as LOD")), earlier > 0);
    }
    QVERIFY2(duplicates > 0, "close targets on a coarse octree must give a repeated level");
    QVERIFY2(misses > 0, "some target must be missed");
    // The exported HTML carries the flags too.
    const QString html = window_->reportPanel()->toHtml({});
    QVERIFY(html.contains(QStringLiteral("same as LOD")));
    QVERIFY(html.contains(QStringLiteral("<th>Target</th>")));

    // The pack exported from the studio (Ctrl+Shift+E, a new folder typed) leaves out exactly the levels
    // the labels flag: no level is exported twice.
    QTemporaryDir root;
    QVERIFY(root.isValid());
    QTest::keyClick(window_.get(), Qt::Key_E, Qt::ControlModifier | Qt::ShiftModifier);
    lodforge::studio::OutputFolderDialog* dialog = nullptr;
    QTRY_VERIFY((dialog = window_->findChild<lodforge::studio::OutputFolderDialog*>()) && dialog->isVisible());
    const QString packDir = root.filePath(QStringLiteral("spot_pack"));
    dialog->pathEdit()->setFocus();
    dialog->pathEdit()->selectAll();
    QTest::keyClick(dialog->pathEdit(), Qt::Key_Delete);
    QTest::keyClicks(dialog->pathEdit(), packDir);
    QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
    QTest::keyClick(dialog->pathEdit(), Qt::Key_Return);
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.at(0).at(0).toString(), MainWindow::packJobName());
    QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));
    QFile manifest(packDir + QStringLiteral("/pack.json"));
    QVERIFY(manifest.open(QIODevice::ReadOnly));
    const QJsonObject pack = QJsonDocument::fromJson(manifest.readAll()).object();
    QList<int> dropped, flagged;
    for (const QJsonValue& v : pack.value(QStringLiteral("dropped_levels")).toArray()) dropped << v.toInt();
    for (int i = 1; i < levels->levelCount(); ++i)
        if (levels->levels()[std::size_t(i)].sameAs > 0) flagged << i;
    QCOMPARE(dropped, flagged);
    QCOMPARE(pack.value(QStringLiteral("levels")).toArray().size(), levels->levelCount() - duplicates);
    QVERIFY(window_->logView()->toPlainText().contains(QStringLiteral("left out of the pack")));
}

void StudioStatusTest::parameterEditMarksLevelsStaleAndRebuilds() {
    QString message;
    QVERIFY2(buildByKey(&message), qPrintable(message));
    LevelViews* levels = window_->levelViews();
    QVERIFY(!window_->levelsStale());
    QVERIFY(!levels->staleBar()->isVisible());
    QTRY_VERIFY(levels->singleView()->frameCount() > 0);
    const QImage freshShot = window_->grabWindowImage();
    QCOMPARE(amberPixels(freshShot), 0);

    // One step up in a parameter the levels depend on, by keyboard.
    QDoubleSpinBox* normal = normalWeightBox();
    QVERIFY(normal);
    normal->setFocus();
    const double before = normal->value();
    QTest::keyClick(normal, Qt::Key_Up);
    QVERIFY(normal->value() > before);
    QVERIFY(window_->levelsStale());
    QVERIFY(levels->staleBar()->isVisible());
    QVERIFY2(levels->singleLabel()->text().startsWith(QStringLiteral("Stale · LOD")),
             qPrintable(levels->singleLabel()->text()));
    const qint64 amber = amberPixels(window_->grabWindowImage());
    qInfo("stale bar: %lld amber pixels", amber);
    QVERIFY2(amber > 2000, qPrintable(QString::number(amber)));

    // Undo brings the parameters of the build back: fresh again; redo: stale. (From the view: in the spin
    // box, Ctrl+Z undoes its own text.)
    levels->singleView()->setFocus();
    QTest::keyClick(window_.get(), Qt::Key_Z, Qt::ControlModifier);
    QVERIFY(!window_->levelsStale());
    QVERIFY(!levels->staleBar()->isVisible());
    QTest::keyClick(window_.get(), Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
    QVERIFY(window_->levelsStale());

    // The preset's name and the pack's contents do not make levels.
    QTest::keyClick(window_.get(), Qt::Key_Z, Qt::ControlModifier);
    lodforge::Preset renamed = window_->preset();
    renamed.name = "another name";
    renamed.exports.ply = !renamed.exports.ply;
    window_->setPreset(renamed);
    QVERIFY(!window_->levelsStale());

    // One click on Rebuild builds with the current parameters.
    normal->setFocus();
    QTest::keyClick(normal, Qt::Key_Up);
    QVERIFY(window_->levelsStale());
    auto* rebuild = levels->staleBar()->findChild<QPushButton*>(QStringLiteral("rebuildButton"));
    QVERIFY(rebuild && rebuild->isVisible());
    {
        QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
        QTest::mouseClick(rebuild, Qt::LeftButton);
        QVERIFY(finished.wait(60000));
        QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));
    }
    QVERIFY(!window_->levelsStale());
    QVERIFY(!levels->staleBar()->isVisible());
    QVERIFY(!levels->singleLabel()->text().startsWith(QStringLiteral("Stale")));

    // With the preference on (LOD > Rebuild automatically), an edit rebuilds by itself, and the
    // preference persists.
    auto* autoRebuild = window_->findChild<QAction*>(QStringLiteral("actionAutoRebuild"));
    QVERIFY(autoRebuild && autoRebuild->isCheckable() && !autoRebuild->isChecked());
    autoRebuild->trigger();
    QVERIFY(window_->autoRebuild());
    QVERIFY(QSettings().value(QStringLiteral("lod/autoRebuild")).toBool());
    {
        QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
        normal->setFocus();
        QTest::keyClick(normal, Qt::Key_Up);
        QVERIFY(window_->levelsStale());
        QVERIFY(finished.wait(60000));
        QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));
    }
    QVERIFY(!window_->levelsStale());
    QVERIFY(std::abs(double(window_->preset().weights.normal) - normal->value()) < 1e-6);
}

void StudioStatusTest::singleKeysWorkFromSpinBoxesButTypeInTextFields() {
    QString message;
    QVERIFY2(buildByKey(&message), qPrintable(message));
    LevelViews* levels = window_->levelViews();
    QDoubleSpinBox* normal = normalWeightBox();
    QVERIFY(normal);
    normal->setFocus();
    QTRY_VERIFY(normal->hasFocus());
    const double value = normal->value();
    auto* typingHint = window_->findChild<QLabel*>(QStringLiteral("typingHint"));
    QVERIFY(typingHint);
    QVERIFY(!typingHint->isVisible());

    // S from a spin box: side by side, and the value stays.
    QVERIFY(levels->arrangement() == LevelViews::Arrangement::single);
    QTest::keyClick(normal, Qt::Key_S);
    QVERIFY(levels->arrangement() == LevelViews::Arrangement::sideBySide);
    QCOMPARE(normal->value(), value);
    QTest::keyClick(normal, Qt::Key_W);
    QVERIFY(window_->viewOptions().wireframe);
    QTest::keyClick(normal, Qt::Key_O, Qt::ShiftModifier);
    QVERIFY(window_->viewOptions().cellsByTriangles);
    QTest::keyClick(normal, Qt::Key_S);
    QVERIFY(levels->arrangement() == LevelViews::Arrangement::single);
    QCOMPARE(normal->hasFocus(), true);
    // Numbers still go to the spin box.
    normal->selectAll();
    QTest::keyClicks(normal, QStringLiteral("2.5"));
    QTest::keyClick(normal, Qt::Key_Return);
    QCOMPARE(normal->value(), 2.5);

    // In the preset's name, letters are text: no shortcut, and the status bar says why.
    auto* name = window_->parametersPanel()->findChild<QLineEdit*>(QStringLiteral("presetName"));
    QVERIFY(name);
    name->setFocus();
    QTRY_VERIFY(name->hasFocus());
    QVERIFY(typingHint->isVisible());
    name->selectAll();
    QTest::keyClicks(name, QStringLiteral("shx"));
    QCOMPARE(name->text(), QStringLiteral("shx"));
    QVERIFY(levels->arrangement() == LevelViews::Arrangement::single);
    QVERIFY(!levels->heatmapVisible());
    QVERIFY(!levels->compareVisible());
    // Leaving the field ends the pause.
    levels->singleView()->setFocus();
    QTRY_VERIFY(!typingHint->isVisible());
    QTest::keyClick(levels->singleView(), Qt::Key_X);
    QVERIFY(levels->compareVisible());
}

void StudioStatusTest::helpListsTheKeysAndLinksTheDocs() {
    QTest::keyClick(window_.get(), Qt::Key_F1);
    QDialog* sheet = nullptr;
    QTRY_VERIFY((sheet = window_->findChild<QDialog*>(QStringLiteral("shortcutsSheet"))) && sheet->isVisible());
    auto* table = sheet->findChild<QTableWidget*>(QStringLiteral("shortcutsTable"));
    QVERIFY(table && table->rowCount() > 20);
    // Every action with keys in the menus is on the sheet, with its keys.
    auto rowOf = [table](const QString& action) {
        for (int r = 0; r < table->rowCount(); ++r)
            if (table->item(r, 1)->text() == action) return r;
        return -1;
    };
    int row = rowOf(QStringLiteral("Side by side"));
    QVERIFY(row >= 0);
    QCOMPARE(table->item(row, 0)->text(), QStringLiteral("S"));
    row = rowOf(QStringLiteral("Build LOD chain"));
    QVERIFY(row >= 0);
    QCOMPARE(table->item(row, 0)->text(), QKeySequence(Qt::CTRL | Qt::Key_B).toString(QKeySequence::NativeText));
    QVERIFY(rowOf(QStringLiteral("Cells coloured by triangle count")) >= 0);
    sheet->close();

    // Help > Documentation opens docs/studio.md.
    UrlCatcher catcher;
    QDesktopServices::setUrlHandler(QStringLiteral("file"), &catcher, "open");
    auto* docs = window_->findChild<QAction*>(QStringLiteral("actionDocumentation"));
    QVERIFY(docs);
    docs->trigger();
    QDesktopServices::unsetUrlHandler(QStringLiteral("file"));
    QVERIFY2(catcher.last.isLocalFile() && catcher.last.toLocalFile().endsWith(QStringLiteral("docs/studio.md")),
             qPrintable(catcher.last.toString()));
    QFile doc(catcher.last.toLocalFile());
    QVERIFY(doc.open(QIODevice::ReadOnly));
    QVERIFY(doc.readAll().contains("# The studio"));
}

void StudioStatusTest::exportDialogsCreateFoldersAskAndRemember() {
    QTemporaryDir root;
    QVERIFY(root.isValid());
    using lodforge::studio::OutputFolderDialog;
    auto openPackDialog = [this]() -> OutputFolderDialog* {
        QTest::keyClick(window_.get(), Qt::Key_E, Qt::ControlModifier | Qt::ShiftModifier);
        OutputFolderDialog* dialog = nullptr;
        if (!QTest::qWaitFor([&] { return (dialog = window_->findChild<OutputFolderDialog*>()) && dialog->isVisible(); }))
            return nullptr;
        return dialog;
    };
    auto typePath = [](QLineEdit* edit, const QString& path) {
        edit->setFocus();
        edit->selectAll();
        QTest::keyClick(edit, Qt::Key_Delete);
        QTest::keyClicks(edit, path);
    };

    // A new folder typed by name is created and the pack written into it; the first proposal is named
    // after the mesh, outside the data folder.
    OutputFolderDialog* dialog = openPackDialog();
    QVERIFY(dialog);
    QVERIFY2(dialog->pathEdit()->text().endsWith(QStringLiteral("spot_triangulated_pack")), qPrintable(dialog->pathEdit()->text()));
    QVERIFY(!dialog->pathEdit()->text().startsWith(QFileInfo(spotPath).absolutePath()));
    const QString first = root.filePath(QStringLiteral("packs/first"));
    typePath(dialog->pathEdit(), first);
    {
        QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
        QTest::keyClick(dialog->pathEdit(), Qt::Key_Return);
        QVERIFY(finished.wait(60000));
        QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));
    }
    QVERIFY(QFile::exists(first + QStringLiteral("/pack.json")));

    // The next proposal sits beside the last pack.
    dialog = openPackDialog();
    QVERIFY(dialog);
    QCOMPARE(QDir::fromNativeSeparators(dialog->pathEdit()->text()), root.filePath(QStringLiteral("packs/spot_triangulated_pack")));
    // Into the non-empty folder: a question first; No keeps the dialog and writes nothing.
    typePath(dialog->pathEdit(), first);
    QVERIFY2(dialog->findChild<QLabel*>(QStringLiteral("folderNote"))->text().contains(QStringLiteral("already holds")),
             qPrintable(dialog->findChild<QLabel*>(QStringLiteral("folderNote"))->text()));
    QSignalSpy finished(window_.get(), &MainWindow::jobFinished);
    QTest::keyClick(dialog->pathEdit(), Qt::Key_Return);
    QMessageBox* box = nullptr;
    QTRY_VERIFY((box = dialog->findChild<QMessageBox*>(QStringLiteral("nonEmptyFolderBox"))) && box->isVisible());
    QTest::mouseClick(box->button(QMessageBox::No), Qt::LeftButton);
    QTRY_VERIFY(!dialog->findChild<QMessageBox*>(QStringLiteral("nonEmptyFolderBox")));
    QVERIFY(dialog->isVisible());
    QTest::qWait(200);
    QCOMPARE(finished.count(), 0);
    // Write into it: the pack is written.
    QTest::keyClick(dialog->pathEdit(), Qt::Key_Return);
    QTRY_VERIFY((box = dialog->findChild<QMessageBox*>(QStringLiteral("nonEmptyFolderBox"))) && box->isVisible());
    QTest::mouseClick(box->button(QMessageBox::Yes), Qt::LeftButton);
    QVERIFY(finished.wait(60000));
    QVERIFY2(finished.at(0).at(1).toBool(), qPrintable(finished.at(0).at(2).toString()));

    // The report dialog starts in the folder of the last report and writes there.
    QTRY_VERIFY(!window_->findChild<OutputFolderDialog*>());
    window_->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    QString message;
    QVERIFY2(buildByKey(&message), qPrintable(message));
    auto openReportDialog = [this]() -> QFileDialog* {
        QTest::keyClick(window_.get(), Qt::Key_E, Qt::ControlModifier);
        QFileDialog* d = nullptr;
        if (!QTest::qWaitFor([&] { return (d = window_->findChild<QFileDialog*>(QStringLiteral("reportDialog"))) && d->isVisible(); }))
            return nullptr;
        // No window manager under Xvfb: activate the dialog as one would on opening it.
        d->activateWindow();
        if (!QTest::qWaitForWindowActive(d)) return nullptr;
        return d;
    };
    const QString reviews = root.filePath(QStringLiteral("reviews"));
    QVERIFY(QDir().mkpath(reviews));
    QSettings().setValue(QStringLiteral("export/reportDir"), reviews);  // as a report exported there before
    QFileDialog* reportDialog = openReportDialog();
    QVERIFY(reportDialog);
    QCOMPARE(reportDialog->directory().absolutePath(), reviews);
    auto* name = reportDialog->findChild<QLineEdit*>(QStringLiteral("fileNameEdit"));
    QVERIFY(name);
    typePath(name, QStringLiteral("spot.html"));
    if (QCompleter* completer = name->completer(); completer && completer->popup()->isVisible())
        QTest::keyClick(completer->popup(), Qt::Key_Escape);
    QTest::keyClick(name, Qt::Key_Return);
    QTRY_VERIFY(QFile::exists(reviews + QStringLiteral("/spot.html")));
}

void StudioStatusTest::heatmapRangeIsPerMesh() {
    // A range typed for one mesh (model units) would flatten the next mesh's colours: it goes back to auto.
    auto* range = window_->findChild<QDoubleSpinBox*>(QStringLiteral("heatmapRange"));
    QVERIFY(range);
    range->setFocus();
    range->selectAll();
    QTest::keyClicks(range, QStringLiteral("0.05"));
    QTest::keyClick(range, Qt::Key_Return);
    QCOMPARE(range->value(), 0.05);
    QCOMPARE(window_->levelViews()->heatmapRange(), 0.05);
    QVERIFY(lodforge::testing::loadInStudio(*window_, spotPath));
    QCOMPARE(range->value(), 0.0);
    QCOMPARE(range->text(), QStringLiteral("auto"));
    QVERIFY(window_->levelViews()->heatmapRange() != 0.05);
}

void StudioStatusTest::dockTabsReadableAt1280x800() {
    window_->resize(1280, 800);
    // The right column as narrow as a user may drag it: six tabs in 260 pixels.
    auto* params = window_->findChild<QDockWidget*>(QStringLiteral("parametersDock"));
    QVERIFY(params);
    window_->resizeDocks({params}, {260}, Qt::Horizontal);
    QTest::qWait(200);
    int tabs = 0;
    for (QTabBar* bar : window_->findChildren<QTabBar*>()) {
        if (!bar->isVisible() || !qobject_cast<QMainWindow*>(bar->parentWidget())) continue;
        for (int i = 0; i < bar->count(); ++i) {
            ++tabs;
            const QString text = bar->tabText(i);
            const int needed = bar->fontMetrics().horizontalAdvance(text);
            QVERIFY2(bar->tabRect(i).width() > needed, qPrintable(QStringLiteral("%1: %2 < %3").arg(text).arg(bar->tabRect(i).width()).arg(needed)));
        }
    }
    QVERIFY2(tabs >= 6, qPrintable(QString::number(tabs)));
}

int main(int argc, char* argv[]) {
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("LodForgeTests"));
    QApplication::setApplicationName(QStringLiteral("gui_studio_status_test"));
    StudioStatusTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_status_test.moc"
