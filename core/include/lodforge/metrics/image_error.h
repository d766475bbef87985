// Image-space error: what an artist sees. Two meshes rendered with the same camera, light and materials
// from a fixed set of views, compared pixel by pixel. The renderer lives outside the core (it needs VTK:
// lodforge/render/image_compare.h); these are the parameters and results, so the pack (pack.json) and
// the front ends can carry them without a renderer. docs/image-compare.md describes the measures.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace lodforge {

struct ImageErrorParams {
    int size = 256;           // square images, pixels per side
    int threshold = 32;       // a pixel "differs" when a colour channel differs by more than this (0-255)
    std::string output_dir;   // when set: side-by-side and difference PNGs per view are written there
};

struct ViewImageError {
    std::string name;              // "+x", "-y", "+x+y-z", ...
    double mean_abs = 0;           // mean absolute colour difference (0-255, over R, G, B) over covered pixels
    double over_threshold = 0;     // fraction of covered pixels whose colour differs by more than the threshold
    double silhouette = 0;         // fraction of covered pixels covered by one mesh and not the other
    std::size_t covered = 0;       // pixels covered by either mesh
};

struct ImageError {
    std::vector<ViewImageError> views;  // 6 axis views, then 8 diagonal ones
    // Over all views: each measure's pixels summed over the views, so larger views weigh more.
    double mean_abs = 0, over_threshold = 0, silhouette = 0;
    int size = 0, threshold = 0;   // the parameters used
    std::vector<std::string> files;  // PNGs written (ImageErrorParams::output_dir), in view order
};

// The overall measures from the views' (each view weighted by its covered pixels).
void summarize_image_error(ImageError& error);

// JSON text: {"size", "threshold", "mean_abs", "over_threshold", "silhouette"[, "views": [{"name",
// "mean_abs", "over_threshold", "silhouette", "covered"}]][, "files"]}: one format for `compare --json`
// and pack.json.
std::string image_error_json(const ImageError& error, bool with_views);

}  // namespace lodforge
