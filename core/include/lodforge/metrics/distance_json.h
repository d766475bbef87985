// The distance summary every report writes (pack.json levels, `lodforge lod`'s lods.json, `lodforge
// compare --json`): one key list, so the reports cannot drift apart.
#pragma once

#include "lodforge/metrics/metrics.h"

#include <string>

namespace lodforge {

// A JSON object with hausdorff, mean and rms, absolute and relative to the reference's diagonal, and
// color_rms / texcoord_rms when they were measured; the per-vertex fields are left out. With
// `with_one_sided`, also the diagonal and both one-sided distances (test_to_reference, reference_to_test:
// max, mean, rms, samples), as `lodforge compare` prints them.
std::string distance_json(const DistanceResult& d, bool with_one_sided = false);

}  // namespace lodforge
