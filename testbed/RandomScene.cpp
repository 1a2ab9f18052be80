#include "testbed/RandomScene.h"

#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

#include <vector>

namespace scenes {

using namespace sg;

namespace {
struct Maker {
    Rng& rng;
    std::vector<ref_ptr<Material>> mats;
    std::vector<ref_ptr<Mesh>> meshes;
    ref_ptr<Node> proto;

    ref_ptr<Material> mat() { return mats[size_t(rng.below(int(mats.size())))]; }
    ref_ptr<Geometry> box() { return make<Geometry>(meshes[size_t(rng.below(int(meshes.size())))], mat()); }

    dmat4 randomMatrix(double spread, bool scale) {
        dmat4 m = glm::translate(dmat4(1.0), dvec3(rng.uniform(-spread, spread), rng.uniform(-spread, spread),
                                                   rng.uniform(-spread, spread)));
        const dvec3 axis = glm::normalize(dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.1, 1)));
        m = glm::rotate(m, rng.uniform(0, 6.283), axis);
        if (scale) m = glm::scale(m, dvec3(rng.uniform(0.3, 3), rng.uniform(0.3, 3), rng.uniform(0.3, 3)));
        return m;
    }

    ref_ptr<Node> object(int depth) {
        switch (depth > 2 ? 0 : rng.below(7)) {
            case 0: return box();
            case 1: {
                auto t = make<Transform>(randomMatrix(4.0, true));
                t->addChild(object(depth + 1));
                if (rng.chance(0.5)) t->addChild(object(depth + 1));
                return t;
            }
            case 2: {
                auto lod = make<LOD>();
                lod->setCenter(dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 0));
                const float split = float(rng.uniform(10, 80));
                lod->addChild(object(depth + 1), 0.0f, split);
                lod->addChild(box(), split, 1e5f);
                return lod;
            }
            case 3: {
                auto sw = make<Switch>();
                for (int k = 0; k < 3; ++k) sw->addChild(object(depth + 1), rng.chance(0.5));
                return sw;
            }
            case 4: {
                auto bb = make<Billboard>();
                if (rng.chance(0.5)) bb->setMode(Billboard::Mode::PointEye);
                auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(rng.uniform(-1, 1), 0, rng.uniform(0, 2))));
                t->addChild(make<Geometry>(makeBoxMesh(dvec3(-1.5, -0.05, 0), dvec3(1.5, 0.05, 4)), mat()));
                bb->addChild(t);
                return bb;
            }
            case 5: return make<Instance>(proto, randomMatrix(4.0, rng.chance(0.5)));
            default: {
                auto g = make<BspGroup>();
                for (int k = 0; k < 4; ++k) {
                    auto t =
                        make<Transform>(glm::translate(dmat4(1.0), dvec3(rng.uniform(-8, 8), rng.uniform(-8, 8), 0)));
                    t->addChild(box());
                    g->addChild(t);
                }
                return g;
            }
        }
    }
};
}  // namespace

ref_ptr<Group> buildRandomScene(uint64_t seed, const RandomSceneOptions& opt) {
    Rng rng(seed);
    Maker mk{rng, {}, {}, {}};
    for (int k = 0; k < 8; ++k)
        mk.mats.push_back(make<Material>(
            vec4(float(rng.uniform(0.2, 1)), float(rng.uniform(0.2, 1)), float(rng.uniform(0.2, 1)), 1.0f)));
    for (int k = 0; k < 6; ++k) {
        const dvec3 h(rng.uniform(0.2, 3), rng.uniform(0.2, 3), rng.uniform(0.2, 3));
        mk.meshes.push_back(makeBoxMesh(-h, h, 1 + rng.below(3)));
    }
    auto protoGroup = make<Group>();
    for (int k = 0; k < 3; ++k) {
        auto t = make<Transform>(mk.randomMatrix(3.0, true));
        t->addChild(mk.box());
        protoGroup->addChild(t);
    }
    mk.proto = protoGroup;
    auto root = make<Group>();
    auto top = make<Transform>(glm::translate(dmat4(1.0), opt.offset));
    root->addChild(top);
    for (int k = 0; k < opt.objects; ++k) {
        auto t = make<Transform>(mk.randomMatrix(opt.spread, rng.chance(0.3)));
        t->addChild(mk.object(0));
        top->addChild(t);
    }
    return root;
}

Camera randomCamera(Rng& rng, const Box& b, int k, int width, int height) {
    const auto kind = ViewKind(k % int(ViewKind::Count));
    const dvec3 c = b.center(), e = b.halfExtent();
    auto inside = [&](double s) {
        return c + dvec3(rng.uniform(-s, s) * e.x, rng.uniform(-s, s) * e.y, rng.uniform(-s, s) * e.z);
    };
    dvec3 eye = inside(1.3), target = inside(0.8), up(0, 0, 1);
    double fov = rng.uniform(30, 100), zn = rng.uniform(0.05, 2), zf = glm::length(e) * rng.uniform(1.0, 4.0) + 10;
    switch (kind) {
        case ViewKind::General: break;
        case ViewKind::InsideObject:
            eye = inside(0.5);
            zn = rng.uniform(0.01, 0.3);
            break;
        case ViewKind::StraightDown:
            eye = dvec3(c.x + rng.uniform(-e.x, e.x), c.y + rng.uniform(-e.y, e.y), b.max.z + rng.uniform(1, 80));
            target = eye - dvec3(0, 0, 1);
            up = dvec3(0, 1, 0);
            break;
        case ViewKind::NearCutting:
            zn = rng.uniform(2, 12);
            eye = inside(0.7);
            break;
        case ViewKind::VeryWide: fov = rng.uniform(150, 175); break;
        case ViewKind::VeryNarrow:
            fov = rng.uniform(0.3, 2.5);
            eye = inside(2.0);
            target = inside(0.3);
            break;
        default: break;
    }
    if (glm::length(target - eye) < 1e-3) target = eye + dvec3(1, 0.3, -0.2);
    if (glm::length(glm::cross(glm::normalize(target - eye), up)) < 1e-6) up = dvec3(0, 1, 0);
    Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(fov, double(width) / height, zn, std::max(zf, zn * 10));
    cam.setLookAt(eye, target, up);
    return cam;
}

}  // namespace scenes
