// LodHistory: what each LOD entry of an image showed last frame, which LOD hysteresis and the LOD budget favour so
// that levels do not flicker, and the child it showed when it last showed one. The budget favours that child even
// after a frame that left the LOD out: else a budget that shrinks for a frame and grows back puts back other LODs
// than those it left out (each ranks as it did before it was favoured), and a still view twinkles.
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
    // hysteresis approximately).
    static constexpr uint8_t kMaxChild = 125;
    static uint8_t child(int k) { return k < 0 ? kNone : uint8_t(std::min(k, int(kMaxChild))); }

    // An entry's record is one byte, kept by LodHistory for its image's entries and by its users for others
    // (an Instance prototype's LODs, placement by placement): a child shown last frame (0..kMaxChild), none shown
    // with the child shown before (0x80 | child), none shown and none ever (0xfe), or not seen yet (kUnseen).
    static constexpr uint8_t kUnseen = 0xff;
    // The child shown last frame, kNone: none (or not seen yet).
    static uint8_t shown(uint8_t record) { return record <= kMaxChild ? record : kNone; }
    // The child shown when one last was, through the frames since that showed none; kNone: never.
    static uint8_t drawn(uint8_t record) {
        return record <= kMaxChild ? record : record < kNever ? uint8_t(record & 0x7f) : kNone;
    }
    // The record after a frame that showed `child` (kNone: none).
    static uint8_t next(uint8_t record, uint8_t child) {
        if (child != kNone) return std::min(child, kMaxChild);
        if (record <= kMaxChild) return uint8_t(0x80 | record);
        return record == kUnseen ? kNever : record;
    }
    // Whether showing `child` is a change a viewer sees: the entry was seen before and showed another child or none.
    static bool changes(uint8_t record, uint8_t child) {
        return record != kUnseen && shown(record) != (child == kNone ? kNone : std::min(child, kMaxChild));
    }

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
        record_[i] = next(record_[i], child);
        return changed;
    }

private:
    static constexpr uint8_t kNever = 0xfe;
    std::vector<uint8_t> record_;
    const FlatImage* image_ = nullptr;
    uint64_t version_ = 0;
};

}  // namespace sg
