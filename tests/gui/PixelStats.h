// Pixel measurements for the GUI tests: find the 3D view's region in a screenshot by its background
// colour, and describe the model's pixels in it. Tolerances, not baselines: rendering differs slightly
// between drivers, the checks ask "is there a textured/coloured model" and "did the picture change".
#pragma once

#include <QColor>
#include <QImage>
#include <QRect>
#include <QSet>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace lodforge::testing {

struct PixelStats {
    QRect view;               // bounding box of background pixels (the 3D view), empty when none
    qint64 viewPixels = 0;    // pixels in `view`
    qint64 modelPixels = 0;   // pixels in `view` that are not background
    int distinctColors = 0;   // distinct colours of model pixels, 5 bits per channel
    double lumaStdDev = 0;    // standard deviation of model pixel luma (0..255)
    double chromaticFraction = 0;  // model pixels whose channels spread by >= 40 (clearly not grey)
    double meanRedMinusBlue = 0;   // warm (> 0) or cool (< 0) tint of the model pixels

    double modelFraction() const { return viewPixels ? double(modelPixels) / double(viewPixels) : 0.0; }
};

inline bool nearColor(QRgb pixel, QColor color, int tolerance) {
    return std::abs(qRed(pixel) - color.red()) <= tolerance && std::abs(qGreen(pixel) - color.green()) <= tolerance &&
           std::abs(qBlue(pixel) - color.blue()) <= tolerance;
}

// The rectangle covered by background-coloured pixels (the view, as the model sits inside it).
inline QRect backgroundRect(const QImage& image, QColor background, int tolerance = 2) {
    const QImage rgb = image.convertToFormat(QImage::Format_RGB32);
    int left = rgb.width(), top = rgb.height(), right = -1, bottom = -1;
    for (int y = 0; y < rgb.height(); ++y) {
        const auto* line = reinterpret_cast<const QRgb*>(rgb.constScanLine(y));
        for (int x = 0; x < rgb.width(); ++x) {
            if (!nearColor(line[x], background, tolerance)) continue;
            left = std::min(left, x);
            right = std::max(right, x);
            top = std::min(top, y);
            bottom = std::max(bottom, y);
        }
    }
    return right < 0 ? QRect() : QRect(QPoint(left, top), QPoint(right, bottom));
}

inline PixelStats measure(const QImage& image, QColor background, QRect region = {}, int tolerance = 2) {
    PixelStats stats;
    const QImage rgb = image.convertToFormat(QImage::Format_RGB32);
    stats.view = region.isNull() ? backgroundRect(rgb, background, tolerance) : region;
    if (stats.view.isEmpty()) return stats;
    QSet<int> colors;
    double sum = 0, sumSquares = 0, redMinusBlue = 0;
    qint64 chromatic = 0;
    for (int y = stats.view.top(); y <= stats.view.bottom(); ++y) {
        const auto* line = reinterpret_cast<const QRgb*>(rgb.constScanLine(y));
        for (int x = stats.view.left(); x <= stats.view.right(); ++x) {
            ++stats.viewPixels;
            const QRgb p = line[x];
            if (nearColor(p, background, tolerance)) continue;
            ++stats.modelPixels;
            const int r = qRed(p), g = qGreen(p), b = qBlue(p);
            colors.insert(((r >> 3) << 10) | ((g >> 3) << 5) | (b >> 3));
            const double luma = 0.299 * r + 0.587 * g + 0.114 * b;
            sum += luma;
            sumSquares += luma * luma;
            if (std::max({r, g, b}) - std::min({r, g, b}) >= 40) ++chromatic;
            redMinusBlue += r - b;
        }
    }
    stats.distinctColors = int(colors.size());
    if (stats.modelPixels > 0) {
        const double n = double(stats.modelPixels);
        const double mean = sum / n;
        stats.lumaStdDev = std::sqrt(std::max(0.0, sumSquares / n - mean * mean));
        stats.chromaticFraction = double(chromatic) / n;
        stats.meanRedMinusBlue = redMinusBlue / n;
    }
    return stats;
}

// Fraction of the pixels of `region` (both images the same size) that are model pixels in at least one
// image and differ by more than `threshold` in some channel.
inline double differingFraction(const QImage& a, const QImage& b, QColor background, QRect region = {},
                                int threshold = 24) {
    const QImage ra = a.convertToFormat(QImage::Format_RGB32);
    const QImage rb = b.convertToFormat(QImage::Format_RGB32);
    if (ra.size() != rb.size()) return 1.0;
    if (region.isNull()) region = ra.rect();
    qint64 model = 0, different = 0;
    for (int y = region.top(); y <= region.bottom(); ++y) {
        const auto* la = reinterpret_cast<const QRgb*>(ra.constScanLine(y));
        const auto* lb = reinterpret_cast<const QRgb*>(rb.constScanLine(y));
        for (int x = region.left(); x <= region.right(); ++x) {
            if (nearColor(la[x], background, 2) && nearColor(lb[x], background, 2)) continue;
            ++model;
            if (std::abs(qRed(la[x]) - qRed(lb[x])) > threshold || std::abs(qGreen(la[x]) - qGreen(lb[x])) > threshold ||
                std::abs(qBlue(la[x]) - qBlue(lb[x])) > threshold)
                ++different;
        }
    }
    return model ? double(different) / double(model) : 0.0;
}

// Hue clusters of the model pixels in `region` (whole image when null): the clearly coloured pixels
// (channels spread >= 40, not dark) binned by hue in 30-degree bins; a cluster is a bin holding at least
// `minShare` of them. A heat map shows several; a textured or grey rendering one or two.
inline int hueClusters(const QImage& image, QColor background, QRect region = {}, double minShare = 0.02) {
    const QImage rgb = image.convertToFormat(QImage::Format_RGB32);
    if (region.isNull()) region = rgb.rect();
    qint64 bins[12] = {};
    qint64 total = 0;
    for (int y = region.top(); y <= region.bottom(); ++y) {
        const auto* line = reinterpret_cast<const QRgb*>(rgb.constScanLine(y));
        for (int x = region.left(); x <= region.right(); ++x) {
            const QRgb p = line[x];
            if (nearColor(p, background, 2)) continue;
            const int r = qRed(p), g = qGreen(p), b = qBlue(p);
            if (std::max({r, g, b}) - std::min({r, g, b}) < 40 || std::max({r, g, b}) < 50) continue;
            const int hue = QColor(r, g, b).hsvHue();
            if (hue < 0) continue;
            ++bins[std::min(11, hue / 30)];
            ++total;
        }
    }
    int clusters = 0;
    for (qint64 n : bins)
        if (total > 0 && double(n) >= minShare * double(total)) ++clusters;
    return clusters;
}

}  // namespace lodforge::testing
