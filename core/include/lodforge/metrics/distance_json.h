// The distance summary every report writes (pack.json levels, `lodforge lod`'s lods.json).
#pragma once

#include "lodforge/metrics/metrics.h"

#include <string>

namespace lodforge {

// A JSON object with hausdorff, mean and rms, absolute and relative to the reference's diagonal, and
// color_rms / texcoord_rms when they were measured; the per-vertex fields are left out.
std::string distance_json(const DistanceResult& d);

}  // namespace lodforge
