// Builds a BspGroup's tree over its children's boxes (in the group's frame): axis-aligned splits at
// the median centre, children that straddle a plane stay on it.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "nodes/BspGroup.h"

#include <vector>

namespace sg {

void buildBsp(BspGroup& group, const std::vector<Box>& childBoxes);

}  // namespace sg
