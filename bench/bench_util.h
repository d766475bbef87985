// Small helpers every benchmark's command line and timing tables use.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace lodforge::bench {

// "a,b,c" -> {"a", "b", "c"} (model and ratio lists of the --models / --ratios options).
inline std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(item);
    return out;
}

// The value of option argv[i] (argv[i + 1]; i moves onto it). A missing value ends the run with status 2.
inline std::string option_value(int argc, char** argv, int& i) {
    if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", argv[i]);
        std::exit(2);
    }
    return argv[++i];
}

// Median of repeated timings (robust to the noise of a shared machine).
inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace lodforge::bench
