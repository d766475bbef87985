#include "simplify_options.h"

#include "lodforge/error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace lodforge::cli {
namespace {

std::vector<std::string> split(const std::string& text, char sep) {
    std::vector<std::string> parts;
    std::stringstream in(text);
    std::string part;
    while (std::getline(in, part, sep)) parts.push_back(part);
    if (!text.empty() && text.back() == sep) parts.emplace_back();
    return parts;
}

double parse_number(const std::string& text, const std::string& what) {
    const char* begin = text.c_str();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (text.empty() || end != begin + text.size() || !std::isfinite(v))
        throw Error(Error::Kind::argument, what + ": '" + text + "' is not a number");
    return v;
}

}  // namespace

// `uvN` (or `texcoordN`) sets texcoord set N's weight; sets before N without their own entry keep the
// plain `uv` weight, whichever order the items come in.
void parse_weights(const std::string& text, SimplifyWeights& weights) {
    const char* names = " (names: normal, color, uv, uv0, uv1, ...)";
    std::vector<std::pair<std::size_t, float>> per_set;
    for (const std::string& item : split(text, ',')) {
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos)
            throw Error(Error::Kind::argument, "--weights: expected name=value, got '" + item + "'" + names);
        const std::string name = item.substr(0, eq);
        const double v = parse_number(item.substr(eq + 1), "--weights " + name);
        if (v < 0) throw Error(Error::Kind::argument, "--weights " + name + ": must be >= 0");
        std::string digits;
        if (name.size() > 2 && name.compare(0, 2, "uv") == 0) digits = name.substr(2);
        else if (name.size() > 8 && name.compare(0, 8, "texcoord") == 0) digits = name.substr(8);
        if (name == "normal") weights.normal = static_cast<float>(v);
        else if (name == "color" || name == "colour") weights.color = static_cast<float>(v);
        else if (name == "uv" || name == "texcoord") weights.texcoord = static_cast<float>(v);
        else if (!digits.empty() && digits.size() <= 2 && digits.find_first_not_of("0123456789") == std::string::npos)
            per_set.emplace_back(std::stoul(digits), static_cast<float>(v));
        else
            throw Error(Error::Kind::argument, "--weights: unknown attribute '" + name + "'" + names);
    }
    std::size_t sets = weights.texcoord_sets.size();
    for (const auto& [set, w] : per_set) sets = std::max(sets, set + 1);
    weights.texcoord_sets.resize(sets, weights.texcoord);
    for (const auto& [set, w] : per_set) weights.texcoord_sets[set] = w;
}

std::vector<double> parse_number_list(const std::string& text, const std::string& option) {
    std::vector<double> values;
    for (const std::string& item : split(text, ',')) values.push_back(parse_number(item, option));
    if (values.empty()) throw Error(Error::Kind::argument, option + ": give at least one value");
    return values;
}

}  // namespace lodforge::cli
