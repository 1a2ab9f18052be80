// The statistics the benchmarks and the programs report, one definition for all of them (the OpenSceneGraph peers
// in bench/osg_peer, built alone, keep copies of the same formulas): a median is the mean of the two middle values
// for an even count, other percentiles are nearest-rank. Header-only, so that programs without the testbed (the
// map) use it too.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace stats {

// 0 for no values.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return (v.size() % 2) ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Nearest rank: the smallest value with at least a share p (0..1) of the values at or below it; 0 for no values.
inline double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t rank = size_t(std::ceil(p * double(v.size())));
    return v[std::min(std::max<size_t>(rank, 1), v.size()) - 1];
}

}  // namespace stats
