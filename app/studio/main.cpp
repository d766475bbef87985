// lodforge-studio [FILE] [--screenshot OUT.png [--size WxH]] [--wireframe] [--flat] [--no-texture]
//                 [--no-colors]
#include "MainWindow.h"

#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

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

// --screenshot: when the load finishes, write the window as a PNG and quit with the exit status.
void saveScreenshotWhenLoaded(lodforge::studio::MainWindow& window, const QString& path) {
    QObject::connect(&window, &lodforge::studio::MainWindow::loadFinished, &window,
                     [&window, path](bool ok, const QString& message) {
        if (!ok) {
            printError(message.isEmpty() ? QStringLiteral("loading was cancelled") : message);
            QApplication::exit(exitLoadFailed);
            return;
        }
        if (const auto model = window.model()) {
            for (const QString& warning : model->warnings) printError(QStringLiteral("warning: %1").arg(warning));
        }
        // Let the window settle (layout, first paint) before grabbing it.
        QTimer::singleShot(100, &window, [&window, path] {
            const QImage image = window.grabWindowImage();
            if (image.isNull() || !image.save(path, "PNG")) {
                printError(QStringLiteral("cannot write %1").arg(path));
                QApplication::exit(exitSaveFailed);
                return;
            }
            QApplication::exit(0);
        });
    });
}

// The command line; one definition for the GUI run and for --help/--version without a display.
struct CommandLine {
    QCommandLineOption screenshot{
        QStringLiteral("screenshot"),
        QStringLiteral("Open FILE, save a PNG of the window to <out.png> once it is shown, and exit "
                       "(exit status 2 when FILE cannot be loaded, 3 when the PNG cannot be written)."),
        QStringLiteral("out.png")};
    QCommandLineOption size{
        QStringLiteral("size"), QStringLiteral("Window size, e.g. 1024x768 (for --screenshot: 1280x800 unless given)."),
        QStringLiteral("WxH")};
    QCommandLineOption wireframe{QStringLiteral("wireframe"), QStringLiteral("Start in wireframe.")};
    QCommandLineOption flat{QStringLiteral("flat"), QStringLiteral("Start with flat shading.")};
    QCommandLineOption noTexture{QStringLiteral("no-texture"), QStringLiteral("Start with textures off.")};
    QCommandLineOption noColors{QStringLiteral("no-colors"), QStringLiteral("Start with vertex colours off.")};
    QCommandLineParser parser;

    CommandLine() {
        parser.setApplicationDescription(
            QStringLiteral("LodForge Studio: view meshes and their levels of detail."));
        parser.addHelpOption();
        parser.addVersionOption();
        parser.addPositionalArgument(QStringLiteral("file"),
                                     QStringLiteral("Mesh to open (PLY, OBJ, glTF, GLB)."), QStringLiteral("[FILE]"));
        parser.addOptions({screenshot, size, wireframe, flat, noTexture, noColors});
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

    lodforge::widgets::ViewOptions options;
    options.wireframe = parser.isSet(commandLine.wireframe);
    options.flatShading = parser.isSet(commandLine.flat);
    options.textures = !parser.isSet(commandLine.noTexture);
    options.vertexColors = !parser.isSet(commandLine.noColors);

    lodforge::studio::MainWindow window;
    window.setViewOptions(options);
    if (screenshot || parser.isSet(commandLine.size)) window.resize(size);
    if (screenshot) {
        window.setInteractive(false);
        saveScreenshotWhenLoaded(window, parser.value(commandLine.screenshot));
    }
    window.show();
    if (!file.isEmpty()) {
        QTimer::singleShot(0, &window, [&window, file] { window.openFile(file); });
    }
    return QApplication::exec();
}
