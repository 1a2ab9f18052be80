// LodSelector: the time-budgeted choice of detail levels of Funkhouser and Sequin's adaptive display (1993).
// Every visible object offers its levels as (predicted draw cost, benefit) options, plus drawing nothing;
// select() picks one option per object so that the total cost fits a frame budget and the total benefit is
// high. It is greedy by benefit per cost over each object's upper convex hull of options: the hull makes an
// object's upgrades ever less worth their cost, so taking upgrades best-ratio-first is the classic
// near-optimal answer to this multiple-choice knapsack at a cost linear in the options, where the exact
// answer is a search.
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
        // The best benefit per ms of the steps the budget left out (0: none left out): what a ms was worth at
        // the budget's edge this frame, before any Overrun.
        double leftRatio = 0.0;
        bool fit = true;  // the budget's choice (before any Overrun) kept within it: the floor did not overrun
    };
    // Past the budget: upgrades worth at least minRatio benefit per ms are still bought, the best first, up
    // to maxMs over the budget; an object left out stays out. A frame whose cheapest options alone overrun is late
    // anyway, and the upgrade it needs most (the wall in front of the eye) costs little against what it shows; at the
    // price a ms had in frames that fit (times a margin), it is worth the overrun.
    struct Overrun {
        double minRatio = 0.0;
        double maxMs = 0.0;  // 0: none
    };

    // Chooses the options for this frame. The option chosen last frame ranks as if its benefit were
    // (1 + hysteresis) times larger, so two near-equal choices do not swap every frame. An upgrade that
    // does not fit the remaining budget is skipped and cheaper ones after it still considered. The
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
    };
    static constexpr int kBucketShift = 19;  // histogram buckets: the key's top 12 bits
    static constexpr std::size_t kBuckets = std::size_t(1) << (31 - kBucketShift);
    struct Candidate {
        double cost, rank;
        int option;
    };
    Selection sel_;
    std::vector<Candidate> cand_;
    std::vector<Step> steps_;
    std::vector<std::uint64_t> order_, scratch_;  // ratio key (high 32 bits) and step index
    std::array<double, kBuckets> bucketCost_{};   // summed step costs per ratio bucket
    std::vector<char> stuck_;                     // an upgrade of this object did not fit
};

}  // namespace sg
