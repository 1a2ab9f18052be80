#include "sg/lod/LodSelector.h"

#include "sg/core/Assert.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace sg {

namespace {

bool amount(double v) { return v >= 0 && std::isfinite(v); }
constexpr double kMax = std::numeric_limits<double>::max();  // NaN fails every comparison

// `object` and `option` are -1 when the value is not theirs.
[[noreturn]] void refuse(long object, int option, const char* what, double v, const char* why) {
    std::string where;
    if (object >= 0) where += "object " + std::to_string(object) + " ";
    if (option >= 0) where += "option " + std::to_string(option) + " ";
    std::ostringstream msg;
    msg << "LodSelector::select(): " << where << what << " " << v << " " << why;
    throw std::invalid_argument(msg.str());
}

// Descending ratio as an ascending integer key. A float keeps the ranking to 7 digits, enough to order
// benefits that are estimates anyway; the sort below reads its top 24 bits (5 digits).
std::uint32_t descendingKey(double ratio) {
    const float f = static_cast<float>(ratio);
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return 0x7fffffffu - bits;  // ratio >= 0: the bits of a non-negative float (up to inf) grow with it
}

// Stable LSD radix sort on bits 7 to 30 of the high word, two passes of 12 bits: linear in the steps,
// where a comparison sort or a heap over 10,000 objects would cost more than all the rest of select().
// Stability keeps an object's steps in hull order when their keys are equal.
// Returns where the sorted keys are: `v` or `tmp` (the passes alternate between them).
const std::uint64_t* sortByKey(std::uint64_t* v, std::uint64_t* tmp, std::size_t n) {
    constexpr int kShift0 = 32 + 7, kBits = 12, kBuckets = 1 << kBits;
    static thread_local std::uint32_t count[2][kBuckets + 1];
    std::memset(count, 0, sizeof count);
    for (std::size_t k = 0; k < n; ++k) {
        ++count[0][((v[k] >> kShift0) & (kBuckets - 1)) + 1];
        ++count[1][((v[k] >> (kShift0 + kBits)) & (kBuckets - 1)) + 1];
    }
    for (int pass = 0; pass < 2; ++pass) {
        std::uint32_t* c = count[pass];
        const int shift = kShift0 + kBits * pass;
        if (c[((v[0] >> shift) & (kBuckets - 1)) + 1] == n) continue;  // one bucket: nothing moves
        for (int b = 0; b < kBuckets; ++b) c[b + 1] += c[b];
        for (std::size_t k = 0; k < n; ++k) tmp[c[(v[k] >> shift) & (kBuckets - 1)]++] = v[k];
        std::swap(v, tmp);
    }
    return v;
}

}  // namespace

const LodSelector::Selection& LodSelector::select(const std::vector<Object>& objects, double budgetMs,
                                                  double hysteresis, Floor floor, const Overrun& overrun) {
    if (!amount(budgetMs)) refuse(-1, -1, "budgetMs", budgetMs, "is negative or not finite");
    if (!amount(overrun.minRatio)) refuse(-1, -1, "overrun minRatio", overrun.minRatio, "is negative or not finite");
    if (!amount(overrun.maxMs)) refuse(-1, -1, "overrun maxMs", overrun.maxMs, "is negative or not finite");
    if (!amount(hysteresis)) refuse(-1, -1, "hysteresis", hysteresis, "is negative or not finite");
    const std::size_t n = objects.size();
    sel_.level.assign(n, -1);
    std::size_t total = 0;
    for (const Object& obj : objects) total += obj.count > 0 ? std::size_t(obj.count) : 0;
    // At most one step per option. Grown, never shrunk: no clearing of memory every frame.
    if (steps_.size() < total) {
        steps_.resize(total);
        order_.resize(total);
        scratch_.resize(total);
    }
    std::size_t nSteps = 0;
    double spent = 0.0;
    // CheapestFirst: the cheapest options alone decide which of the two it is (a NaN sum fails the test;
    // the loop below names the culprit).
    bool onlyCheapest = false;
    if (floor == Floor::CheapestFirst) {
        double cheapest = 0.0;
        for (const Object& obj : objects) {
            if (obj.count <= 0 || !obj.options) continue;
            double c = obj.options[0].costMs;
            for (int i = 1; i < obj.count; ++i) c = std::min(c, obj.options[i].costMs);
            cheapest += c;
        }
        onlyCheapest = !(cheapest <= budgetMs);
        floor = onlyCheapest ? Floor::Nothing : Floor::Cheapest;
    }

    for (std::size_t o = 0; o < n; ++o) {
        const Object& obj = objects[o];
        const long at = static_cast<long>(o);
        if (obj.count < 0 || (obj.count > 0 && !obj.options))
            refuse(at, -1, "count", obj.count, "is negative or its options are missing");
        if (obj.last < -1 || obj.last >= obj.count) refuse(at, -1, "last", obj.last, "is not one of its options");
        if (obj.count == 0) continue;
        if (cand_.size() < std::size_t(obj.count)) cand_.resize(obj.count);
        Candidate* cand = cand_.data();
        // One test per object: a negative value fails `ok`, a NaN or infinity makes the sum so; the culprit
        // is looked for only then (a sum that overflows finds none and goes on).
        bool ok = true;
        double sum = 0.0;
        for (int i = 0; i < obj.count; ++i) {
            const Option& op = obj.options[i];
            ok &= (op.costMs >= 0.0) & (op.benefit >= 0.0);
            sum += op.costMs + op.benefit;
            cand[i] = {op.costMs, i == obj.last ? op.benefit * (1.0 + hysteresis) : op.benefit, i};
        }
        if (!ok || !(sum <= kMax))
            for (int i = 0; i < obj.count; ++i) {
                const Option& op = obj.options[i];
                if (!amount(op.costMs)) refuse(at, i, "costMs", op.costMs, "is negative or not finite");
                if (!amount(op.benefit)) refuse(at, i, "benefit", op.benefit, "is negative or not finite");
            }
        // Cheapest first, the better of equal costs first. Insertion sort: a handful of levels.
        for (std::size_t i = 1; i < std::size_t(obj.count); ++i) {
            const Candidate c = cand[i];
            std::size_t j = i;
            for (; j > 0 && (cand[j - 1].cost > c.cost || (cand[j - 1].cost == c.cost && cand[j - 1].rank < c.rank));
                 --j)
                cand[j] = cand[j - 1];
            cand[j] = c;
        }
        const std::size_t m =
            onlyCheapest ? 1 : std::size_t(obj.count);  // cand[0]: the cheapest, the best of equal costs
        Candidate base{0.0, 0.0, -1};
        std::size_t first = 0;
        if (floor == Floor::Cheapest || obj.keep) {
            base = cand[0];
            first = 1;
            sel_.level[o] = base.option;
            spent += base.cost;
        }
        // Upper convex hull from the base, kept in place in cand[first, top). A point with no more
        // benefit than the last kept one is dominated; a kept point under the segment from its predecessor
        // to the new point is below the hull. Collinear points stay: a smaller step may still fit.
        std::size_t top = first;
        for (std::size_t i = first; i < m; ++i) {
            const Candidate p = cand[i];
            if (p.rank <= (top > first ? cand[top - 1].rank : base.rank)) continue;
            while (top > first) {
                const Candidate& a = top - 1 > first ? cand[top - 2] : base;
                const Candidate& b = cand[top - 1];
                if ((b.rank - a.rank) * (p.cost - a.cost) >= (p.rank - a.rank) * (b.cost - a.cost)) break;
                --top;
            }
            cand[top++] = p;
        }
        double prevCost = base.cost, prevRank = base.rank;
        int prevOption = base.option;
        for (std::size_t i = first; i < top; ++i) {
            const double dCost = cand[i].cost - prevCost;
            // The budget cut below sums step costs by bucket: a negative step would undercount.
            SG_ASSERT(dCost >= 0.0, "LodSelector::select(): a hull step lowers the cost");
            SG_ASSERT(nSteps < total, "LodSelector::select(): more hull steps than options");
            const double ratio =
                dCost > 0 ? (cand[i].rank - prevRank) / dCost : std::numeric_limits<double>::infinity();
            steps_[nSteps++] = {static_cast<int>(o), cand[i].option, prevOption, descendingKey(ratio), dCost};
            prevOption = cand[i].option;
            prevCost = cand[i].cost;
            prevRank = cand[i].rank;
        }
    }

    // The hull makes each object's steps ever less worth their cost, so all steps in one order of ratio
    // are the priority queue's order, and an object's steps come in hull order. Sorting every step is not
    // needed: a histogram of their costs by ratio finds the buckets whose steps all fit together, and only
    // the steps of the bucket where the budget runs out, and smaller ones after it, go through the greedy.
    bucketCost_.fill(0.0);
    for (std::size_t k = 0; k < nSteps; ++k) bucketCost_[steps_[k].key >> kBucketShift] += steps_[k].dCost;
    // A margin, since these sums are added in another order than the steps are taken below.
    const double room = (budgetMs - spent) * (1.0 - 1e-12);
    std::size_t cut = 0;
    for (double sum = 0.0; cut < kBuckets && sum + bucketCost_[cut] <= room; ++cut) sum += bucketCost_[cut];
    // Every step in a bucket before the cut is taken (an object's taken steps are a prefix of its hull).
    std::size_t nRest = 0;
    for (std::size_t k = 0; k < nSteps; ++k) {
        const Step& st = steps_[k];
        const std::size_t b = st.key >> kBucketShift;
        if (b < cut) {
            spent += st.dCost;
            sel_.level[st.object] = st.option;
        } else if (b == cut) {
            order_[nRest++] = std::uint64_t(st.key) << 32 | k;
        }
    }
    stuck_.assign(n, 0);
    auto greedy = [&](std::size_t count) {
        const std::uint64_t* sorted = count > 0 ? sortByKey(order_.data(), scratch_.data(), count) : nullptr;
        for (std::size_t k = 0; k < count; ++k) {
            const Step& st = steps_[sorted[k] & 0xffffffffu];
            if (stuck_[st.object]) continue;
            if (spent + st.dCost <= budgetMs) {
                spent += st.dCost;
                sel_.level[st.object] = st.option;
            } else {
                stuck_[st.object] = 1;  // its later steps cost more still, and the budget left only shrinks
            }
        }
    };
    greedy(nRest);
    // After the cut: only steps that fit what is left can be taken. One that does not fit now never will,
    // and leaves its object stuck, as the greedy in ratio order would.
    nRest = 0;
    for (std::size_t k = 0; k < nSteps; ++k) {
        const Step& st = steps_[k];
        if ((st.key >> kBucketShift) <= cut || stuck_[st.object]) continue;
        if (spent + st.dCost <= budgetMs)
            order_[nRest++] = std::uint64_t(st.key) << 32 | k;
        else
            stuck_[st.object] = 1;
    }
    greedy(nRest);
    // What the budget left out: the best of it, and with an overrun, what of it is worth the time. A step is
    // left out when its object stands on the option it steps up from.
    std::uint32_t best = ~0u;
    const std::uint32_t worth = descendingKey(overrun.minRatio);
    nRest = 0;
    for (std::size_t k = 0; k < nSteps; ++k) {
        const Step& st = steps_[k];
        if (sel_.level[st.object] != st.prev) continue;
        best = std::min(best, st.key);
        // An overrun buys detail for what is drawn, never back what the budget left out to fit.
        if (overrun.maxMs > 0.0 && st.prev >= 0 && st.key <= worth) order_[nRest++] = std::uint64_t(st.key) << 32 | k;
    }
    sel_.fit = spent <= budgetMs;
    sel_.leftRatio = 0.0;
    if (best != ~0u) {
        const std::uint32_t bits = 0x7fffffffu - best;
        float f;
        std::memcpy(&f, &bits, sizeof f);
        sel_.leftRatio = double(f);
    }
    if (nRest > 0) {
        // In ratio order an object's steps come in hull order, so each finds its object on the option it
        // steps up from unless an earlier one of them did not fit.
        const double limit = std::max(budgetMs, spent) + overrun.maxMs;
        const std::uint64_t* sorted = sortByKey(order_.data(), scratch_.data(), nRest);
        for (std::size_t k = 0; k < nRest; ++k) {
            const Step& st = steps_[sorted[k] & 0xffffffffu];
            if (sel_.level[st.object] == st.prev && spent + st.dCost <= limit) {
                spent += st.dCost;
                sel_.level[st.object] = st.option;
            }
        }
    }
    sel_.costMs = spent;
    sel_.benefit = 0.0;
    for (std::size_t o = 0; o < n; ++o)
        if (sel_.level[o] >= 0) sel_.benefit += objects[o].options[sel_.level[o]].benefit;
    return sel_;
}

}  // namespace sg
