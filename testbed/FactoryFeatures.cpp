// The factory's buildings and machines as features (docs/scenes.md): one property store with a table of class
// `building` and one of class `machine`, bound to the nodes that place them, so that a pick names what it struck.
#include "testbed/FactoryBuild.h"

#include "nodes/Instance.h"
#include "sg/core/PropertyTableBuilder.h"

#include <cstdio>
#include <string>

namespace scenes {

std::string factoryMachineName(int workshop, int k) {
    char s[32];
    std::snprintf(s, sizeof s, "machine %d.%02d", workshop + 1, k + 1);
    return s;
}

namespace factory {
namespace {

// "workshop 2" where several buildings share a kind, "office" where one has it.
std::string buildingName(const std::vector<BuildingSpec>& specs, size_t b) {
    int same = 0, before = 0;
    for (size_t i = 0; i < specs.size(); ++i)
        if (std::string(specs[i].kind) == specs[b].kind) {
            ++same;
            if (i < b) ++before;
        }
    return same > 1 ? std::string(specs[b].kind) + " " + std::to_string(before + 1) : std::string(specs[b].kind);
}

ref_ptr<MeshFeatures> buildingFeatures(const ref_ptr<PropertyStore>& store) {
    PropertyTableBuilder t("building", "buildings");
    t.addString("name");
    t.addString("kind");
    const std::vector<BuildingSpec>& specs = buildingSpecs();
    for (size_t b = 0; b < specs.size(); ++b)
        t.addRow({PropertyValue::ofString(buildingName(specs, b)), PropertyValue::ofString(specs[b].kind)});
    return rowFeatures(store, t.finish(*store), "building");
}

}  // namespace

// Buildings by their rows in buildingSpecs(); a workshop's interior is its building too, so that a pick on a
// machine names the machine and then its workshop. Machines in workshop order, then as placed.
void addFeatures(FactorySite& site) {
    Factory& f = site.f;
    auto store = make<PropertyStore>();
    f.buildingFeatures = buildingFeatures(store);
    for (size_t b = 0; b < f.buildings.size(); ++b) f.buildings[b].place->setFeatures(f.buildingFeatures, uint32_t(b));

    PropertyTableBuilder t("machine", "machines");
    t.addString("name");
    t.addString("kind");
    t.addScalar("line", ComponentType::UInt16);
    const int n = site.prm.machinesPerWorkshop, perRow = (n + 2) / 3;
    std::vector<std::pair<Instance*, uint32_t>> machines;
    for (size_t w = 0; w < f.workshops.size(); ++w) {
        const FactoryWorkshop& ws = f.workshops[w];
        ws.interiorGroup->setFeatures(f.buildingFeatures, uint32_t(ws.building));
        int k = 0;
        for (size_t i = 0; i < ws.interiorGroup->numChildren(); ++i) {
            Node* c = ws.interiorGroup->child(i);
            if (c->kind() != NodeKind::Instance) continue;
            // Three production lines a workshop, one a row of machines: workshop 1 holds lines 1 to 3.
            const int line = int(w) * 3 + k / perRow + 1;
            t.addRow({PropertyValue::ofString(factoryMachineName(int(w), k)),
                      PropertyValue::ofString("making and packing"), PropertyValue::ofUInt(uint64_t(line))});
            machines.emplace_back(static_cast<Instance*>(c), uint32_t(machines.size()));
            ++k;
        }
    }
    f.machineFeatures = rowFeatures(store, t.finish(*store), "machine");
    for (auto& [instance, row] : machines) instance->setFeatures(f.machineFeatures, row);
}

}  // namespace factory
}  // namespace scenes
