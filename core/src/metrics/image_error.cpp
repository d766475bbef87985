#include "lodforge/metrics/image_error.h"

#include <nlohmann/json.hpp>

namespace lodforge {

void summarize_image_error(ImageError& error) {
    double covered = 0, mean_abs = 0, over = 0, silhouette = 0;
    for (const ViewImageError& v : error.views) {
        const auto c = static_cast<double>(v.covered);
        covered += c;
        mean_abs += v.mean_abs * c;
        over += v.over_threshold * c;
        silhouette += v.silhouette * c;
    }
    error.mean_abs = covered > 0 ? mean_abs / covered : 0.0;
    error.over_threshold = covered > 0 ? over / covered : 0.0;
    error.silhouette = covered > 0 ? silhouette / covered : 0.0;
}

std::string image_error_json(const ImageError& error, bool with_views) {
    nlohmann::ordered_json j;
    j["size"] = error.size;
    j["threshold"] = error.threshold;
    j["mean_abs"] = error.mean_abs;
    j["over_threshold"] = error.over_threshold;
    j["silhouette"] = error.silhouette;
    if (with_views) {
        nlohmann::ordered_json views = nlohmann::ordered_json::array();
        for (const ViewImageError& v : error.views)
            views.push_back({{"name", v.name},
                             {"mean_abs", v.mean_abs},
                             {"over_threshold", v.over_threshold},
                             {"silhouette", v.silhouette},
                             {"covered", v.covered}});
        j["views"] = std::move(views);
    }
    if (!error.files.empty()) j["files"] = error.files;
    return j.dump();
}

}  // namespace lodforge
