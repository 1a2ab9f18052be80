#include "testbed/Factory.h"

#include "testbed/FactoryBuild.h"

#include "nodes/Geometry.h"

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

namespace scenes {

using namespace sg;

namespace {

void fail(const std::string& what) { throw std::invalid_argument("scenes::buildFactory(): " + what); }

// Triangles under `n` with every switch on and every LOD at its finest level: each placement counted
// (drawn; an Instance's one child is its prototype), or each distinct mesh once (stored).
struct TriangleCount {
    std::set<const Mesh*> meshes;
    uint64_t drawn = 0, stored = 0;
    void walk(Node& n) {
        if (n.kind() == NodeKind::Geometry) {
            const Mesh* m = static_cast<Geometry&>(n).mesh();
            if (!m) return;
            drawn += m->triangleCount();
            if (meshes.insert(m).second) stored += m->triangleCount();
            return;
        }
        if (n.kind() == NodeKind::LOD) {
            if (n.numChildren() > 0) walk(*n.child(0));
            return;
        }
        for (size_t i = 0; i < n.numChildren(); ++i) walk(*n.child(i));
    }
};

void checkParams(const FactoryParams& prm) {
    auto finitePositive = [](double v) { return std::isfinite(v) && v > 0.0; };
    if (!finitePositive(prm.siteSize) || prm.siteSize < 600.0)
        fail("siteSize " + std::to_string(prm.siteSize) + " must be finite and at least 600 (the yard's size)");
    if (prm.terrainCells <= 0 || prm.terrainTiles <= 0 || prm.terrainCells % prm.terrainTiles != 0)
        fail("terrainCells " + std::to_string(prm.terrainCells) + " must be a positive multiple of terrainTiles " +
             std::to_string(prm.terrainTiles));
    if (prm.machinesPerWorkshop < 0 || prm.machinesPerWorkshop > 21)
        fail("machinesPerWorkshop " + std::to_string(prm.machinesPerWorkshop) + " is not in 0..21 (three rows of 7)");
    if (prm.trees < 0) fail("trees " + std::to_string(prm.trees) + " is negative");
    if (prm.cars < 0 || prm.cars > 64)
        fail("cars " + std::to_string(prm.cars) + " is not in 0..64 (the car park's bays)");
    if (!finitePositive(prm.pixelError)) fail("pixelError " + std::to_string(prm.pixelError) + " must be positive");
    if (!(prm.fadeFraction >= 0.0 && prm.fadeFraction < 1.0))
        fail("fadeFraction " + std::to_string(prm.fadeFraction) + " is not in [0, 1)");
}

}  // namespace

namespace factory {

ref_ptr<Material> texturedMaterial(ref_ptr<Texture> tex, float anisotropy, float specular, float shininess) {
    tex->maxAnisotropy = anisotropy;
    auto m = make<Material>(vec4(1.0f), std::move(tex));
    m->specular = specular;
    m->shininess = shininess;
    return m;
}

ref_ptr<Material> glossyMaterial(float specular, float shininess) {
    auto m = make<Material>(vec4(1.0f));
    m->specular = specular;
    m->shininess = shininess;
    return m;
}

}  // namespace factory

Factory buildFactory(const FactoryParams& prm) {
    checkParams(prm);
    Factory f;
    f.root = make<Group>();
    f.root->setName("factory");
    f.outside = make<Switch>();
    f.outside->setName("outside");
    auto outside = make<Group>();
    f.outside->addChild(outside, true);
    f.root->addChild(f.outside);
    auto occluders = make<Group>();
    occluders->setName("occluders");
    f.root->addChild(occluders);
    auto interiors = make<Group>();
    interiors->setName("interiors");
    f.root->addChild(interiors);

    factory::FactorySite site{
        prm, f, outside, occluders, interiors, make<Material>(vec4(1.0f)), factory::Rng(prm.seed)};
    factory::addTerrain(site);
    factory::addRoads(site);
    factory::addStream(site);
    factory::addChimney(site);
    factory::addBuildings(site);
    factory::addTrees(site);
    factory::addCars(site);
    factory::addWorkshops(site);
    factory::addFeatures(site);

    TriangleCount tc;
    tc.walk(*f.root);
    f.drawnTriangles = tc.drawn;
    f.storedTriangles = tc.stored;
    return f;
}

int factoryWorkshopAt(const Factory& f, const dvec3& eye) {
    for (size_t k = 0; k < f.workshops.size(); ++k)
        if (f.buildings[size_t(f.workshops[k].building)].box.contains(eye)) return int(k);
    return -1;
}

void setFactoryEye(Factory& f, int workshop) {
    if (workshop >= int(f.workshops.size()))
        throw std::out_of_range("scenes::setFactoryEye(): workshop " + std::to_string(workshop) + " of " +
                                std::to_string(f.workshops.size()));
    f.outside->setAll(workshop < 0);
    for (size_t k = 0; k < f.workshops.size(); ++k) f.workshops[k].interior->setAll(int(k) == workshop);
}

Camera factoryOrbitCamera(int frame, int width, int height) {
    const double a = 2.0 * M_PI * frame / kFactoryOrbitFrames;
    const dvec3 target(-20.0, 20.0, 0.0);
    const dvec3 eye = target + dvec3(300.0 * std::cos(a), 300.0 * std::sin(a), 90.0);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, double(width) / height, 1.0, 3000.0);
    cam.setLookAt(eye, target, dvec3(0, 0, 1));
    return cam;
}

Camera factoryWorkshopCamera(const Factory& f, int workshop, int width, int height) {
    const Box& b = f.buildings.at(size_t(f.workshops.at(size_t(workshop)).building)).box;
    const dvec3 eye(b.min.x + 2.0, b.center().y - 2.0, 1.7);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, double(width) / height, 0.1, 500.0);
    cam.setLookAt(eye, eye + dvec3(1.0, 0.05, -0.08), dvec3(0, 0, 1));
    return cam;
}

}  // namespace scenes
