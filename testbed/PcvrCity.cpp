#include "testbed/PcvrCity.h"

#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "testbed/RandomScene.h"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace scenes {

using namespace sg;

namespace {

// A flat street along x, [0, length] x [-width/2, width/2] at z = 0, facing up: `along` quads by 2 across,
// in rows along its length, so that consecutive triangles are neighbours.
ref_ptr<Mesh> streetMesh(double length, double width, uint32_t along) {
    std::vector<vec3> pos, nrm;
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i <= along; ++i)
        for (int j = 0; j <= 2; ++j) {
            pos.push_back(vec3(float(length * i / along), float(width * (j - 1) / 2.0), 0.0f));
            nrm.push_back(vec3(0, 0, 1));
        }
    for (uint32_t i = 0; i < along; ++i)
        for (uint32_t j = 0; j < 2; ++j) {
            const uint32_t a = i * 3 + j, b = a + 1, c = a + 3, d = c + 1;
            idx.insert(idx.end(), {a, c, d, a, d, b});
        }
    auto m = make<Mesh>();
    m->set(std::move(pos), std::move(nrm), std::move(idx));
    return m;
}

ref_ptr<Transform> placed(const dvec3& at, double yawDeg, const ref_ptr<Node>& child) {
    auto t = make<Transform>();
    if (yawDeg != 0.0)
        t->setMatrix(glm::rotate(glm::translate(dmat4(1.0), at), glm::radians(yawDeg), dvec3(0, 0, 1)));
    else
        t->setTranslation(at);
    t->addChild(child);
    return t;
}

}  // namespace

ref_ptr<Group> buildPcvrCity(uint64_t seed) {
    Rng rng(seed);
    auto root = make<Group>();
    root->setName("pcvr-city");
    uint32_t triangles = 0;

    // Buildings: the nine blocks between the streets (0..94, 106..294, 306..400 on each axis); six blocks hold
    // two buildings side by side along x, three hold one: 15.
    const double lo[3] = {0.0, 106.0, 306.0}, hi[3] = {94.0, 294.0, 400.0};
    const bool pair[9] = {true, false, true, true, true, false, true, false, true};
    const vec4 greys[3] = {{0.72f, 0.70f, 0.66f, 1.0f}, {0.62f, 0.64f, 0.68f, 1.0f}, {0.78f, 0.74f, 0.64f, 1.0f}};
    for (int b = 0; b < 9; ++b) {
        const int bx = b % 3, by = b / 3;
        const int count = pair[b] ? 2 : 1;
        const double w = (hi[bx] - lo[bx]) / count;
        for (int k = 0; k < count; ++k) {
            const double x0 = lo[bx] + w * k + 6.0, x1 = lo[bx] + w * (k + 1) - 6.0;
            const double y0 = lo[by] + 6.0, y1 = hi[by] - 6.0;
            const double h = 10.0 + 5.0 * rng.below(11);
            const int div = 7 + rng.below(5);  // 588 to 1,452 triangles
            const ref_ptr<Mesh> mesh = makeBoxMesh(dvec3(0, 0, 0), dvec3(x1 - x0, y1 - y0, h), div);
            triangles += mesh->triangleCount();
            root->addChild(placed(dvec3(x0, y0, 0), 0.0, make<Geometry>(mesh, make<Material>(greys[rng.below(3)]))));
        }
    }
    // Cars: 48 triangles each, on the streets, along them.
    const ref_ptr<Mesh> car = makeBoxMesh(dvec3(-2, -1, 0), dvec3(2, 1, 1.5), 2);
    const auto carMat = make<Material>(vec4(0.8f, 0.15f, 0.1f, 1.0f));
    for (int c = 0; c < 6; ++c) {
        const bool alongX = c % 2 == 0;
        const double street = (c / 2) % 2 ? 300.0 : 100.0, at = rng.uniform(20.0, 380.0);
        const double side = rng.chance(0.5) ? 3.0 : -3.0;
        const dvec3 p = alongX ? dvec3(at, street + side, 0.0) : dvec3(street + side, at, 0.0);
        root->addChild(placed(p, alongX ? 0.0 : 90.0, make<Geometry>(car, carMat)));
        triangles += car->triangleCount();
    }
    // Streets: what is left, 4 triangles per quad row, split over the four.
    if (triangles + 16 > kPcvrTriangles || (kPcvrTriangles - triangles) % 4)
        throw std::logic_error("buildPcvrCity(): the buildings and cars leave no whole street rows");
    const uint32_t rows = (kPcvrTriangles - triangles) / 4;
    const auto streetMat = make<Material>(vec4(0.3f, 0.3f, 0.32f, 1.0f));
    for (int s = 0; s < 4; ++s) {
        const uint32_t n = s < 3 ? rows / 4 : rows - 3 * (rows / 4);
        const ref_ptr<Mesh> mesh = streetMesh(400.0, 12.0, n);
        const double c = s % 2 ? 300.0 : 100.0;
        // (streets along y are turned 90 degrees about z: their length runs from y = 0 to 400)
        const dvec3 at = s < 2 ? dvec3(0.0, c, 0.0) : dvec3(c, 0.0, 0.0);
        root->addChild(placed(at, s < 2 ? 0.0 : 90.0, make<Geometry>(mesh, streetMat)));
    }
    return root;
}

Camera pcvrCityCamera(int frame, int width, int height) {
    // Round the square (100, 100) -> (300, 100) -> (300, 300) -> (100, 300), a quarter of the frames per side.
    const int f = ((frame % kPcvrFrames) + kPcvrFrames) % kPcvrFrames;
    const int per = kPcvrFrames / 4, side = f / per;
    const double t = double(f % per) / per;
    const dvec3 corner[4] = {{100, 100, 0}, {300, 100, 0}, {300, 300, 0}, {100, 300, 0}};
    const dvec3 a = corner[side], b = corner[(side + 1) % 4];
    const dvec3 eye = a + (b - a) * t + dvec3(0, 0, 1.5);
    const double yaw = std::atan2(b.y - a.y, b.x - a.x) + 0.35 * std::sin(2.0 * M_PI * f / 40.0);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, double(width) / height, 0.5, 250.0);
    cam.setLookAt(eye, eye + dvec3(std::cos(yaw), std::sin(yaw), 0.0), dvec3(0, 0, 1));
    return cam;
}

}  // namespace scenes
