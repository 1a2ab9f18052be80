#include "testbed/FactoryWalk.h"

#include "sg/intersect/IntersectTraversal.h"
#include "sg/intersect/ViewpointCollider.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace scenes {

using sg::dvec3;

namespace {
double smooth(double s) {
    s = std::clamp(s, 0.0, 1.0);
    return s * s * (3.0 - 2.0 * s);
}
void clearCollidable(sg::Node& n) { n.setNodeMask(n.nodeMask() & ~sg::kCollidable); }

// A leg of the script: a share of the frames, the wanted eye position at s in [0, 1], walking or flying,
// and for flying legs the point looked at (walking legs look where they go).
struct Leg {
    const char* name;
    double share;
    bool walking;
    std::function<dvec3(double)> at;
    std::function<dvec3(double)> look;
};

// Local y of the widest free aisle along the workshop's length (between pillars, machine rows and
// conveyors, as buildFactory places them: rows at -9, 0 (turned round) and 9, conveyors at -4.5 and 4.5).
double aisleY(const Factory& f, double halfDepth) {
    double lo = 1e9, hi = -1e9;
    for (const sg::vec3& p : f.machineMesh->positions()) {
        lo = std::min(lo, double(p.y));
        hi = std::max(hi, double(p.y));
    }
    const double gaps[3][2] = {{-halfDepth + 2.25, -9.0 + lo}, {-9.0 + hi, -4.95}, {-4.05, -hi}};
    double best = 0.0, width = -1.0;
    for (const auto& g : gaps)
        if (g[1] - g[0] > width) {
            width = g[1] - g[0];
            best = 0.5 * (g[0] + g[1]);
        }
    return best;
}
}  // namespace

void makeWorkshopWallsPassable(Factory& f) {
    for (const FactoryWorkshop& w : f.workshops) {
        clearCollidable(*f.buildings[size_t(w.building)].place);
        clearCollidable(*w.interiorGroup->child(0));  // the shell: floor, inner wall faces, ceiling
    }
}

WalkPath buildWalkPath(Factory& f, sg::Scene& scene, int frames) {
    if (frames < 10) throw std::invalid_argument("factory::buildWalkPath(): " + std::to_string(frames) + " frames");
    WalkPath path;
    // The southernmost, then westernmost workshop: its south side faces the main road and the open yard.
    for (size_t k = 1; k < f.workshops.size(); ++k) {
        const dvec3 c = f.buildings[size_t(f.workshops[k].building)].box.center();
        const dvec3 b = f.buildings[size_t(f.workshops[size_t(path.workshop)].building)].box.center();
        if (c.y < b.y - 1.0 || (std::abs(c.y - b.y) <= 1.0 && c.x < b.x)) path.workshop = int(k);
    }
    const sg::Box box = f.buildings[size_t(f.workshops[size_t(path.workshop)].building)].box;
    const dvec3 c = box.center();
    const double hw = 0.5 * (box.max.x - box.min.x) - 0.35, hd = 0.5 * (box.max.y - box.min.y) - 0.35;
    // In through the south door, in the middle of the wall (between the middle machine columns).
    const double xd = c.x, ya = c.y + aisleY(f, hd);
    auto ground = [&](double x, double y) { return dvec3(x, y, f.terrainHeight(x, y) + 1.7); };
    auto mix = [](const dvec3& a, const dvec3& b, double s) { return a + (b - a) * s; };
    const dvec3 A = ground(xd, box.min.y - 95.0), B = ground(xd, box.min.y - 2.0), C = ground(xd, ya);
    const dvec3 D = ground(c.x - hw + 3.0, ya), E = ground(box.max.x + 12.0, ya);
    const dvec3 O(-20.0, 20.0, 0.0);  // the yard's middle, what the circle looks at
    const double a0 = std::atan2(E.y - O.y, E.x - O.x), r0 = std::hypot(E.x - O.x, E.y - O.y);
    auto circle = [=, &f](double s) {
        const double a = a0 + 2.0 * M_PI * 0.85 * s;
        const double r = r0 + (260.0 - r0) * smooth((s - 0.05) * 4.0);
        const double x = O.x + r * std::cos(a), y = O.y + r * std::sin(a);
        return dvec3(x, y, f.terrainHeight(x, y) + 1.7 + 43.3 * smooth(8.0 * s));
    };
    const dvec3 F = circle(1.0);
    const dvec3 G(O.x + 0.6 * (F.x - O.x), O.y + 0.6 * (F.y - O.y), 300.0);
    const std::vector<Leg> legs = {
        {"approach", 0.22, true, [=](double s) { return mix(A, B, s); }, nullptr},
        {"enter", 0.08, true, [=](double s) { return mix(B, C, s); }, nullptr},
        {"machines", 0.20, true, [=](double s) { return mix(C, D, smooth(s)); }, nullptr},
        {"leave", 0.20, true, [=](double s) { return mix(D, E, s); }, nullptr},
        {"circle", 0.18, false, circle, [=](double) { return O; }},
        {"overview", 0.12, false, [=](double s) { return mix(F, G, smooth(s)); }, [=](double) { return O; }},
    };

    makeWorkshopWallsPassable(f);
    setFactoryEye(f, -1);
    scene.update();
    sg::ViewpointSettings vs;
    vs.radius = path.eyeRadius;
    sg::ViewpointCollider collider(vs);
    sg::IntersectTraversal probe;
    sg::QueryOptions opt;
    opt.traversalMask = sg::kCollidable;
    std::vector<sg::Hit> hits;
    dvec3 eye = A, dir(0.0, 1.0, 0.0);
    int inside = -1, done = 0;
    for (size_t l = 0; l < legs.size(); ++l) {
        const Leg& leg = legs[l];
        const int n = l + 1 == legs.size() ? frames - done : std::max(1, int(std::lround(leg.share * frames)));
        for (int i = 0; i < n; ++i) {
            const dvec3 want = leg.at(n > 1 ? double(i) / (n - 1) : 1.0);
            const dvec3 from = eye;
            eye = collider.move(scene, eye, want - eye);
            hits.clear();
            probe.intersectSphere(scene, eye, path.eyeRadius, opt, hits);
            for (const sg::Hit& h : hits)
                if (h.distance < path.eyeRadius) {
                    ++path.penetrations;
                    break;
                }
            const int k = factoryWorkshopAt(f, eye);
            if (k != inside) {
                setFactoryEye(f, k);
                scene.update();
                inside = k;
            }
            PathFrame p;
            p.eye = eye;
            p.workshop = k;
            p.walking = leg.walking;
            p.segment = leg.name;
            if (leg.walking) {
                // Look where the walk goes, turning smoothly (15% of the way per frame).
                dvec3 go = want - from;
                go.z = 0.0;
                if (glm::length(go) > 1e-6) dir = glm::normalize(dir + 0.15 * (glm::normalize(go) - dir));
                p.target = eye + dvec3(dir.x, dir.y, -0.06) * 10.0;
            } else {
                p.target = leg.look(double(i) / std::max(1, n - 1));
                dir = glm::normalize(dvec3(p.target.x - eye.x, p.target.y - eye.y, 0.0) + dvec3(1e-9, 0, 0));
            }
            path.insideFrames += k >= 0;
            path.frames.push_back(p);
        }
        done += n;
    }
    setFactoryEye(f, -1);
    scene.update();
    return path;
}

sg::Camera pathCamera(const PathFrame& p, int width, int height) {
    sg::Camera cam;
    cam.setViewport(width, height);
    cam.setPerspective(60.0, double(width) / height, p.walking ? 0.1 : 1.0, 3000.0);
    cam.setLookAt(p.eye, p.target, dvec3(0, 0, 1));
    return cam;
}

}  // namespace scenes
