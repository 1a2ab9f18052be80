// Stats: the median and the 95th percentile of per-frame times.
#include <algorithm>
#include <cmath>
#include <vector>

#include "Bench.h"

namespace osgbench {

// The same definitions as sgbench's (compare_osg.sh divides one program's median by the other's): the
// median is the mean of the two middle elements for an even count, other percentiles are nearest-rank.
double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return (v.size() % 2) ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double percentile95(std::vector<double> v) {
    if (v.empty()) return 0.0;
    // Nearest-rank percentile.
    std::sort(v.begin(), v.end());
    size_t rank = size_t(std::ceil(0.95 * double(v.size())));
    return v[std::max<size_t>(rank, 1) - 1];
}

}  // namespace osgbench
