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

// Descending ratio as an ascending integer key. A float keeps the ranking to 7 digits; the sort below reads its
// top 24 bits (5 digits), and sortExact() orders the steps it cannot tell apart by their full ratio: the order
// must be exact for more budget never to show less, estimates as the benefits are.
std::uint32_t descendingKey(double ratio) {
    const float f = static_cast<float>(ratio);
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return 0x7fffffffu - bits;  // ratio >= 0: the bits of a non-negative float (up to inf) grow with it
}

constexpr int kSortShift = 32 + 7;  // the radix sort reads the high word's bits from 7 up

// Stable LSD radix sort on bits 7 to 30 of the high word, two passes of 12 bits: linear in the steps,
// where a comparison sort or a heap over 10,000 objects would cost more than all the rest of select().
// Stability keeps an object's steps in hull order when their keys are equal.
// Returns where the sorted keys are: `v` or `tmp` (the passes alternate between them).
std::uint64_t* sortByKey(std::uint64_t* v, std::uint64_t* tmp, std::size_t n) {
    constexpr int kBits = 12, kBuckets = 1 << kBits;
    static thread_local std::uint32_t count[2][kBuckets + 1];
    std::memset(count, 0, sizeof count);
    for (std::size_t k = 0; k < n; ++k) {
        ++count[0][((v[k] >> kSortShift) & (kBuckets - 1)) + 1];
        ++count[1][((v[k] >> (kSortShift + kBits)) & (kBuckets - 1)) + 1];
    }
    for (int pass = 0; pass < 2; ++pass) {
        std::uint32_t* c = count[pass];
        const int shift = kSortShift + kBits * pass;
        if (c[((v[0] >> shift) & (kBuckets - 1)) + 1] == n) continue;  // one bucket: nothing moves
        for (int b = 0; b < kBuckets; ++b) c[b + 1] += c[b];
        for (std::size_t k = 0; k < n; ++k) tmp[c[(v[k] >> shift) & (kBuckets - 1)]++] = v[k];
        std::swap(v, tmp);
    }
    return v;
}

}  // namespace

// Checks one object's options and returns them ranked (the last one's benefit raised by the hysteresis),
// cheapest first, the better of equal costs first.
LodSelector::Candidate* LodSelector::rankOptions(const Object& obj, long at, double hysteresis) {
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
    // Insertion sort: a handful of levels.
    for (std::size_t i = 1; i < std::size_t(obj.count); ++i) {
        const Candidate c = cand[i];
        std::size_t j = i;
        for (; j > 0 && (cand[j - 1].cost > c.cost || (cand[j - 1].cost == c.cost && cand[j - 1].rank < c.rank)); --j)
            cand[j] = cand[j - 1];
        cand[j] = c;
    }
    return cand;
}

// Puts object `o` on its floor (when `floored` or kept) and appends its steps up its upper convex hull of
// ranked options to steps_; with `onlyCheapest`, its cheapest option is its only one.
void LodSelector::addSteps(const Object& obj, std::size_t o, double hysteresis, bool floored, bool onlyCheapest) {
    const long at = static_cast<long>(o);
    if (obj.count < 0 || (obj.count > 0 && !obj.options))
        refuse(at, -1, "count", obj.count, "is negative or its options are missing");
    if (obj.last < -1 || obj.last >= obj.count) refuse(at, -1, "last", obj.last, "is not one of its options");
    if (obj.count == 0) return;
    Candidate* cand = rankOptions(obj, at, hysteresis);
    const std::size_t m = onlyCheapest ? 1 : std::size_t(obj.count);  // cand[0]: the cheapest, the best of equals
    Candidate base{0.0, 0.0, -1};
    std::size_t first = 0;
    if (floored || obj.keep) {
        base = cand[0];
        first = 1;
        sel_.level[o] = base.option;
        spent_ += base.cost;
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
    Candidate prev = base;
    for (std::size_t i = first; i < top; ++i) {
        const double dCost = cand[i].cost - prev.cost;
        // The budget cut sums step costs by bucket: a negative step would undercount.
        SG_ASSERT(dCost >= 0.0, "LodSelector::select(): a hull step lowers the cost");
        SG_ASSERT(nSteps_ < steps_.size(), "LodSelector::select(): more hull steps than options");
        double ratio = dCost > 0 ? (cand[i].rank - prev.rank) / dCost : std::numeric_limits<double>::infinity();
        if (!(ratio >= 0.0)) ratio = 0.0;  // a NaN from benefits that overflow with the bonus: the order needs none
        steps_[nSteps_++] = {static_cast<int>(o), cand[i].option, prev.option, descendingKey(ratio), dCost, ratio};
        prev = cand[i];
    }
}

// The hull makes each object's steps ever less worth their cost, so all steps in one order of ratio are the
// priority queue's order, and an object's steps come in hull order. Sorting every step is not needed: a
// histogram of their costs by ratio finds the buckets whose steps all fit together, taken here, and only the
// steps of the bucket where the budget runs out (put in order_, `cutCount` of them), and smaller ones after
// it, go through the greedy. Returns that bucket.
std::size_t LodSelector::takeWholeBuckets(std::size_t& cutCount) {
    bucketCost_.fill(0.0);
    for (std::size_t k = 0; k < nSteps_; ++k) bucketCost_[steps_[k].key >> kBucketShift] += steps_[k].dCost;
    // A margin, since these sums are added in another order than the greedy would add them.
    const double room = (budget_ - spent_) * (1.0 - 1e-12);
    std::size_t cut = 0;
    for (double sum = 0.0; cut < kBuckets && sum + bucketCost_[cut] <= room; ++cut) sum += bucketCost_[cut];
    // Every step in a bucket before the cut is taken (an object's taken steps are a prefix of its hull).
    cutCount = 0;
    for (std::size_t k = 0; k < nSteps_; ++k) {
        const Step& st = steps_[k];
        const std::size_t b = st.key >> kBucketShift;
        if (b < cut) {
            spent_ += st.dCost;
            sel_.level[st.object] = st.option;
        } else if (b == cut) {
            order_[cutCount++] = std::uint64_t(st.key) << 32 | k;
        }
    }
    return cut;
}

// The steps after the cut that can still be taken: an object's steps in hull order up to the first that does
// not fit what is left (it never will: what is spent only grows). That one counts here as the greedy would
// count it on reaching it: in the best ratio left out, and when it closes the overrun, from its place on.
std::size_t LodSelector::candidatesAfter(std::size_t cut) {
    std::size_t count = 0;
    int dropped = -1;  // an object whose step did not fit (its steps are together in steps_)
    for (std::size_t k = 0; k < nSteps_; ++k) {
        const Step& st = steps_[k];
        if ((st.key >> kBucketShift) <= cut || stuck_[st.object] || st.object == dropped) continue;
        if (spent_ + st.dCost <= (pastBudget(st) ? overLimit_ : budget_)) {
            order_[count++] = std::uint64_t(st.key) << 32 | k;
            continue;
        }
        dropped = st.object;
        left_ = std::max(left_, st.ratio);
        if (closes(st) && (closeAt_ == kNoStep || before(std::uint32_t(k), closeAt_))) closeAt_ = std::uint32_t(k);
    }
    return count;
}

// order_[0, count) in the greedy's exact order: the radix sort, then each run of keys it cannot tell apart
// sorted by the full ratio (runs are short: the sort reads 16 bits of the ratio's mantissa).
const std::uint64_t* LodSelector::sortExact(std::size_t count) {
    std::uint64_t* v = sortByKey(order_.data(), scratch_.data(), count);
    const auto earlier = [this](std::uint64_t a, std::uint64_t b) {
        return before(std::uint32_t(a & 0xffffffffu), std::uint32_t(b & 0xffffffffu));
    };
    for (std::size_t i = 0, j = 0; i < count; i = j) {
        for (j = i + 1; j < count && (v[j] >> kSortShift) == (v[i] >> kSortShift);) ++j;
        if (j - i > 1) std::sort(v + i, v + j, earlier);
    }
    return v;
}

// Takes the steps in order_[0, count), best ratio first, each that fits its limit: the budget, or for an
// upgrade worth the overrun while it is open, the overrun's. One that does not fit stops its object (its later
// steps cost more still, and what is left only shrinks).
void LodSelector::greedy(std::size_t count) {
    if (count == 0) return;
    const std::uint64_t* sorted = sortExact(count);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t i = std::uint32_t(sorted[k] & 0xffffffffu);
        const Step& st = steps_[i];
        if (stuck_[st.object]) continue;
        if (closeAt_ != kNoStep && !before(i, closeAt_)) closed_ = true;
        if (spent_ + st.dCost > budget_) left_ = std::max(left_, st.ratio);
        if (spent_ + st.dCost <= (pastBudget(st) && !closed_ ? overLimit_ : budget_)) {
            spent_ += st.dCost;
            sel_.level[st.object] = st.option;
        } else {
            stuck_[st.object] = 1;
            closed_ = closed_ || closes(st);
        }
    }
}

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
    // CheapestFirst: the cheapest options alone decide which of the two it is (a NaN sum fails the test;
    // addSteps names the culprit).
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
    nSteps_ = 0;
    spent_ = 0.0;
    for (std::size_t o = 0; o < n; ++o) addSteps(objects[o], o, hysteresis, floor == Floor::Cheapest, onlyCheapest);

    budget_ = budgetMs;
    sel_.fit = spent_ <= budgetMs;  // the floor fits; the budget's steps keep within it
    overrun_ = overrun.maxMs > 0.0;
    overLimit_ = overrun_ ? std::max(budgetMs, spent_) + overrun.maxMs : budgetMs;
    minRatio_ = overrun.minRatio;
    closed_ = false;
    closeAt_ = kNoStep;
    left_ = 0.0;
    stuck_.assign(n, 0);
    std::size_t count = 0;
    const std::size_t cut = takeWholeBuckets(count);
    greedy(count);
    greedy(candidatesAfter(cut));

    sel_.leftRatio = left_;
    sel_.costMs = spent_;
    sel_.benefit = 0.0;
    sel_.score = 0.0;
    for (std::size_t o = 0; o < n; ++o) {
        const int l = sel_.level[o];
        if (l < 0) continue;
        const double b = objects[o].options[l].benefit;
        sel_.benefit += b;
        sel_.score += l == objects[o].last ? b * (1.0 + hysteresis) : b;
    }
    return sel_;
}

}  // namespace sg
