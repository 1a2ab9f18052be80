// LodHistory: what each LOD entry of an image showed last frame, which LOD hysteresis and the LOD budget favour so
// that levels do not flicker, and whether it was seen at all before: an LOD that appears where it showed nothing
// is a change a viewer sees; one met for the first time is not.
#pragma once
#include "sg/scene/FlatImage.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace sg {

class LodHistory {
public:
    static constexpr uint8_t kNone = 0xff;  // no child
    // A child index as recorded: children past kMaxChild as kMaxChild (an LOD of so many levels keeps its
    // hysteresis approximately); the two values above it mean none shown and not seen.
    static constexpr uint8_t kMaxChild = 253;
    static uint8_t child(int k) { return k < 0 ? kNone : uint8_t(std::min(k, int(kMaxChild))); }

    // An entry's record is one byte, kept by LodHistory for its image's entries and by its users for others
    // (an Instance prototype's LODs, placement by placement): the child shown last frame (0..kMaxChild), none shown
    // (kNothing) or not seen yet (kUnseen).
    static constexpr uint8_t kUnseen = 0xff;
    // The child shown last frame, kNone: none (or not seen yet).
    static uint8_t shown(uint8_t record) { return record <= kMaxChild ? record : kNone; }
    // The record after a frame that showed `child` (kNone: none).
    static uint8_t next(uint8_t child) { return child == kNone ? kNothing : std::min(child, kMaxChild); }
    // Whether showing `child` is a change a viewer sees: the entry was seen before and showed another child or none.
    static bool changes(uint8_t record, uint8_t child) { return record != kUnseen && record != next(child); }

    // Keeps what was recorded when `img` and its structure version are those of the last call; otherwise
    // (another image, entries added or removed) every entry starts again unseen.
    void track(const FlatImage& img, uint64_t structureVersion);

    // Entry i's record. Valid for entries of the tracked image.
    uint8_t record(uint32_t i) const { return record_[i]; }
    // Entry i's child shown last frame, kNone: none.
    uint8_t last(uint32_t i) const { return shown(record_[i]); }
    // Records the child entry i shows this frame (kNone: none); returns whether that is a change (changes()).
    bool show(uint32_t i, uint8_t child) {
        const bool changed = changes(record_[i], child);
        record_[i] = next(child);
        return changed;
    }

private:
    static constexpr uint8_t kNothing = 0xfe;
    std::vector<uint8_t> record_;
    const FlatImage* image_ = nullptr;
    uint64_t version_ = 0;
};

}  // namespace sg
