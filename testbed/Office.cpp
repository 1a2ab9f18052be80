#include "testbed/Office.h"

#include "nodes/Geometry.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"

#include <cmath>
#include <map>

namespace scenes {

using namespace sg;

namespace {
// One mesh per distinct box size (furniture kinds, wall pieces), placed by its minimum corner.
struct Boxes {
    std::map<std::array<double, 3>, ref_ptr<Mesh>> meshes;
    ref_ptr<Mesh> mesh(const dvec3& size) {
        auto& m = meshes[{size.x, size.y, size.z}];
        if (!m) m = makeBoxMesh(dvec3(0.0), size);
        return m;
    }
    ref_ptr<Transform> place(const dvec3& minCorner, const dvec3& size, const ref_ptr<Material>& mat, bool occluder) {
        auto t = make<Transform>();
        t->setTranslation(minCorner);
        t->addChild(make<Geometry>(mesh(size), mat));
        if (occluder) {
            auto o = make<Occluder>();
            o->setBox(Box{dvec3(0.0), size});
            t->addChild(o);
        }
        return t;
    }
};
}  // namespace

ref_ptr<Group> buildOffice(int r, OfficeCounts* counts) {
    Boxes boxes;
    OfficeCounts n;
    const auto wallMat = make<Material>(vec4(0.85f, 0.84f, 0.8f, 1.0f));
    const auto floorMat = make<Material>(vec4(0.45f, 0.42f, 0.4f, 1.0f));
    const auto woodMat = make<Material>(vec4(0.6f, 0.45f, 0.3f, 1.0f));
    const auto darkMat = make<Material>(vec4(0.15f, 0.15f, 0.17f, 1.0f));
    const double t = 0.2, h = 3.0, doorW = 1.0, doorH = 2.2, len = 6.0;
    auto root = make<Group>();
    root->setName("office");

    // A wall on a room boundary: along x (constant y) or along y (constant x), from `from` over 6 m.
    // Inner walls have the door opening at their middle: two full-height boxes beside it and a lintel.
    auto wall = [&](Group& g, bool alongX, double fixed, double from, bool door) {
        auto box = [&](double a0, double a1, double z0, double z1) {
            const dvec3 mn = alongX ? dvec3(a0, fixed - t / 2, z0) : dvec3(fixed - t / 2, a0, z0);
            const dvec3 sz = alongX ? dvec3(a1 - a0, t, z1 - z0) : dvec3(t, a1 - a0, z1 - z0);
            g.addChild(boxes.place(mn, sz, wallMat, true));
            n.wallBoxes++;
        };
        if (!door) return box(from, from + len, 0.0, h);
        const double d0 = from + (len - doorW) / 2, d1 = d0 + doorW;
        box(from, d0, 0.0, h);
        box(d1, from + len, 0.0, h);
        box(d0, d1, doorH, h);
    };

    for (int i = 0; i < r; ++i)
        for (int j = 0; j < r; ++j) {
            auto room = make<Group>();
            const dvec3 o(len * i, len * j, 0.0);
            n.rooms++;
            room->addChild(boxes.place(o + dvec3(0, 0, -0.1), dvec3(len, len, 0.1), floorMat, false));
            // The room's west and south walls (outer ones have no door), plus east and north at the edge.
            wall(*room, false, o.x, o.y, i > 0);
            wall(*room, true, o.y, o.x, j > 0);
            if (i == r - 1) wall(*room, false, o.x + len, o.y, false);
            if (j == r - 1) wall(*room, true, o.y + len, o.x, false);

            auto furniture = [&](const dvec3& mn, const dvec3& sz, const ref_ptr<Material>& m) {
                room->addChild(boxes.place(o + mn, sz, m, false));
                n.furnitureBoxes++;
            };
            for (const dvec3& d : {dvec3(1, 1, 0), dvec3(3.4, 1, 0), dvec3(1, 4.2, 0), dvec3(3.4, 4.2, 0)}) {
                // Desk: top 1.6 x 0.8 x 0.05 at 0.72, a 0.05 leg under each corner.
                furniture(d + dvec3(0, 0, 0.72), dvec3(1.6, 0.8, 0.05), woodMat);
                for (const dvec3& leg : {dvec3(0, 0, 0), dvec3(1.55, 0, 0), dvec3(0, 0.75, 0), dvec3(1.55, 0.75, 0)})
                    furniture(d + leg, dvec3(0.05, 0.05, 0.72), woodMat);
                // Chair: 0.3 m in front (towards -y) of the desk's centre; seat at 0.45, back above the seat's
                // far edge, one post.
                const dvec3 c = d + dvec3(0.8, 0.4 - 0.3, 0.0);
                furniture(dvec3(c.x - 0.25, c.y - 0.25, 0.45), dvec3(0.5, 0.5, 0.05), darkMat);
                furniture(dvec3(c.x - 0.25, c.y - 0.25, 0.5), dvec3(0.5, 0.05, 0.5), darkMat);
                furniture(dvec3(c.x - 0.025, c.y - 0.025, 0.0), dvec3(0.05, 0.05, 0.45), darkMat);
                // Monitor on the desk's centre, on a 0.1 m foot.
                const dvec3 top = d + dvec3(0.8, 0.4, 0.77);
                furniture(top + dvec3(-0.05, -0.05, 0.0), dvec3(0.1, 0.1, 0.1), darkMat);
                furniture(top + dvec3(-0.25, -0.025, 0.1), dvec3(0.5, 0.05, 0.35), darkMat);
            }
            // Shelf with four boards inside it.
            furniture(dvec3(0.1, 0.2, 0.0), dvec3(0.4, 2.0, 2.0), woodMat);
            for (double z : {0.4, 0.8, 1.2, 1.6}) furniture(dvec3(0.1, 0.2, z), dvec3(0.4, 2.0, 0.02), woodMat);
            root->addChild(room);
        }
    if (counts) *counts = n;
    return root;
}

Camera officeWalkCamera(int r, int f, int width, int height) {
    const double y = 6.0 * std::floor(r / 2.0) + 3.0;
    const double x = 0.5 + (6.0 * r - 1.0) * f / double(kWalkFrames - 1);
    const double a = 0.6 * std::sin(2.0 * M_PI * f / 80.0);
    const dvec3 eye(x, y, 1.6);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, 1280.0 / 720.0, 0.1, 200.0);
    cam.setLookAt(eye, eye + dvec3(std::cos(a), std::sin(a), 0.0), dvec3(0, 0, 1));
    return cam;
}

}  // namespace scenes
