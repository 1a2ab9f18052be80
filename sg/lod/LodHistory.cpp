#include "sg/lod/LodHistory.h"

namespace sg {

void LodHistory::track(const FlatImage& img, uint64_t structureVersion) {
    if (image_ == &img && version_ == structureVersion && record_.size() == img.size()) return;
    record_.assign(img.size(), kUnseen);
    image_ = &img;
    version_ = structureVersion;
}

}  // namespace sg
