#include "sg/cull/DrawList.h"

#include <cstring>

namespace sg {

void DrawList::keepEmissionOrder() {
    order.resize(items.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
}

void DrawList::sort() {
    const uint32_t n = uint32_t(items.size());
    for (uint32_t i = uint32_t(keys_.size()); i < n; ++i)
        keys_.push_back(makeKey(items[i].mesh, items[i].material, 0.0f));
    keysTmp_.resize(n);
    order.resize(n);
    tmp_.resize(n);
    work_.resize(n);
    // LSD radix sort of the 22-bit keys in two passes of 11 bits (histograms small enough for L1), both
    // histograms from one read; a pass where every key falls in one bucket is skipped. Sorted in the
    // work arrays: keys_ stays in item order.
    constexpr int kBits[2] = {11, 11}, kShift[2] = {0, 11};
    std::vector<uint32_t>& count = count_;
    count.assign(2 * 2048, 0);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t k = keysTmp_[i] = keys_[i];
        order[i] = i;
        count[k & 0x7ff]++;
        count[2048 + ((k >> 11) & 0x7ff)]++;
    }
    for (int pass = 0; pass < 2; ++pass) {
        uint32_t* c = &count[size_t(pass) * 2048];
        const int shift = kShift[pass];
        const uint32_t digitMask = (1u << kBits[pass]) - 1;
        if (n == 0 || c[(keysTmp_[0] >> shift) & digitMask] == n) continue;
        uint32_t pos = 0;
        for (uint32_t b = 0; b <= digitMask; ++b) {
            const uint32_t v = c[b];
            c[b] = pos;
            pos += v;
        }
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t k = keysTmp_[i];
            const uint32_t dst = c[(k >> shift) & digitMask]++;
            work_[dst] = k;
            tmp_[dst] = order[i];
        }
        keysTmp_.swap(work_);
        order.swap(tmp_);
    }
}

}  // namespace sg
