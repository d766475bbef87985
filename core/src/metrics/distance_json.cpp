#include "lodforge/metrics/distance_json.h"

#include <nlohmann/json.hpp>

namespace lodforge {
namespace {

nlohmann::ordered_json one_sided_json(const OneSidedDistance& d) {
    return {{"max", d.max}, {"mean", d.mean}, {"rms", d.rms}, {"samples", d.samples}};
}

}  // namespace

std::string distance_json(const DistanceResult& d, bool with_one_sided) {
    nlohmann::ordered_json e;
    e["hausdorff"] = d.hausdorff;
    e["hausdorff_relative"] = d.hausdorff_relative;
    e["mean"] = d.mean;
    e["mean_relative"] = d.mean_relative;
    e["rms"] = d.rms;
    e["rms_relative"] = d.rms_relative;
    if (with_one_sided) {
        e["diagonal"] = d.diagonal;
        e["test_to_reference"] = one_sided_json(d.test_to_reference);
        e["reference_to_test"] = one_sided_json(d.reference_to_test);
    }
    if (d.has_color_error) e["color_rms"] = d.color_rms;
    if (d.has_texcoord_error) e["texcoord_rms"] = d.texcoord_rms;
    return e.dump();
}

}  // namespace lodforge
