#include "testbed/Accuracy.h"

#include "testbed/City.h"
#include "testbed/RandomScene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace accuracy {

using namespace sg;

std::string settingName(const CullSettings& s) {
    std::string name = strategyName(s.strategy);
    if (s.smallFeaturePixels > 0) name += "+small-feature";
    if (s.screenRect && s.strategy != CullStrategy::None) name += "+screen-rect";
    if (s.strategy != CullStrategy::None && s.occlusion.mode != OcclusionMode::Off) {
        name += s.occlusion.mode == OcclusionMode::Adaptive ? "+occlusion-adaptive" : "+occlusion";
        if (s.occlusion.measureOnly.cap == OccluderCap::CenterPlane) name += "-centre";
        if (s.occlusion.method == OcclusionMethod::Hom) name += s.occlusion.homOpacity < 1.0 ? "-hom-approx" : "-hom";
        if (s.occlusion.method == OcclusionMethod::Auto) name += "-method-auto";
    }
    return name;
}

std::vector<CullSettings> conservativeSettings() {
    std::vector<CullSettings> s;
    for (auto st : {CullStrategy::Sphere, CullStrategy::Aabb, CullStrategy::SphereSphere}) {
        CullSettings c;
        c.strategy = st;
        c.occlusion.mode = OcclusionMode::Off;
        s.push_back(c);
    }
    CullSettings tree;
    tree.occlusion.mode = OcclusionMode::EveryFrame;
    tree.occlusion.method = OcclusionMethod::Tree;
    s.push_back(tree);
    CullSettings hom = tree;
    hom.occlusion.method = OcclusionMethod::Hom;
    s.push_back(hom);
    return s;
}

std::string describeCamera(const Camera& c) {
    const dvec3 e = c.eye(), d = c.viewDirection(), t = e + d;
    // The view's rows are the camera's axes: row 1 is up.
    const dmat4& v = c.view();
    const dvec3 up(v[0][1], v[1][1], v[2][1]);
    const dmat4& p = c.projection();
    char buf[512];
    if (c.perspective()) {
        // glm::perspective: p[1][1] = 1 / tan(fovy / 2), p[2][2] = -(f + n) / (f - n), p[3][2] = -2 f n / (f - n).
        const double fov = 2.0 * std::atan(1.0 / p[1][1]) * 180.0 / M_PI;
        const double zn = p[3][2] / (p[2][2] - 1.0), zf = p[3][2] / (p[2][2] + 1.0);
        std::snprintf(
            buf, sizeof buf,
            "eye (%.17g, %.17g, %.17g) target (%.17g, %.17g, %.17g) up (%.6g, %.6g, %.6g) fovy %.6g aspect %.6g "
            "near %.9g far %.9g viewport %dx%d",
            e.x, e.y, e.z, t.x, t.y, t.z, up.x, up.y, up.z, fov, p[1][1] / p[0][0], zn, zf, c.width(), c.height());
    } else {
        std::snprintf(buf, sizeof buf,
                      "orthographic: eye (%.17g, %.17g, %.17g) target (%.17g, %.17g, %.17g) viewport %dx%d", e.x, e.y,
                      e.z, t.x, t.y, t.z, c.width(), c.height());
    }
    return buf;
}

Harness::Harness(int w, int h) : w_(w), h_(h), ctx_(w, h), renderer_(std::make_unique<Renderer>()) {}

Image Harness::render(CullTraversal& cull, const Scene& scene, const Camera& view, const CullSettings& s,
                      CullStats& st) {
    st = CullStats{};
    cull.cull(scene, view, s, list_, st);
    renderer_->draw(list_, view);
    return renderer_->readColor();
}

uint64_t Harness::compare(const Scene& scene, const Camera& view, const CullSettings& s, Image* refOut, Image* gotOut,
                          CullStats* statsOut) {
    CullSettings off = s;
    off.strategy = CullStrategy::None;
    off.smallFeaturePixels = 0.0;
    CullStats st;
    const Image ref = render(refCull_, scene, view, off, st);
    const Image got = render(compareCull_, scene, view, s, st);
    const uint64_t d = countDifferingPixels(ref, got);
    if (refOut) *refOut = ref;
    if (gotOut) *gotOut = got;
    if (statsOut) *statsOut = st;
    return d;
}

std::vector<Result> Harness::run(const Scene& scene, const std::vector<Camera>& views,
                                 const std::vector<CullSettings>& settings) {
    std::vector<Result> out(settings.size());
    culls_.clear();
    for (size_t k = 0; k < settings.size(); ++k) {
        out[k].name = settingName(settings[k]);
        out[k].framePixels = double(w_) * h_;
        culls_.push_back(std::make_unique<CullTraversal>());
    }
    for (size_t v = 0; v < views.size(); ++v) {
        Camera cam = views[v];
        cam.setViewport(w_, h_);
        CullSettings off;
        off.strategy = CullStrategy::None;
        CullStats refStats;
        const Image ref = render(refCull_, scene, cam, off, refStats);
        for (size_t k = 0; k < settings.size(); ++k) {
            CullStats st;
            const uint64_t d = countDifferingPixels(ref, render(*culls_[k], scene, cam, settings[k], st));
            Result& r = out[k];
            r.views++;
            r.perView.push_back(d);
            r.differingTotal += d;
            if (d > r.differingMax) {
                r.differingMax = d;
                r.worstView = int(v);
            }
            r.viewsWithError += d > 0;
            r.culledOcclusionTotal += st.culledOcclusion;
            r.occludersUsedTotal += st.occludersUsed;
            r.viewsOcclusionRan += st.occlusionRan;
            r.viewsWithOcclusionCulls += st.culledOcclusion > 0;
            r.trianglesTotal += st.triangles;
            r.referenceTrianglesTotal += refStats.triangles;
            r.perViewCulledOcclusion.push_back(st.culledOcclusion);
        }
    }
    return out;
}

std::vector<Camera> cityViews(int n, int count, uint64_t seed, int w, int h) {
    scenes::Rng rng(seed);
    const Box city{dvec3(0, 0, 0), dvec3(20.0 * n, 20.0 * n, 60.0)};
    std::vector<Camera> views;
    for (int k = 0; k < count; ++k) {
        Camera cam = scenes::randomCamera(rng, city, k, w, h);
        switch (k % 8) {
            case 6: {  // street level, looking along a street
                const double x = 20.0 * rng.below(n), y = rng.uniform(0, 20.0 * n), t = rng.uniform(0, 6.283);
                const dvec3 eye(x, y, 1.7);
                cam.setPerspective(60, double(w) / h, 0.5, 3000);
                cam.setLookAt(eye, eye + dvec3(std::sin(t), std::cos(t), rng.uniform(-0.1, 0.3)), dvec3(0, 0, 1));
                break;
            }
            case 7: {  // inside a building
                const int i = rng.below(n), j = rng.below(n);
                const double hgt = scenes::cityHeight(uint32_t(i), uint32_t(j));
                const dvec3 eye(20.0 * i + 10 + rng.uniform(-5, 5), 20.0 * j + 10 + rng.uniform(-5, 5),
                                rng.uniform(0.5, hgt - 0.5));
                cam.setPerspective(rng.uniform(40, 120), double(w) / h, rng.uniform(0.05, 1), 3000);
                cam.setLookAt(eye, eye + dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.5, 0.5)),
                              dvec3(0, 0, 1));
                break;
            }
            default: break;
        }
        views.push_back(cam);
    }
    return views;
}

std::vector<Camera> boxViews(const Box& b, int count, uint64_t seed, int w, int h) {
    scenes::Rng rng(seed);
    std::vector<Camera> views;
    for (int k = 0; k < count; ++k) views.push_back(scenes::randomCamera(rng, b, k, w, h));
    return views;
}

namespace {

constexpr double kPi = 3.14159265358979323846;

// A perspective camera looking from `eye` along `dir`; up is +Z unless the view is (nearly) vertical.
// `exact` (bit 0: x, 1: y, 2: z): eye coordinates that must come out exactly as given, for eyes meant to lie
// exactly in a plane. The camera derives its eye from the inverted view matrix, which rounds: the eye given
// is nudged by the error, and if that does not land, the direction is turned by a negligible angle (below
// 1e-5 radians) and the nudging tried again.
Camera lookAlong(const dvec3& eye, const dvec3& dir, double fov, double zNear, double zFar, int w, int h,
                 int exact = 0) {
    const dvec3 d0 = glm::normalize(dir);
    const dvec3 up = std::abs(d0.z) > 1.0 - 1e-9 ? dvec3(0, 1, 0) : dvec3(0, 0, 1);
    Camera cam;
    cam.setViewport(w, h);
    cam.setPerspective(fov, double(w) / h, zNear, zFar);
    auto landed = [&] {
        for (int a = 0; a < 3; ++a)
            if ((exact >> a & 1) && cam.eye()[a] != eye[a]) return false;
        return true;
    };
    for (int attempt = 0; attempt < 64; ++attempt) {
        const dvec3 d = attempt == 0 ? d0 : glm::normalize(d0 + 1e-7 * attempt * dvec3(0.3, -0.7, 0.2));
        dvec3 given = eye;
        cam.setLookAt(given, given + d, up);
        for (int k = 0; k < 4 && !landed(); ++k) {
            for (int a = 0; a < 3; ++a)
                if (exact >> a & 1) given[a] += eye[a] - cam.eye()[a];
            cam.setLookAt(given, given + d, up);
        }
        if (landed()) break;
    }
    return cam;
}

// The direction of a yaw (radians, from +X towards +Y) and a pitch (radians, up positive).
dvec3 heading(double yaw, double pitch) {
    return dvec3(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch));
}

// A view from above: looking down at `target` with the given depression below the horizon (radians) from
// the height `z`; the eye stands back from the target along -yaw.
Camera lookDownAt(const dvec3& target, double z, double yaw, double depression, double fov, double zNear, double zFar,
                  int w, int h) {
    const double back = (z - target.z) / std::tan(depression);
    const dvec3 eye(target.x - back * std::cos(yaw), target.y - back * std::sin(yaw), z);
    return lookAlong(eye, target - eye, fov, zNear, zFar, w, h);
}

}  // namespace

// City geometry (docs/scenes.md): building (i, j) occupies [20i+4, 20i+16] x [20j+4, 20j+16] x [0, h(i, j)]; the
// streets are the 8 m gaps around x = 20i and y = 20j (edge streets included); cars are 4 x 2 x 1.5 boxes at
// (20i+1, 20j+1, 0), lower than any street-level eye.
std::vector<Camera> cityOcclusionViews(int n, int count, uint64_t seed, int w, int h) {
    scenes::Rng rng(seed);
    const double L = 20.0 * n;
    const double fov = 60.0, zfar = 3000.0;
    auto eyeZ = [&] { return rng.uniform(1.5, 2.0); };
    auto yaw = [&] { return rng.uniform(0.0, 2.0 * kPi); };
    auto pitch = [&] { return rng.uniform(-0.15, 0.25); };
    // Either a random yaw or (half the time) along the face whose plane is x = const (alongY) or y = const.
    auto yawNearFace = [&](bool alongY) {
        if (rng.chance(0.5)) return yaw();
        const double base = (alongY ? 0.5 * kPi : 0.0) + (rng.chance(0.5) ? kPi : 0.0);
        return base + rng.uniform(-0.05, 0.05);
    };
    std::vector<Camera> views;
    for (int k = 0; k < count; ++k) {
        const int i = rng.below(n), j = rng.below(n);
        const bool alongY = rng.chance(0.5);  // which of the building's faces (x = const or y = const) or streets
        // The building's face planes: the near and far one across the chosen axis.
        const double lo = 20.0 * (alongY ? i : j) + 4, hi = lo + 12;
        const double faceCoord = rng.chance(0.5) ? lo : hi;
        const double otherLo = 20.0 * (alongY ? j : i) + 4;  // the building along the face
        auto put = [&](double across, double along, double z) {
            return alongY ? dvec3(across, along, z) : dvec3(along, across, z);
        };
        const int acrossBit = alongY ? 1 : 2, alongBit = alongY ? 2 : 1;  // lookAlong's `exact` bits
        if (k % 2 == 0) {                                                 // street level
            dvec3 eye;
            double yw = yaw(), pt = pitch();
            int exact = 0;
            bool axisAligned = false;  // the view exactly along the street: put(0, +-1, 0)
            switch (k % 20) {
                case 0:  // exactly on a building's vertical edge
                    eye = put(faceCoord, rng.chance(0.5) ? otherLo : otherLo + 12, eyeZ());
                    exact = acrossBit | alongBit;
                    break;
                case 4:  // in a face's plane, beside the face (in the cross street): the face is seen edge-on
                    eye = put(faceCoord, otherLo - 8 + rng.uniform(0, 8) + (rng.chance(0.5) ? 0 : 20), eyeZ());
                    yw = yawNearFace(alongY);
                    exact = acrossBit;
                    break;
                case 8:  // exactly on a face
                    eye = put(faceCoord, otherLo + rng.uniform(0, 12), eyeZ());
                    exact = acrossBit;
                    break;
                case 12: {  // very close to a face, outside the building
                    const double gap = std::pow(10.0, rng.uniform(-4, -0.5));
                    eye = put(faceCoord == lo ? lo - gap : hi + gap, otherLo + rng.uniform(-1, 13), eyeZ());
                    yw = yawNearFace(alongY);
                    break;
                }
                case 16: {  // exactly along a street (level, or nearly), in its middle or anywhere across it
                    const double across = 20.0 * rng.below(n + 1) + (rng.chance(0.5) ? 0.0 : rng.uniform(-3.5, 3.5));
                    const double along = rng.uniform(-4, L + 4);
                    eye = put(across, along, eyeZ());
                    yw = along < 0.5 * L ? 1.0 : -1.0;  // the sign along the street: into the city
                    axisAligned = rng.chance(0.5);
                    pt = axisAligned ? 0.0 : rng.uniform(-0.05, 0.1);
                    exact = acrossBit;
                    break;
                }
                default:  // anywhere in a street
                    eye = put(20.0 * rng.below(n + 1) + rng.uniform(-4, 4), rng.uniform(-4, L + 4), eyeZ());
                    break;
            }
            const dvec3 dir = k % 20 != 16  ? heading(yw, pt)
                              : axisAligned ? put(0, yw, 0)
                                            : put(0, yw, 0) + dvec3(0, 0, pt);
            views.push_back(lookAlong(eye, dir, fov, 0.5, zfar, w, h, exact));
        } else {  // from above
            const dvec3 target(rng.uniform(0, L), rng.uniform(0, L), rng.uniform(0, 20));
            const double z = 30.0 * std::pow(800.0 / 30.0, rng.uniform(0, 1));  // more low views than high ones
            switch (k % 20) {
                case 11:  // straight down
                    views.push_back(lookAlong(dvec3(target.x, target.y, z), dvec3(0, 0, -1), fov, 1.0, zfar, w, h));
                    break;
                case 15: {  // steeply down, the eye in a face's plane
                    const dvec3 eye = put(faceCoord, otherLo + rng.uniform(-4, 16), z);
                    views.push_back(lookAlong(eye, heading(yawNearFace(alongY), -rng.uniform(0.9, 1.55)), fov, 1.0,
                                              zfar, w, h, acrossBit));
                    break;
                }
                case 19: {  // level with a roof (the tallest building found in a few tries), just beside it
                    int bi = i, bj = j;
                    for (int t = 0; t < 8; ++t) {
                        const int ti = rng.below(n), tj = rng.below(n);
                        if (scenes::cityHeight(uint32_t(ti), uint32_t(tj)) >
                            scenes::cityHeight(uint32_t(bi), uint32_t(bj))) {
                            bi = ti;
                            bj = tj;
                        }
                    }
                    const double roof = scenes::cityHeight(uint32_t(bi), uint32_t(bj));
                    const double gap = rng.chance(0.5) ? 0.0 : rng.uniform(0, 20);
                    const dvec3 eye(20.0 * bi + 4 - gap, 20.0 * bj + rng.uniform(0, 20), roof);
                    views.push_back(lookAlong(eye, heading(yaw(), rng.chance(0.5) ? 0.0 : -rng.uniform(0, 0.3)), fov,
                                              0.5, zfar, w, h, gap == 0.0 ? 5 : 4));
                    break;
                }
                default: {
                    // Oblique (8-45 degrees below the horizon) or steep (45-89), the target no farther than 2.5 km.
                    const double minDep = std::asin(std::min(1.0, (z - target.z) / 2500.0));
                    const double dep =
                        std::max(minDep, rng.chance(0.5) ? rng.uniform(0.14, 0.785) : rng.uniform(0.785, 1.553));
                    views.push_back(lookDownAt(target, z, yaw(), dep, fov, 1.0, zfar, w, h));
                    break;
                }
            }
        }
    }
    return views;
}

// Office geometry (docs/scenes.md): room (i, j) spans [6i, 6i+6] x [6j, 6j+6]; walls 0.2 m thick and 3 m high
// centred on the room boundaries; inner walls have a door opening 1 m wide (the middle of the wall) and
// 2.2 m high. No ceiling.
std::vector<Camera> officeViews(int r, int count, uint64_t seed, int w, int h) {
    scenes::Rng rng(seed);
    const double L = 6.0 * r, fov = 60.0, zNear = 0.1, zFar = 200.0;
    auto eyeZ = [&] { return rng.uniform(1.2, 1.8); };
    auto yaw = [&] { return rng.uniform(0.0, 2.0 * kPi); };
    auto pitch = [&] { return rng.uniform(-0.25, 0.2); };
    // Furniture an eye 1.2-1.8 m high could stand in (room offsets, with a margin): the shelf (2 m high)
    // and the monitors (up to 1.22 m).
    auto inFurniture = [](double x, double y) {
        if (x < 0.65 && y > 0.05 && y < 2.35) return true;
        for (const glm::dvec2 d : {glm::dvec2(1, 1), glm::dvec2(3.4, 1), glm::dvec2(1, 4.2), glm::dvec2(3.4, 4.2)})
            if (x > d.x + 0.4 && x < d.x + 1.2 && y > d.y + 0.2 && y < d.y + 0.6) return true;
        return false;
    };
    // A point in room (i, j) at least `margin` from the wall faces and clear of the furniture.
    auto inRoom = [&](int i, int j, double margin) {
        for (;;) {
            const double x = rng.uniform(0.1 + margin, 5.9 - margin), y = rng.uniform(0.1 + margin, 5.9 - margin);
            if (!inFurniture(x, y)) return glm::dvec2(6.0 * i + x, 6.0 * j + y);
        }
    };
    std::vector<Camera> views;
    for (int k = 0; k < count; ++k) {
        const int i = rng.below(r), j = rng.below(r);
        // An inner wall of room (i, j): its west wall (x = 6i, doors span y in [6j+2.5, 6j+3.5]) or its south
        // wall (y = 6j). With a single row of rooms there is no inner wall along that axis.
        bool west = rng.chance(0.5);
        if (r > 1 && (west ? i == 0 : j == 0)) west = !west;
        const int wi = std::max(i, r > 1 ? 1 : 0), wj = std::max(j, r > 1 ? 1 : 0);
        const double wallCoord = west ? 6.0 * wi : 6.0 * wj;          // the wall's centre plane
        const double doorMid = west ? 6.0 * j + 3.0 : 6.0 * i + 3.0;  // the door's middle along the wall
        auto put = [&](double across, double along, double z) {
            return west ? dvec3(across, along, z) : dvec3(along, across, z);
        };
        const double alongYaw = west ? 0.5 * kPi : 0.0;               // yaw along the wall
        const int acrossBit = west ? 1 : 2, alongBit = west ? 2 : 1;  // lookAlong's `exact` bits
        switch (k % 10) {
            case 3: {  // standing in a door opening
                const dvec3 eye = put(wallCoord + rng.uniform(-0.1, 0.1), doorMid + rng.uniform(-0.45, 0.45), eyeZ());
                views.push_back(lookAlong(eye, heading(yaw(), pitch()), fov, zNear, zFar, w, h));
                break;
            }
            case 4:
            case 5: {  // in a room, looking through a door into the next room
                const double side = rng.chance(0.5) ? 1.0 : -1.0;  // which room of the two
                dvec3 eye;
                for (;;) {
                    eye = put(wallCoord + side * rng.uniform(0.4, 5.5), doorMid + rng.uniform(-2.5, 2.5), eyeZ());
                    const double rx = eye.x - 6.0 * std::floor(eye.x / 6.0), ry = eye.y - 6.0 * std::floor(eye.y / 6.0);
                    if (!inFurniture(rx, ry)) break;
                }
                const dvec3 target = put(wallCoord, doorMid + rng.uniform(-0.4, 0.4), rng.uniform(0.5, 2.0));
                views.push_back(lookAlong(eye, target - eye, fov, zNear, zFar, w, h));
                break;
            }
            case 6: {  // awkward eyes
                dvec3 eye;
                double yw = yaw();
                int exact = 0;
                switch ((k / 10) % 4) {
                    case 0:  // exactly in a wall's face plane: on the face, or in the door opening's plane
                        eye = put(wallCoord + (rng.chance(0.5) ? 0.1 : -0.1), doorMid + rng.uniform(-2.9, 2.9), eyeZ());
                        if (rng.chance(0.5)) yw = alongYaw + (rng.chance(0.5) ? kPi : 0.0) + rng.uniform(-0.05, 0.05);
                        exact = acrossBit;
                        break;
                    case 1:  // exactly in a door jamb's plane (a face of the wall box beside the opening)
                        eye = put(wallCoord + rng.uniform(-2, 2), doorMid + (rng.chance(0.5) ? 0.5 : -0.5), eyeZ());
                        exact = alongBit;
                        break;
                    case 2: {  // very close to a wall's face
                        const double gap = std::pow(10.0, rng.uniform(-4, -1.3));
                        eye = put(wallCoord + (rng.chance(0.5) ? 0.1 + gap : -0.1 - gap),
                                  doorMid + rng.uniform(-2.8, 2.8), eyeZ());
                        if (rng.chance(0.5)) yw = alongYaw + (rng.chance(0.5) ? kPi : 0.0) + rng.uniform(-0.1, 0.1);
                        break;
                    }
                    default:  // in the door opening exactly level with the lintel's underside
                        eye = put(wallCoord + rng.uniform(-0.1, 0.1), doorMid + rng.uniform(-0.45, 0.45), 2.2);
                        exact = 4;
                        break;
                }
                views.push_back(lookAlong(eye, heading(yw, pitch()), fov, zNear, zFar, w, h, exact));
                break;
            }
            case 7:
            case 8:
            case 9: {  // from above, at the walls' top (exactly, or just over it) or higher
                const dvec3 target(rng.uniform(0, L), rng.uniform(0, L), rng.uniform(0, 1.5));
                if (k % 10 == 9 && (k / 10) % 2 == 0) {
                    // Over a room or standing on a wall (the eye on its top face when exactly level with it).
                    const bool top = rng.chance(0.5);
                    const double z = top ? 3.0 : rng.uniform(3.0, 4.0);
                    const dvec3 eye =
                        rng.chance(0.5) ? dvec3(inRoom(i, j, 0.2), z)
                                        : put(wallCoord + rng.uniform(-0.1, 0.1), doorMid + rng.uniform(-2.9, 2.9), z);
                    views.push_back(
                        lookAlong(eye, heading(yaw(), -rng.uniform(0.0, 0.6)), fov, zNear, zFar, w, h, top ? 4 : 0));
                } else {
                    const double z = 4.0 * std::pow(15.0, rng.uniform(0, 1));  // 4-60 m
                    const double dep = rng.chance(0.5) ? rng.uniform(0.3, 0.785) : rng.uniform(0.785, 1.5708);
                    if (dep > 1.57)
                        views.push_back(
                            lookAlong(dvec3(target.x, target.y, z), dvec3(0, 0, -1), fov, zNear, zFar, w, h));
                    else
                        views.push_back(lookDownAt(target, z, yaw(), dep, fov, zNear, zFar, w, h));
                }
                break;
            }
            default: {  // anywhere in a room
                const glm::dvec2 p = inRoom(i, j, 0.25);
                views.push_back(lookAlong(dvec3(p, eyeZ()), heading(yaw(), pitch()), fov, zNear, zFar, w, h));
                break;
            }
        }
    }
    return views;
}

}  // namespace accuracy
