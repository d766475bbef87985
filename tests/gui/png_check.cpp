// Checks studio screenshots by their pixels (used by the ctest screenshot entries).
//   png_check model FILE [--min-fraction F] [--min-colors N] [--min-chromatic F] [--min-hues N]
//       the 3D view (found by its background colour) shows a model covering at least F of the view,
//       with at least N distinct colours and at least F of its pixels clearly coloured
//   png_check differ A B --min-fraction F
//       at least F of the model pixels in the 3D view differ between two screenshots of the same size
// Exit status 0 when the check holds, 1 when it does not, 2 on bad usage or unreadable files.
#include "PixelStats.h"

#include "lodforge/widgets/ViewOptions.h"

#include <QCoreApplication>
#include <QImage>
#include <QStringList>

#include <cstdio>

using lodforge::testing::PixelStats;

namespace {

int usage() {
    std::fprintf(stderr,
                 "usage: png_check model FILE [--min-fraction F] [--min-colors N] [--min-chromatic F] [--min-hues N]\n"
                 "       png_check differ A B --min-fraction F\n");
    return 2;
}

bool loadImage(const QString& path, QImage& image) {
    if (image.load(path)) return true;
    std::fprintf(stderr, "png_check: cannot read %s\n", qPrintable(path));
    return false;
}

void print(const QString& name, const PixelStats& s) {
    std::printf("%s: view %dx%d at %d,%d; model %lld px (%.1f%%); %d colours; luma sd %.1f; chromatic %.1f%%; "
                "r-b %.1f\n",
                qPrintable(name), s.view.width(), s.view.height(), s.view.x(), s.view.y(), s.modelPixels,
                100.0 * s.modelFraction(), s.distinctColors, s.lumaStdDev, 100.0 * s.chromaticFraction,
                s.meanRedMinusBlue);
}

}  // namespace

int main(int argc, char* argv[]) {
    QCoreApplication app(argc, argv);
    QStringList args = QCoreApplication::arguments().mid(1);
    if (args.isEmpty()) return usage();
    const QString command = args.takeFirst();

    QStringList files;
    double minFraction = 0, minChromatic = 0;
    int minColors = 0, minHues = 0;
    for (int i = 0; i < args.size(); ++i) {
        const QString& a = args[i];
        bool ok = true;
        if (a == QLatin1String("--min-fraction") && i + 1 < args.size()) {
            minFraction = args[++i].toDouble(&ok);
        } else if (a == QLatin1String("--min-colors") && i + 1 < args.size()) {
            minColors = args[++i].toInt(&ok);
        } else if (a == QLatin1String("--min-hues") && i + 1 < args.size()) {
            minHues = args[++i].toInt(&ok);
        } else if (a == QLatin1String("--min-chromatic") && i + 1 < args.size()) {
            minChromatic = args[++i].toDouble(&ok);
        } else if (a.startsWith(QLatin1String("--"))) {
            return usage();
        } else {
            files << a;
        }
        if (!ok) return usage();
    }
    const QColor background = lodforge::widgets::viewBackgroundColor();

    if (command == QLatin1String("model") && files.size() == 1) {
        QImage image;
        if (!loadImage(files[0], image)) return 2;
        const PixelStats s = lodforge::testing::measure(image, background);
        print(files[0], s);
        bool pass = true;
        if (s.view.isEmpty()) {
            std::printf("FAIL: no 3D view background found\n");
            return 1;
        }
        if (s.modelFraction() < minFraction) {
            std::printf("FAIL: model covers %.3f of the view, expected >= %.3f\n", s.modelFraction(), minFraction);
            pass = false;
        }
        if (s.distinctColors < minColors) {
            std::printf("FAIL: %d distinct colours, expected >= %d\n", s.distinctColors, minColors);
            pass = false;
        }
        if (s.chromaticFraction < minChromatic) {
            std::printf("FAIL: %.3f of the model pixels coloured, expected >= %.3f\n", s.chromaticFraction,
                        minChromatic);
            pass = false;
        }
        const int hues = lodforge::testing::hueClusters(image, background, s.view);
        std::printf("%d hue clusters\n", hues);
        if (hues < minHues) {
            std::printf("FAIL: %d hue clusters, expected >= %d\n", hues, minHues);
            pass = false;
        }
        return pass ? 0 : 1;
    }
    if (command == QLatin1String("differ") && files.size() == 2) {
        QImage a, b;
        if (!loadImage(files[0], a) || !loadImage(files[1], b)) return 2;
        if (a.size() != b.size()) {
            std::printf("FAIL: sizes differ (%dx%d vs %dx%d)\n", a.width(), a.height(), b.width(), b.height());
            return 1;
        }
        print(files[0], lodforge::testing::measure(a, background));
        print(files[1], lodforge::testing::measure(b, background));
        // Compare inside the 3D view only: menus and panels are the same in both.
        const QRect view = lodforge::testing::backgroundRect(a, background)
                               .united(lodforge::testing::backgroundRect(b, background));
        const double fraction = lodforge::testing::differingFraction(a, b, background, view);
        std::printf("%.1f%% of the model pixels differ (expected >= %.1f%%)\n", 100.0 * fraction, 100.0 * minFraction);
        return fraction >= minFraction ? 0 : 1;
    }
    return usage();
}
