#include "sg/cull/LodHistory.h"

namespace sg {

void LodHistory::track(const FlatImage& img, uint64_t structureVersion) {
    if (image_ == &img && version_ == structureVersion && last_.size() == img.size()) return;
    last_.assign(img.size(), kNone);
    image_ = &img;
    version_ = structureVersion;
}

}  // namespace sg
