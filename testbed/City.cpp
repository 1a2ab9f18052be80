#include "testbed/City.h"

#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/core/PropertyTableBuilder.h"

#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace scenes {

using namespace sg;

uint32_t cityHeight(uint32_t i, uint32_t j) { return 10u + ((i * 73856093u) ^ (j * 19349663u)) % 51u; }

uint64_t cityNodeCount(int n) {
    const uint64_t tiles = uint64_t((n + 7) / 8) * uint64_t((n + 7) / 8);
    return 7ull * uint64_t(n) * uint64_t(n) + tiles + 1;
}

CityBuilding cityBuilding(int n, uint32_t i, uint32_t j) {
    CityBuilding b;
    b.id = i * uint32_t(n) + j;
    b.height = double(cityHeight(i, j));
    b.floors = uint16_t(cityHeight(i, j) / 3u);
    b.use = kCityUses[(((i * 2654435761u) ^ (j * 40503u)) >> 13) & 3u];
    return b;
}

namespace {

// One row per building, i-major: the set's index of building (i, j) is its id.
ref_ptr<MeshFeatures> buildingFeatures(int n) {
    PropertyTableBuilder b("building", "buildings");
    b.addScalar("id", ComponentType::UInt32);
    b.addScalar("height", ComponentType::Float64);
    b.addScalar("floors", ComponentType::UInt16);
    b.addEnum("use", "use", {std::begin(kCityUses), std::end(kCityUses)});
    for (uint32_t i = 0; i < uint32_t(n); ++i)
        for (uint32_t j = 0; j < uint32_t(n); ++j) {
            const CityBuilding c = cityBuilding(n, i, j);
            b.addRow({PropertyValue::ofUInt(c.id), PropertyValue::ofNumber(c.height), PropertyValue::ofUInt(c.floors),
                      PropertyValue::ofString(c.use)});
        }
    auto store = make<PropertyStore>();
    const int table = b.finish(*store);
    return rowFeatures(store, table, "building");
}

}  // namespace

ref_ptr<Group> buildCity(const CityOptions& opt) {
    const int n = opt.n;
    if (opt.features && (n < 1 || n > 65535))
        throw std::invalid_argument("buildCity(): features want 1 to 65535 cells a side (32-bit ids), not " +
                                    std::to_string(n));
    const ref_ptr<MeshFeatures> features = opt.features ? buildingFeatures(n) : nullptr;
    std::vector<ref_ptr<Mesh>> detailed(61), coarse(61);
    for (int h = 10; h <= 60; ++h) {
        detailed[size_t(h)] = makeBoxMesh(dvec3(-6, -6, 0), dvec3(6, 6, h), 10);
        coarse[size_t(h)] = makeBoxMesh(dvec3(-6, -6, 0), dvec3(6, 6, h), 1);
    }
    const ref_ptr<Mesh> car = makeBoxMesh(dvec3(0, 0, 0), dvec3(4, 2, 1.5), 1);
    const auto buildingMat = make<Material>(vec4(0.72f, 0.70f, 0.66f, 1.0f));
    const auto carMat = make<Material>(vec4(0.8f, 0.15f, 0.1f, 1.0f));

    auto root = make<Group>();
    root->setName("city");
    for (int ti = 0; ti < n; ti += 8)
        for (int tj = 0; tj < n; tj += 8) {
            auto tile = make<Group>();
            for (int i = ti; i < std::min(ti + 8, n); ++i)
                for (int j = tj; j < std::min(tj + 8, n); ++j) {
                    const uint32_t h = cityHeight(uint32_t(i), uint32_t(j));
                    auto cell = make<Group>();
                    auto place = make<Transform>();
                    place->setTranslation(dvec3(20.0 * i + 10, 20.0 * j + 10, 0));
                    if (features) place->setFeatures(features, uint32_t(i) * uint32_t(n) + uint32_t(j));
                    auto lod = make<LOD>();
                    lod->setCenter(dvec3(0, 0, h / 2.0));
                    lod->addChild(make<Geometry>(detailed[h], buildingMat), 0.0f, 250.0f);
                    lod->addChild(make<Geometry>(coarse[h], buildingMat), 250.0f, 2500.0f);
                    place->addChild(lod);
                    if (opt.occluders) {
                        auto occ = make<Occluder>();
                        occ->setBox(Box{dvec3(-6, -6, 0), dvec3(6, 6, h)});
                        place->addChild(occ);
                    }
                    auto carPlace = make<Transform>();
                    carPlace->setTranslation(dvec3(20.0 * i + 1, 20.0 * j + 1, 0));
                    carPlace->addChild(make<Geometry>(car, carMat));
                    cell->addChild(place);
                    cell->addChild(carPlace);
                    tile->addChild(cell);
                }
            root->addChild(tile);
        }
    return root;
}

Camera cityOrbitCamera(int n, int f, int width, int height) {
    const double a = 2.0 * M_PI * f / 120.0;
    const dvec3 c(10.0 * n, 10.0 * n, 0.0);
    const dvec3 eye = c + dvec3(5.0 * n * std::cos(a), 5.0 * n * std::sin(a), 40.0);
    const dvec3 d = glm::normalize(dvec3(-std::sin(a), std::cos(a), -0.15));
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, 1280.0 / 720.0, 1.0, 3000.0);
    cam.setLookAt(eye, eye + d, dvec3(0, 0, 1));
    return cam;
}

Camera cityStreetCamera(int n, int f, int width, int height) {
    const dvec3 eye(20.0 * std::floor(n / 2.0), 20.0 * n * f / 239.0, 1.7);
    const double t = 0.5 * std::sin(2.0 * M_PI * f / 60.0);
    const dvec3 d(std::sin(t), std::cos(t), 0.0);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, 1280.0 / 720.0, 0.5, 3000.0);
    cam.setLookAt(eye, eye + d, dvec3(0, 0, 1));
    return cam;
}

}  // namespace scenes
