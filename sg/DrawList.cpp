#include "sg/DrawList.h"

#include <cstring>

namespace sg {

void DrawList::keepEmissionOrder() {
    order.resize(items.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
}

void DrawList::sort() {
    const uint32_t n = uint32_t(items.size());
    if (keys_.size() != n) {  // items pushed directly: make their keys now
        keys_.resize(n);
        for (uint32_t i = 0; i < n; ++i) keys_[i] = items[i].key = makeKey(items[i].mesh, items[i].material, items[i].depth);
    }
    keysTmp_.resize(n);
    order.resize(n);
    tmp_.resize(n);
    // LSD radix sort, 8 bits a pass; all four histograms in one read, passes with one bucket skipped.
    work_.resize(n);
    uint32_t count[4][256] = {};
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t k = keysTmp_[i] = keys_[i];  // sorted in the work arrays: keys_ stays in item order
        order[i] = i;
        count[0][k & 0xff]++;
        count[1][(k >> 8) & 0xff]++;
        count[2][(k >> 16) & 0xff]++;
        count[3][k >> 24]++;
    }
    for (int pass = 0; pass < 4; ++pass) {
        uint32_t* c = count[pass];
        if (n == 0 || c[(keysTmp_[0] >> (8 * pass)) & 0xff] == n) continue;
        uint32_t pos = 0;
        for (int b = 0; b < 256; ++b) {
            const uint32_t v = c[b];
            c[b] = pos;
            pos += v;
        }
        const int shift = 8 * pass;
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t dst = c[(keysTmp_[i] >> shift) & 0xff]++;
            work_[dst] = keysTmp_[i];
            tmp_[dst] = order[i];
        }
        keysTmp_.swap(work_);
        order.swap(tmp_);
    }
}

}  // namespace sg
