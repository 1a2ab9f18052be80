#include "map/RegionFeatures.h"

#include "sg/core/PropertyTableBuilder.h"

namespace sgmap {

void bindRegionFeatures(Level& level) {
    sg::PropertyTableBuilder t("region", level.name + " regions");
    t.addString("name");
    t.addString("code");
    t.addString("kind");
    t.addScalar("area", sg::ComponentType::Float64);
    for (const Region& r : level.regions)
        t.addRow({sg::PropertyValue::ofString(r.name), sg::PropertyValue::ofString(r.id),
                  sg::PropertyValue::ofString(r.kind), sg::PropertyValue::ofNumber(r.areaKm2)});
    auto store = sg::make<sg::PropertyStore>();
    level.features = sg::rowFeatures(store, t.finish(*store), "region");
    for (size_t i = 0; i < level.regions.size(); ++i) level.regions[i].node->setFeatures(level.features, uint32_t(i));
}

}  // namespace sgmap
