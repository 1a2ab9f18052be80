// The regions of a map level as features: their file's properties (id, name, kind, area) as a property table of
// class `region`, each region's node bound to its row, so that a pick on the map names the region through the same
// API that files' features use (sg::featuresAt).
#pragma once
#include "map/Atlas.h"

namespace sgmap {

// Row i is level.regions[i]: `name` and `code` (the region's id) STRING, `kind` STRING, `area` FLOAT64 in km².
// Binds each Region::node (Node::setFeatures) and keeps the set in Level::features.
void bindRegionFeatures(Level& level);

}  // namespace sgmap
