// Option parsing shared by `simplify` and `lod`: attribute weights and comma-separated number lists.
// Bad values throw lodforge::Error(argument) naming the option, so they exit 1 with a clear message.
#pragma once

#include "lodforge/simplify/simplify.h"

#include <string>
#include <vector>

namespace lodforge::cli {

// "normal=0.02,color=0.1,uv=0.1,uv1=0.4" (keys: normal, color or colour, uv or texcoord, uvN or texcoordN
// for set N; values finite, >= 0)
// applied over `weights`.
// The --weights option's help, shared by every command that simplifies.
inline constexpr const char* kWeightsHelp =
    "Attribute weights, e.g. normal=0.02,color=0.1,uv=0.1; uv0=, uv1=, ... weigh one texcoord set";
void parse_weights(const std::string& text, SimplifyWeights& weights);

// "0.5,0.25,0.1": finite numbers; `option` names the option in messages.
std::vector<double> parse_number_list(const std::string& text, const std::string& option);

}  // namespace lodforge::cli
