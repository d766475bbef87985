#include "lodforge/metrics/distance_json.h"

#include <nlohmann/json.hpp>

namespace lodforge {

std::string distance_json(const DistanceResult& d) {
    nlohmann::ordered_json e;
    e["hausdorff"] = d.hausdorff;
    e["hausdorff_relative"] = d.hausdorff_relative;
    e["mean"] = d.mean;
    e["mean_relative"] = d.mean_relative;
    e["rms"] = d.rms;
    e["rms_relative"] = d.rms_relative;
    if (d.has_color_error) e["color_rms"] = d.color_rms;
    if (d.has_texcoord_error) e["texcoord_rms"] = d.texcoord_rms;
    return e.dump();
}

}  // namespace lodforge
