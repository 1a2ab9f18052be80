// LodSelector: the time-budgeted choice of detail levels of Funkhouser and Sequin's adaptive display (1993).
// Every visible object offers its levels as (predicted draw cost, benefit) options, plus drawing nothing;
// select() picks one option per object so that the total cost fits a frame budget and the total benefit is
// high. It is greedy by benefit per cost over each object's upper convex hull of options: the hull makes an
// object's upgrades ever less worth their cost, so taking upgrades best-ratio-first is the classic
// near-optimal answer to this multiple-choice knapsack at a cost linear in the options, where the exact
// answer is a search.
//
// More budget never shows less. For the same objects, last choices, hysteresis, floor and overrun, the score
// (Selection::score: the chosen benefits, the last choice's raised by the hysteresis) at a larger budget is at
// least the score at a smaller one. The score rather than the plain benefit, because the score is what the
// choice weighs: keeping last frame's level is worth its bonus, as a level that changes shows as a pop. No
// choice that honours the hysteresis can promise the plain benefit: with a hysteresis of 10% and last frame's
// level costlier and 5% less worth than another, a budget that affords only the other shows it, and one that
// affords both keeps last frame's. The benefit stays within that bonus: at the larger budget it is at least the
// smaller budget's over (1 + hysteresis), and with no hysteresis, or no last choices, it never falls.
// Why: the upgrades are taken in one fixed order (best ratio first, ties in hull order), each if it fits, an
// object stopping at its first upgrade that does not. Two budgets take the same upgrades up to the first, X,
// that only the larger affords. After X the smaller has less room left than X costs and buys only upgrades
// worth at most X's ratio: at most X's worth in all, which the larger gained with X alone. For that the order
// is exact (ratios compared in full, not only the bits the sort reads), and no upgrade after X may have more
// room than X had (the overrun closes when an object worth it is left out). CheapestFirst's two regimes meet at
// the sum of the cheapest options: below it the score is at most theirs, above it at least. In floating point
// it holds up to the rounding of the cost sums: two budgets closer than that may differ.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sg {

class LodSelector {
public:
    struct Option {
        double costMs = 0.0;   // predicted draw time, >= 0
        double benefit = 0.0;  // >= 0, e.g. projected pixels times the level's accuracy
    };
    struct Object {
        const Option* options = nullptr;  // one per level, in any order; read only during select()
        int count = 0;
        int last = -1;  // the option chosen last frame, or -1 for nothing
        // Never left out, whatever the floor: drawn at least at its cheapest option, as Floor::Cheapest
        // draws every object (when CheapestFirst leaves others out, at its cheapest).
        bool keep = false;
    };
    // Whether an object may be left out: Nothing lets the budget drop it; Cheapest draws every object at
    // least at its cheapest option, even when those alone overrun the budget. CheapestFirst drops last:
    // when every object's cheapest option fits, as Cheapest; else no upgrade at all, and only cheapest
    // options are bought, the most benefit per cost first, so that no object is left out while another is
    // drawn finer than its cheapest. An object's `keep` overrides the floor for it.
    enum class Floor { Nothing, Cheapest, CheapestFirst };
    struct Selection {
        std::vector<int> level;  // per object: the index of the chosen option, or -1 for nothing
        double costMs = 0.0;     // the chosen costs, summed as chosen; <= the budget unless the floor overran it
                                 // or an Overrun took more
        double benefit = 0.0;    // the chosen benefits, without the hysteresis bonus
        double score = 0.0;      // the chosen benefits with it: what the choice weighs, never less for more budget
        // The best benefit per ms of the steps the budget left out (0: none left out): what a ms was worth at
        // the budget's edge this frame (an Overrun may have bought them past it).
        double leftRatio = 0.0;
        bool fit = true;  // the budget's choice (before any Overrun) kept within it: the floor did not overrun
    };
    // Past the budget: upgrades worth at least minRatio benefit per ms are still bought, the best first, up
    // to maxMs over the budget; an object left out stays out. A frame whose cheapest options alone overrun is late
    // anyway, and the upgrade it needs most (the wall in front of the eye) costs little against what it shows; at the
    // price a ms had in frames that fit (times a margin), it is worth the overrun.
    // They are bought in the budget's own pass, at their place in the ratio order, so that a cheaper upgrade
    // never takes the budget an upgrade worth the overrun would then take past it. Once an object worth minRatio
    // is left out (Floor::Nothing), nothing more is bought past the budget: nothing worth less than what the
    // budget left out, and the overrun's room does not grow when the budget shrinks.
    struct Overrun {
        double minRatio = 0.0;
        double maxMs = 0.0;  // 0: none
    };

    // Chooses the options for this frame. The option chosen last frame ranks as if its benefit were
    // (1 + hysteresis) times larger, so two near-equal choices do not swap every frame. An upgrade that
    // does not fit the remaining budget is skipped, its object's later ones with it, and upgrades of other
    // objects after it still considered; the score never falls as the budget grows (above). The
    // result stays valid until the next call. Throws std::invalid_argument naming the value: a cost,
    // benefit or budget negative or not finite, hysteresis negative or not finite, `last` not an option,
    // a negative count or missing options, an overrun's minRatio or maxMs negative or not finite.
    const Selection& select(const std::vector<Object>& objects, double budgetMs, double hysteresis, Floor floor,
                            const Overrun& overrun);
    const Selection& select(const std::vector<Object>& objects, double budgetMs, double hysteresis,
                            Floor floor = Floor::Nothing) {
        return select(objects, budgetMs, hysteresis, floor, Overrun{});
    }
    const Selection& selection() const { return sel_; }

private:
    // One step up an object's hull: from the previous hull point to `option`.
    struct Step {
        int object;
        int option;
        int prev;           // the option it steps up from (-1: nothing)
        std::uint32_t key;  // descending benefit per cost as an ascending integer (31 bits)
        double dCost;
        double ratio;  // benefit per cost, in full: the greedy's order (the key sorts most of it)
    };
    static constexpr int kBucketShift = 19;  // histogram buckets: the key's top 12 bits
    static constexpr std::size_t kBuckets = std::size_t(1) << (31 - kBucketShift);
    static constexpr std::uint32_t kNoStep = ~0u;
    struct Candidate {
        double cost, rank;
        int option;
    };
    Candidate* rankOptions(const Object& obj, long at, double hysteresis);
    void addSteps(const Object& obj, std::size_t o, double hysteresis, bool floored, bool onlyCheapest);
    std::size_t takeWholeBuckets(std::size_t& cutCount);
    std::size_t candidatesAfter(std::size_t cut);
    const std::uint64_t* sortExact(std::size_t count);
    void greedy(std::size_t count);
    // The greedy's order: the better ratio first, then the earlier step (an object's steps in hull order).
    bool before(std::uint32_t a, std::uint32_t b) const {
        return steps_[a].ratio > steps_[b].ratio || (steps_[a].ratio == steps_[b].ratio && a < b);
    }
    // Whether a step may be bought past the budget (an upgrade of what is drawn, worth the overrun).
    bool pastBudget(const Step& st) const { return overrun_ && st.prev >= 0 && st.ratio >= minRatio_; }
    // Whether leaving it out closes the overrun (an object worth the overrun left out).
    bool closes(const Step& st) const { return overrun_ && st.prev < 0 && st.ratio >= minRatio_; }

    Selection sel_;
    std::vector<Candidate> cand_;
    std::vector<Step> steps_;
    std::size_t nSteps_ = 0;
    std::vector<std::uint64_t> order_, scratch_;  // ratio key (high 32 bits) and step index
    std::array<double, kBuckets> bucketCost_{};   // summed step costs per ratio bucket
    std::vector<char> stuck_;                     // an upgrade of this object did not fit
    // The greedy's state during select().
    double spent_ = 0.0, budget_ = 0.0;
    double overLimit_ = 0.0;  // the overrun's limit: past the budget, or where the floor ended, by maxMs
    double minRatio_ = 0.0;
    bool overrun_ = false, closed_ = false;
    std::uint32_t closeAt_ = kNoStep;  // a left-out step past which the overrun is closed
    double left_ = 0.0;                // the best ratio of the steps that did not fit the budget
};

}  // namespace sg
