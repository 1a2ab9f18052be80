// Helpers shared by the tests: walk the graph as the cull should see it, collect world vertices.
#pragma once
#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/core/Camera.h"
#include "sg/cull/CullSettings.h"
#include "sg/lod/DrawCostModel.h"

#include <functional>

namespace testutil {

using namespace sg;

// A 400x300 view from the origin along +y, z up (60 degrees, near 0.5).
inline Camera lookingAlongY(double zFar = 1000.0) {
    Camera cam;
    cam.setViewport(400, 300);
    cam.setPerspective(60.0, 4.0 / 3.0, 0.5, zFar);
    cam.setLookAt(dvec3(0, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1));
    return cam;
}

// A cost model that knows its machine: 1 ms per frame plus 10 ms per 100,000 triangles, items free.
inline DrawCostModel trainedCostModel() {
    DrawCostModel m;
    for (int f = 0; f < 200; ++f) {
        const double tris = 1000.0 * (f % 50 + 1), items = double((f * 7) % 40);
        m.update({tris, items, 0.0}, 1.0 + 10.0 * tris / 1e5);
    }
    return m;
}

// The time budget alone, without the bounds and the overrun the library's defaults put around it (each tested
// apart): what the planner buys with the budget and nothing else.
inline LodBudgetSettings plainBudget(const DrawCostModel* model, double budgetMs = 33.3) {
    LodBudgetSettings b;
    b.enabled = true;
    b.model = model;
    b.budgetMs = budgetMs;
    b.mayDrop = false;
    b.coarsestScale = 0.0;
    b.finestScale = 0.0;
    b.overrunShare = 0.0;
    b.keepOver = b.keepUnder = 0.0;  // a plan anew every frame: the deadband is tested on its own
    return b;
}

// Calls f(geometry, world matrix) for every geometry the LOD and Switch selection shows from `cam`
// (no frustum tests): the reference set a cull may only shrink.
inline void forEachActive(Node* n, const dmat4& m, const Camera& cam,
                          const std::function<void(Geometry*, const dmat4&)>& f) {
    switch (n->kind()) {
        case NodeKind::Geometry: f(static_cast<Geometry*>(n), m); return;
        case NodeKind::Transform: {
            const dmat4 mm = static_cast<Transform*>(n)->apply(m);
            for (size_t i = 0; i < n->numChildren(); ++i) forEachActive(n->child(i), mm, cam, f);
            return;
        }
        case NodeKind::Instance: {
            auto* in = static_cast<Instance*>(n);
            if (in->prototype()) forEachActive(in->prototype(), m * in->matrix(), cam, f);
            return;
        }
        case NodeKind::Switch:
            for (size_t i = 0; i < n->numChildren(); ++i)
                if (static_cast<Switch*>(n)->isOn(i)) forEachActive(n->child(i), m, cam, f);
            return;
        case NodeKind::Billboard: {
            const dvec3 eyeLocal(glm::inverse(m) * dvec4(cam.eye(), 1.0));
            const dmat4 mm = m * static_cast<Billboard*>(n)->rotationToward(eyeLocal);
            for (size_t i = 0; i < n->numChildren(); ++i) forEachActive(n->child(i), mm, cam, f);
            return;
        }
        case NodeKind::LOD: {
            auto* lod = static_cast<LOD*>(n);
            // Only user centres are compared exactly; tests that use LOD set them.
            const double d = glm::length(dvec3(m * dvec4(lod->center(), 1.0)) - cam.eye());
            for (size_t i = 0; i < n->numChildren(); ++i)
                if (d >= lod->range(i).min && d < lod->range(i).max) forEachActive(n->child(i), m, cam, f);
            return;
        }
        default:
            for (size_t i = 0; i < n->numChildren(); ++i) forEachActive(n->child(i), m, cam, f);
    }
}

// True when some vertex of the geometry lies strictly inside the frustum (by a margin).
inline bool vertexInside(const Geometry& g, const dmat4& m, const Camera& cam, double margin) {
    for (const vec3& p : g.mesh()->positions()) {
        const dvec3 w = dvec3(m * dvec4(dvec3(p), 1.0)) - cam.eye();
        bool in = true;
        for (const Plane& pl : cam.eyePlanes()) in &= pl.distance(w) > margin;
        if (in) return true;
    }
    return false;
}

}  // namespace testutil
