// The factory's buildings and machines as features: a pick on a machine names the machine (name, kind, production
// line) and then its workshop; a pick on a roof names the building.
#include "nodes/Instance.h"
#include "nodes/Transform.h"
#include "sg/intersect/HitFeatures.h"
#include "sg/intersect/IntersectTraversal.h"
#include "testbed/Factory.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

// A small site: the features do not depend on the terrain, trees or cars.
scenes::Factory smallFactory() {
    scenes::FactoryParams p;
    p.terrainCells = 64;
    p.terrainTiles = 8;
    p.trees = 0;
    p.cars = 0;
    return scenes::buildFactory(p);
}

const PropertyValue* find(const PropertyList& props, const std::string& id) {
    for (const auto& p : props)
        if (p.first == id) return &p.second;
    return nullptr;
}

std::string text(const PropertyList& props, const std::string& id) {
    const PropertyValue* v = find(props, id);
    return v ? v->toString() : "(absent)";
}

}  // namespace

TEST(FactoryFeatures, APickOnAMachineNamesItAndThenItsWorkshop) {
    scenes::Factory f = smallFactory();
    scenes::setFactoryEye(f, 1);  // workshop 1's interior on, the outside off
    Scene scene(f.root);
    scene.update();
    // Machine k = 4 of workshop 1: the fifth Instance of its interior.
    const scenes::FactoryWorkshop& ws = f.workshops[1];
    const Instance* target = nullptr;
    for (size_t i = 0, k = 0; i < ws.interiorGroup->numChildren() && !target; ++i)
        if (ws.interiorGroup->child(i)->kind() == NodeKind::Instance && k++ == 4)
            target = static_cast<const Instance*>(ws.interiorGroup->child(i));
    ASSERT_NE(target, nullptr);
    // Straight down onto the centre of the machine's largest upward face (a machine is several parts: the middle
    // of its bound may be a gap), from just above the machine.
    const dmat4 world = static_cast<const Transform*>(ws.interiorGroup->parent(0))->matrix() * target->matrix();
    const Mesh& mesh = *f.machineMesh;
    dvec3 aim(0.0);
    double best = 0.0;
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const dvec3 a(mesh.positions()[mesh.index(3 * t)]), b(mesh.positions()[mesh.index(3 * t + 1)]),
            c(mesh.positions()[mesh.index(3 * t + 2)]);
        const dvec3 n = glm::cross(b - a, c - a);
        if (n.z > best) best = n.z, aim = (a + b + c) / 3.0;
    }
    ASSERT_GT(best, 0.0);
    const dvec3 top(world * dvec4(aim.x, aim.y, mesh.box().max.z + 0.3, 1.0));
    IntersectTraversal it;
    std::vector<Hit> hits;
    it.intersectAll(scene, Ray{top, dvec3(0, 0, -1)}, {}, hits);
    const Hit* onMachine = nullptr;
    for (const Hit& h : hits)
        if (h.instance == target && !onMachine) onMachine = &h;
    ASSERT_NE(onMachine, nullptr);

    const HitFeatures hf = featuresAt(*onMachine);
    ASSERT_EQ(hf.features.size(), 2u);
    const FeatureAtHit& m = hf.features[0];  // innermost first: the machine's Instance
    EXPECT_EQ(m.classId, "machine");
    EXPECT_EQ(m.featureId, 17 + 4);  // workshop 0's 17 machines come first
    EXPECT_EQ(text(m.properties, "name"), "machine 2.05");
    EXPECT_EQ(text(m.properties, "name"), scenes::factoryMachineName(1, 4));
    EXPECT_EQ(text(m.properties, "kind"), "making and packing");
    // Six machines a row: k = 4 stands in the first row, workshop 2's first line, line 4 of the site.
    ASSERT_NE(find(m.properties, "line"), nullptr);
    EXPECT_EQ(find(m.properties, "line")->asNumber(), 4.0);
    const FeatureAtHit& b = hf.features[1];
    EXPECT_EQ(b.classId, "building");
    EXPECT_EQ(b.featureId, 1);
    EXPECT_EQ(text(b.properties, "name"), "workshop 2");
    EXPECT_EQ(text(b.properties, "kind"), "workshop");
}

TEST(FactoryFeatures, APickOnTheOfficeRoofNamesTheOffice) {
    const scenes::Factory f = smallFactory();
    Scene scene(f.root);
    scene.update();
    // The office: building 10, centred at (60, 30), 21 m high.
    ASSERT_EQ(f.buildings[10].kind, "office");
    IntersectTraversal it;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(60, 30, 200), dvec3(0, 0, -1)}, {}, h));
    EXPECT_GT(h.point.z, 20.0);
    const HitFeatures hf = featuresAt(h);
    ASSERT_EQ(hf.features.size(), 1u);
    EXPECT_EQ(hf.features[0].classId, "building");
    EXPECT_EQ(hf.features[0].featureId, 10);
    EXPECT_EQ(text(hf.features[0].properties, "name"), "office");
    EXPECT_EQ(text(hf.features[0].properties, "kind"), "office");
}

TEST(FactoryFeatures, EveryBuildingAndMachineIsARowOfOneStore) {
    const scenes::Factory f = smallFactory();
    ASSERT_TRUE(f.buildingFeatures && f.machineFeatures);
    EXPECT_EQ(f.buildingFeatures->store, f.machineFeatures->store);
    EXPECT_EQ(f.buildingFeatures->store->tables().size(), 2u);
    EXPECT_EQ(f.buildingFeatures->sets[0].featureCount, f.buildings.size());
    EXPECT_EQ(f.machineFeatures->sets[0].featureCount, uint32_t(f.machines));
    for (size_t b = 0; b < f.buildings.size(); ++b) {
        EXPECT_EQ(f.buildings[b].place->features(), f.buildingFeatures.get());
        EXPECT_EQ(f.buildings[b].place->featureIndex(), b);
    }
    // Names: numbered where a kind repeats.
    const PropertyStore& store = *f.buildingFeatures->store;
    const int t = f.buildingFeatures->sets[0].propertyTable;
    EXPECT_EQ(store.value(t, 0, 0).string, "workshop 1");
    EXPECT_EQ(store.value(t, 8, 0).string, "auxiliary 5");
    EXPECT_EQ(store.value(t, 9, 0).string, "technology");
}
