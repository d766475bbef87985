// lodforge-studio [FILE] [--screenshot OUT.png [--size WxH]] [--export-report OUT.html|OUT.pdf] [--wireframe] [--flat] [--no-texture]
//                 [--no-colors] [--edges] [--normals] [--uv-checker] [--uv-checker-cells N] [--cells [--cells-by-triangles]]
//                 [--preset NAME|P.json] [--lod-chain R1,R2,..] [--heatmap] [--side-by-side] [--level N] [--compare]
#include "MainWindow.h"

#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

#include "lodforge/pack/preset.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QIcon>
#include <QRegularExpression>
#include <QTimer>

#include <cstdio>

namespace {

// Exit codes of --screenshot.
constexpr int exitUsage = 1;
constexpr int exitLoadFailed = 2;
constexpr int exitSaveFailed = 3;
constexpr int exitJobFailed = 4;

void printError(const QString& message) {
    std::fprintf(stderr, "lodforge-studio: %s\n", qUtf8Printable(message));
}

bool parseSize(const QString& text, QSize& size) {
    static const QRegularExpression pattern(QStringLiteral("^(\\d{2,5})[xX](\\d{2,5})$"));
    const QRegularExpressionMatch match = pattern.match(text);
    if (!match.hasMatch()) return false;
    size = QSize(match.captured(1).toInt(), match.captured(2).toInt());
    return size.width() >= 64 && size.height() >= 64 && size.width() <= 16384 && size.height() <= 16384;
}

// What to do after the file has loaded: build a LOD chain, compute its heat maps, arrange the views, and
// (--screenshot) write the window as a PNG and quit with the exit status.
struct StartupPlan {
    bool buildChain = false;
    bool heatmap = false;
    bool sideBySide = false;
    int level = -1;  // -1: the last level
    bool compare = false;
    QString screenshot;  // empty: stay open
    QString report;      // --export-report: the report written headless (empty: none)
    bool reportMeasured = false;  // the levels were measured at full precision for the report
    bool reportHeatmaps = false;  // the heat maps were computed for the report's thumbnails
    bool headless() const { return !screenshot.isEmpty() || !report.isEmpty(); }
};

void quitWithError(const StartupPlan& plan, const QString& message, int code) {
    printError(message);
    if (plan.headless()) QApplication::exit(code);
}

void finishStartup(lodforge::studio::MainWindow& window, const StartupPlan& plan) {
    using lodforge::studio::MainWindow;
    if (!plan.report.isEmpty() && !plan.reportMeasured) {
        // An exported report carries the full-precision errors, not the quick estimate.
        StartupPlan next = plan;
        next.reportMeasured = true;
        QObject::connect(&window, &MainWindow::measuringFinished, &window, [&window, next](bool ok) {
            if (!ok) return quitWithError(next, QStringLiteral("the levels' measure did not finish"), exitJobFailed);
            finishStartup(window, next);
        }, Qt::SingleShotConnection);
        window.measureLevels(true);
        if (!window.isMeasuring()) quitWithError(plan, QStringLiteral("--export-report: no levels to report"), exitJobFailed);
        return;
    }
    if (!plan.report.isEmpty() && window.isComputingImageErrors()) {
        // The report's image-error column, filled in by the background job.
        QObject::connect(&window, &MainWindow::imageErrorsSettled, &window, [&window, plan] { finishStartup(window, plan); },
                         Qt::SingleShotConnection);
        return;
    }
    if (!plan.report.isEmpty() && !plan.reportHeatmaps && !window.levelViews()->hasHeatmaps()) {
        // The report shows each level beside its heat map; the view keeps the heat map only when asked
        // (--heatmap). runStartupPlan's handler leaves this job to this one.
        StartupPlan next = plan;
        next.reportHeatmaps = true;
        QObject::connect(&window, &MainWindow::jobFinished, &window,
                         [&window, next](const QString& name, bool ok, const QString& message) {
                             if (!ok) return quitWithError(next, QStringLiteral("%1: %2").arg(name, message), exitJobFailed);
                             window.setHeatmapVisible(next.heatmap);
                             finishStartup(window, next);
                         }, Qt::SingleShotConnection);
        window.computeHeatmaps();
        return;
    }
    if (!plan.screenshot.isEmpty() && window.isMeasuring()) {
        // The labels carry the levels' errors, measured after the chain: shoot once they are in.
        QObject::connect(&window, &lodforge::studio::MainWindow::measuringFinished, &window,
                         [&window, plan](bool) { finishStartup(window, plan); }, Qt::SingleShotConnection);
        return;
    }
    window.setSideBySide(plan.sideBySide);
    if (plan.level >= 0) window.levelViews()->setCurrentLevel(plan.level);
    if (plan.compare) window.setCompareVisible(true);
    if (!plan.headless()) return;
    // Let the window settle (layout, first paint of new views) before grabbing it.
    QTimer::singleShot(plan.sideBySide ? 400 : 100, &window, [&window, plan] {
        if (!plan.report.isEmpty()) {
            QString error;
            if (!window.exportReport(plan.report, &error)) {
                printError(error);
                QApplication::exit(exitSaveFailed);
                return;
            }
        }
        if (!plan.screenshot.isEmpty()) {
            const QImage image = window.grabWindowImage();
            if (image.isNull() || !image.save(plan.screenshot, "PNG")) {
                printError(QStringLiteral("cannot write %1").arg(plan.screenshot));
                QApplication::exit(exitSaveFailed);
                return;
            }
        }
        QApplication::exit(0);
    });
}

void runStartupPlan(lodforge::studio::MainWindow& window, const StartupPlan& plan) {
    using lodforge::studio::MainWindow;
    QObject::connect(&window, &MainWindow::loadFinished, &window, [&window, plan](bool ok, const QString& message) {
        if (!ok) {
            quitWithError(plan, message.isEmpty() ? QStringLiteral("loading was cancelled") : message, exitLoadFailed);
            return;
        }
        if (const auto model = window.model()) {
            for (const QString& warning : model->warnings) printError(QStringLiteral("warning: %1").arg(warning));
        }
        if (plan.buildChain) {
            window.buildLodChain();
        } else if (plan.heatmap) {
            window.computeHeatmaps();
        } else {
            finishStartup(window, plan);
        }
    });
    QObject::connect(&window, &MainWindow::jobFinished, &window,
                     [&window, plan](const QString& name, bool ok, const QString& message) {
        if (name == MainWindow::heatmapJobName() && !plan.heatmap) return;  // the report's: finishStartup's own
        if (!ok) {
            quitWithError(plan, QStringLiteral("%1: %2").arg(name, message.isEmpty() ? QStringLiteral("cancelled") : message),
                          exitJobFailed);
            return;
        }
        if (name == MainWindow::lodChainJobName() && plan.heatmap) {
            window.computeHeatmaps();
            return;
        }
        finishStartup(window, plan);
    });
}

bool parseRatios(const QString& text, std::vector<double>& ratios) {
    ratios.clear();
    for (const QString& part : text.split(QLatin1Char(','), Qt::SkipEmptyParts)) {
        bool ok = false;
        const double r = part.trimmed().toDouble(&ok);
        if (!ok || !(r > 0.0 && r <= 1.0)) return false;
        ratios.push_back(r);
    }
    return !ratios.empty();
}

// The command line; one definition for the GUI run and for --help/--version without a display.
struct CommandLine {
    QCommandLineOption screenshot{
        QStringLiteral("screenshot"),
        QStringLiteral("Open FILE, save a PNG of the window to <out.png> once it is shown, and exit "
                       "(exit status 2 when FILE cannot be loaded, 3 when the PNG cannot be written)."),
        QStringLiteral("out.png")};
    QCommandLineOption exportReport{
        QStringLiteral("export-report"),
        QStringLiteral("Open FILE, build the levels (of --preset, --lod-chain or the default preset), measure them "
                       "at full precision, write the report (.pdf: PDF, else HTML) and exit (exit status 2 when FILE "
                       "cannot be loaded, 3 when the report cannot be written, 4 when the build fails)."),
        QStringLiteral("out.html|out.pdf")};
    QCommandLineOption size{
        QStringLiteral("size"), QStringLiteral("Window size, e.g. 1024x768 (for --screenshot: 1280x800 unless given)."),
        QStringLiteral("WxH")};
    QCommandLineOption wireframe{QStringLiteral("wireframe"), QStringLiteral("Start in wireframe.")};
    QCommandLineOption flat{QStringLiteral("flat"), QStringLiteral("Start with flat shading.")};
    QCommandLineOption noTexture{QStringLiteral("no-texture"), QStringLiteral("Start with textures off.")};
    QCommandLineOption noColors{QStringLiteral("no-colors"), QStringLiteral("Start with vertex colours off.")};
    QCommandLineOption edges{QStringLiteral("edges"), QStringLiteral("Start with edges drawn over the shading.")};
    QCommandLineOption normals{QStringLiteral("normals"), QStringLiteral("Start with normals shown as colours.")};
    QCommandLineOption uvChecker{QStringLiteral("uv-checker"), QStringLiteral("Start with the UV checker texture.")};
    QCommandLineOption uvCheckerCells{QStringLiteral("uv-checker-cells"),
                                      QStringLiteral("The UV checker's squares per texture unit, each way (2-128; "
                                                     "default 8). Implies --uv-checker."),
                                      QStringLiteral("N")};
    QCommandLineOption cells{QStringLiteral("cells"),
                             QStringLiteral("Start with the octree cells drawn over the levels (octree methods).")};
    QCommandLineOption cellsByTriangles{QStringLiteral("cells-by-triangles"),
                                        QStringLiteral("Colour the octree cells by triangle count, not depth.")};
    QCommandLineOption preset{QStringLiteral("preset"),
                              QStringLiteral("Load the parameters from a preset (a JSON file or a shipped name: "
                                             "mobile, console, web, scan-archive) and build its levels."),
                              QStringLiteral("NAME|P.json")};
    QCommandLineOption lodChain{QStringLiteral("lod-chain"),
                                QStringLiteral("Build a LOD chain with these level ratios, e.g. 0.5,0.1 "
                                               "(overrides the preset's levels)."),
                                QStringLiteral("ratios")};
    QCommandLineOption heatmap{QStringLiteral("heatmap"),
                               QStringLiteral("Show the levels as heat maps of their distance to the original.")};
    QCommandLineOption sideBySide{QStringLiteral("side-by-side"),
                                  QStringLiteral("Show every level side by side in synchronised views.")};
    QCommandLineOption level{QStringLiteral("level"), QStringLiteral("Show level N in the single view (0 = original)."),
                             QStringLiteral("N")};
    QCommandLineOption compare{QStringLiteral("compare"),
                               QStringLiteral("Split the single view: the original left, the level right.")};
    QCommandLineParser parser;

    CommandLine() {
        parser.setApplicationDescription(
            QStringLiteral("LodForge Studio: view meshes and their levels of detail."));
        parser.addHelpOption();
        parser.addVersionOption();
        parser.addPositionalArgument(QStringLiteral("file"),
                                     QStringLiteral("Mesh to open (PLY, OBJ, glTF, GLB)."), QStringLiteral("[FILE]"));
        parser.addOptions({screenshot, exportReport, size, wireframe, flat, noTexture, noColors, edges, normals, uvChecker, uvCheckerCells, cells,
                           cellsByTriangles, preset, lodChain, heatmap, sideBySide, level, compare});
    }
};

void setApplicationNames() {
    QCoreApplication::setOrganizationName(QStringLiteral("LodForge"));
    QCoreApplication::setApplicationName(QStringLiteral("lodforge-studio"));
    QCoreApplication::setApplicationVersion(QStringLiteral(LODFORGE_VERSION));
}

bool asksForHelpOrVersion(int argc, char* argv[]) {
    for (int i = 1; i < argc; ++i) {
        const QByteArray arg(argv[i]);
        if (arg == "-h" || arg == "--help" || arg == "--help-all" || arg == "-v" || arg == "--version") return true;
    }
    return false;
}

}  // namespace

int main(int argc, char* argv[]) {
    if (asksForHelpOrVersion(argc, argv)) {
        // No display needed to print the usage.
        QCoreApplication app(argc, argv);
        setApplicationNames();
        CommandLine commandLine;
        commandLine.parser.process(app);  // prints and exits
        return 0;
    }

    // Before QApplication: the OpenGL context format VTK needs.
    lodforge::widgets::VtkView::setDefaultSurfaceFormat();

    QApplication app(argc, argv);
    setApplicationNames();
    QApplication::setApplicationDisplayName(QStringLiteral("LodForge Studio"));
    QApplication::setDesktopFileName(QStringLiteral("lodforge-studio"));
    QApplication::setWindowIcon(QIcon(QStringLiteral(":/lodforge/lodforge.png")));

    CommandLine commandLine;
    QCommandLineParser& parser = commandLine.parser;
    parser.process(app);

    const QStringList positional = parser.positionalArguments();
    if (positional.size() > 1) {
        printError(QStringLiteral("expected at most one FILE, got %1 (see --help)").arg(positional.size()));
        return exitUsage;
    }
    const QString file = positional.value(0);
    const bool screenshot = parser.isSet(commandLine.screenshot);
    QSize size(1280, 800);
    if (parser.isSet(commandLine.size) && !parseSize(parser.value(commandLine.size), size)) {
        printError(QStringLiteral("--size expects WIDTHxHEIGHT between 64x64 and 16384x16384, got '%1'")
                       .arg(parser.value(commandLine.size)));
        return exitUsage;
    }
    if (screenshot && file.isEmpty()) {
        printError(QStringLiteral("--screenshot needs a FILE to open"));
        return exitUsage;
    }
    const bool report = parser.isSet(commandLine.exportReport);
    if (report && file.isEmpty()) {
        printError(QStringLiteral("--export-report needs a FILE to open"));
        return exitUsage;
    }

    lodforge::widgets::ViewOptions options;
    options.wireframe = parser.isSet(commandLine.wireframe);
    options.flatShading = parser.isSet(commandLine.flat);
    options.textures = !parser.isSet(commandLine.noTexture);
    options.vertexColors = !parser.isSet(commandLine.noColors);
    options.edges = parser.isSet(commandLine.edges);
    options.normalColors = parser.isSet(commandLine.normals);
    options.uvChecker = parser.isSet(commandLine.uvChecker);
    options.cells = parser.isSet(commandLine.cells);
    options.cellsByTriangles = parser.isSet(commandLine.cellsByTriangles);
    if (parser.isSet(commandLine.uvCheckerCells)) {
        bool ok = false;
        const int cells = parser.value(commandLine.uvCheckerCells).toInt(&ok);
        if (!ok || cells < lodforge::widgets::minUvCheckerCells || cells > lodforge::widgets::maxUvCheckerCells) {
            printError(QStringLiteral("--uv-checker-cells expects a whole number from %1 to %2, got '%3'")
                           .arg(lodforge::widgets::minUvCheckerCells)
                           .arg(lodforge::widgets::maxUvCheckerCells)
                           .arg(parser.value(commandLine.uvCheckerCells)));
            return exitUsage;
        }
        options.uvChecker = true;
        options.uvCheckerCells = cells;
    }
    const bool viewFlags = options != lodforge::widgets::ViewOptions{};

    StartupPlan plan;
    std::vector<double> ratios;
    if (parser.isSet(commandLine.lodChain) && !parseRatios(parser.value(commandLine.lodChain), ratios)) {
        printError(QStringLiteral("--lod-chain expects ratios in (0, 1] separated by commas, got '%1'")
                       .arg(parser.value(commandLine.lodChain)));
        return exitUsage;
    }
    if (parser.isSet(commandLine.level)) {
        bool ok = false;
        plan.level = parser.value(commandLine.level).toInt(&ok);
        if (!ok || plan.level < 0) {
            printError(QStringLiteral("--level expects a level number >= 0, got '%1'").arg(parser.value(commandLine.level)));
            return exitUsage;
        }
    }
    plan.buildChain = !ratios.empty() || parser.isSet(commandLine.preset) || report;
    plan.heatmap = parser.isSet(commandLine.heatmap);
    plan.sideBySide = parser.isSet(commandLine.sideBySide);
    plan.compare = parser.isSet(commandLine.compare);
    if (screenshot) plan.screenshot = parser.value(commandLine.screenshot);
    if (report) plan.report = parser.value(commandLine.exportReport);

    lodforge::studio::MainWindow window;
    // A screenshot is the same whatever the saved settings say; a normal start keeps them unless told.
    if (plan.headless() || viewFlags) window.setViewOptions(options);
    if (plan.headless() || parser.isSet(commandLine.size)) window.resize(size);
    if (plan.headless()) window.setInteractive(false);
    if (parser.isSet(commandLine.preset)) {
        QString error;
        if (!window.loadPreset(parser.value(commandLine.preset), &error)) {
            printError(error);
            return exitUsage;
        }
    }
    if (!ratios.empty()) {
        lodforge::Preset preset = window.preset();
        preset.levels = lodforge::lod_targets_from_ratios(ratios);
        window.setPreset(preset);
    }
    runStartupPlan(window, plan);
    window.show();
    if (!file.isEmpty()) {
        QTimer::singleShot(0, &window, [&window, file] { window.openFile(file); });
    }
    return QApplication::exec();
}
