// LodHistory: the child each LOD entry of an image showed last frame, which LOD hysteresis and the LOD
// budget favour so that levels do not flicker.
#pragma once
#include "sg/scene/FlatImage.h"

#include <cstdint>
#include <vector>

namespace sg {

class LodHistory {
public:
    static constexpr uint8_t kNone = 0xff;  // nothing shown (or not seen yet)

    // Keeps what was recorded when `img` and its structure version are those of the last call; otherwise
    // (another image, entries added or removed) every entry starts again at kNone.
    void track(const FlatImage& img, uint64_t structureVersion);

    // Entry i's child last shown, kNone: none. Valid for entries of the tracked image.
    uint8_t last(uint32_t i) const { return last_[i]; }
    // Records the child entry i shows this frame (children past 254 are recorded as 254), or kNone.
    void show(uint32_t i, uint8_t child) { last_[i] = child; }
    static uint8_t child(int k) { return k < 0 ? kNone : uint8_t(k < 254 ? k : 254); }

private:
    std::vector<uint8_t> last_;
    const FlatImage* image_ = nullptr;
    uint64_t version_ = 0;
};

}  // namespace sg
