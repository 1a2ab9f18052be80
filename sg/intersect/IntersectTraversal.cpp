#include "sg/intersect/IntersectTraversal.h"

#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/core/Camera.h"
#include "sg/intersect/internal/IntersectPrimitives.h"
#include "sg/lod/internal/LodChooser.h"
#include "sg/scene/Posing.h"
#include "sg/scene/internal/ImageWalk.h"
#include "sg/style/FeatureStyle.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace sg {

namespace {
std::string str(const dvec3& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

void checkPoint(const char* fn, const char* what, const dvec3& p) {
    if (!isFinite(p)) throw std::invalid_argument(std::string(fn) + ": " + what + " " + str(p) + " is not finite");
}

void checkRay(const char* fn, const Ray& r) {
    checkPoint(fn, "ray origin", r.origin);
    checkPoint(fn, "ray direction", r.direction);
    if (!(glm::dot(r.direction, r.direction) > 0.0))
        throw std::invalid_argument(std::string(fn) + ": ray direction " + str(r.direction) + " has zero length");
    if (!(r.tMax >= 0.0))
        throw std::invalid_argument(std::string(fn) + ": ray tMax " + std::to_string(r.tMax) + " is negative or NaN");
}

void checkCone(const char* fn, const QueryOptions& o) {
    if (!(o.coneWidth >= 0.0 && std::isfinite(o.coneWidth) && o.coneSlope >= 0.0 && std::isfinite(o.coneSlope)))
        throw std::invalid_argument(std::string(fn) + ": cone width " + std::to_string(o.coneWidth) + " or slope " +
                                    std::to_string(o.coneSlope) + " is negative or not finite");
}

void checkRadius(const char* fn, double r) {
    if (!(r >= 0.0 && std::isfinite(r)))
        throw std::invalid_argument(std::string(fn) + ": radius " + std::to_string(r) + " is negative or not finite");
}
}  // namespace

// Per image: where it is (ImageFrame: its "eye" is the query's relative origin, the camera's eye or the
// query's start), and the query in that image's coordinates.
struct IntersectTraversal::Ctx : ImageFrame {
    dvec3 o{0.0}, d{0.0}, inv{0.0};  // ray modes
    PointBvh::ConeFrame cone;        // ray modes with a cone: how it widens the image's boxes
    Box region;                      // sphere modes
};

void IntersectTraversal::setupCtx(Ctx& c, const FlatImage& img, const dmat4& t) const {
    static_cast<ImageFrame&>(c) = ImageFrame::make(img, t);
    const dmat4 inv = glm::inverse(t);
    if (mode_ == Mode::Nearest || mode_ == Mode::All) {
        c.o = dvec3(inv * dvec4(o_, 1.0));
        c.d = glm::dmat3(inv) * d_;
        c.inv = dvec3(1.0 / c.d.x, 1.0 / c.d.y, 1.0 / c.d.z);
        if (cone_)
            c.cone = PointBvh::ConeFrame::make(
                {o_, d_, tMax_, opt_->coneWidth, opt_->coneSlope, glm::dmat3(t), dvec3(t[3])});
    } else {
        c.region = transformBox(inv, region_);
    }
}

void IntersectTraversal::run(const Scene& scene, const QueryOptions& opt, const dvec3& origin, const char* fn) {
    checkUpdated(scene, fn);
    checkLodScale(opt.lodScale, fn);
    scene_ = &scene;
    opt_ = &opt;
    q_ = opt.camera ? opt.camera->eye() : origin;
    stats_ = IntersectStats{};
    path_.clear();
    order_.clear();
    instance_ = nullptr;
    placement_ = ~0u;
    found_ = false;
    const FlatImage& img = scene.image();
    if (img.size() == 0) return;
    o_ -= q_;
    if (mode_ == Mode::Sphere || mode_ == Mode::Sweep) {
        const dvec3 reach(radius_);
        region_ = Box{glm::min(o_, o_ + d_) - reach, glm::max(o_, o_ + d_) + reach};
    }
    // As drawn: the cull's ranges and LOD scale (no hysteresis, budget or fade), measured from the relative
    // origin; Highest, or a pixel-size LOD without a camera: the finest child.
    const LodChooser chooser({opt.camera, opt.lodScale, 0.0, false, opt.lod == LodChoice::Highest});
    chooser_ = &chooser;
    Ctx c;
    setupCtx(c, img, glm::translate(dmat4(1.0), img.origin - q_));
    visit(c, 0, scene.root(), glm::translate(dmat4(1.0), -q_), false);
    chooser_ = nullptr;
}

bool IntersectTraversal::intersect(const Scene& scene, const Ray& ray, const QueryOptions& opt, Hit& out) {
    constexpr const char* fn = "IntersectTraversal::intersect()";
    checkRay(fn, ray);
    checkCone(fn, opt);
    mode_ = Mode::Nearest;
    cone_ = opt.coneWidth > 0.0 || opt.coneSlope > 0.0;
    o_ = ray.origin, d_ = ray.direction, tMax_ = ray.tMax;
    Hit h;
    best_ = &h;
    run(scene, opt, ray.origin, fn);
    best_ = nullptr;
    if (found_) out = std::move(h);
    return found_;
}

void IntersectTraversal::intersectAll(const Scene& scene, const Ray& ray, const QueryOptions& opt,
                                      std::vector<Hit>& out) {
    constexpr const char* fn = "IntersectTraversal::intersectAll()";
    checkRay(fn, ray);
    checkCone(fn, opt);
    mode_ = Mode::All;
    cone_ = opt.coneWidth > 0.0 || opt.coneSlope > 0.0;
    o_ = ray.origin, d_ = ray.direction, tMax_ = ray.tMax;
    out.clear();
    all_ = &out;
    run(scene, opt, ray.origin, fn);
    all_ = nullptr;
    std::stable_sort(out.begin(), out.end(), [](const Hit& a, const Hit& b) { return a.t < b.t; });
}

void IntersectTraversal::intersectSphere(const Scene& scene, const dvec3& centre, double radius,
                                         const QueryOptions& opt, std::vector<Hit>& out) {
    constexpr const char* fn = "IntersectTraversal::intersectSphere()";
    checkPoint(fn, "centre", centre);
    checkRadius(fn, radius);
    mode_ = Mode::Sphere;
    cone_ = false;
    o_ = centre, d_ = dvec3(0.0), radius_ = radius;
    out.clear();
    all_ = &out;
    run(scene, opt, centre, fn);
    all_ = nullptr;
    std::stable_sort(out.begin(), out.end(), [](const Hit& a, const Hit& b) { return a.t < b.t; });
}

bool IntersectTraversal::sweepSphere(const Scene& scene, const dvec3& centre, double radius, const dvec3& motion,
                                     const QueryOptions& opt, SweepHit& out) {
    constexpr const char* fn = "IntersectTraversal::sweepSphere()";
    checkPoint(fn, "centre", centre);
    checkPoint(fn, "motion", motion);
    checkRadius(fn, radius);
    mode_ = Mode::Sweep;
    cone_ = false;
    o_ = centre, d_ = motion, radius_ = radius;
    SweepHit h;
    sweep_ = &h;
    run(scene, opt, centre, fn);
    sweep_ = nullptr;
    if (found_) out = std::move(h);
    return found_;
}

// Entry i's bound against the query (in the image's coordinates); tNear: where the ray enters it.
bool IntersectTraversal::test(const Ctx& c, uint32_t i, double& tNear) const {
    const FlatImage& img = *c.img;
    tNear = 0.0;
    const uint8_t fl = img.flags[i];
    if (fl & FlatImage::kEmpty) return false;
    if (fl & (FlatImage::kInvalid | FlatImage::kNoTest)) return true;
    const double cx = img.cx[i], cy = img.cy[i], cz = img.cz[i], ex = img.ex[i], ey = img.ey[i], ez = img.ez[i];
    const double mn[3] = {cx - ex, cy - ey, cz - ez}, mx[3] = {cx + ex, cy + ey, cz + ez};
    if (mode_ == Mode::Nearest || mode_ == Mode::All) {
        const double tMax = mode_ == Mode::Nearest && found_ ? best_->t : tMax_;
        if (cone_) return !c.cone.valid || c.cone.enter(mn, mx, tMax, tNear);  // points near the ray, not on it
        return isect::slab(mn, mx, c.o, c.inv, tMax, tNear);
    }
    const Box& r = c.region;
    return !(mn[0] > r.max.x || mn[1] > r.max.y || mn[2] > r.max.z || mx[0] < r.min.x || mx[1] < r.min.y ||
             mx[2] < r.min.z);
}

void IntersectTraversal::visit(Ctx& c, uint32_t i, Node* n, const dmat4& m, bool tested) {
    const FlatImage& img = *c.img;
    const uint8_t fl = img.flags[i];
    if (fl & FlatImage::kEmpty) return;
    if ((fl & FlatImage::kMasked) && !(n->nodeMask() & opt_->traversalMask)) return;
    if ((fl & FlatImage::kFeature) && opt_->style) {  // a feature the style hides is not there to hit
        const FlatImage::FeatureRef* f = img.featureOf(i);
        if (f && f->features && !opt_->style->shown(*f->features, 0, f->features->idAt(0, f->index))) return;
    }
    double tNear;
    if (!tested && !test(c, i, tNear)) return;
    stats_.entriesVisited++;
    path_.push_back(n);
    switch (img.kind[i]) {
        case NodeKind::Geometry: geometry(n, m, fl & FlatImage::kPosed ? img.poseOf(i) : nullptr); break;
        case NodeKind::Transform: children(c, i, n, transformed(img, i, m)); break;
        case NodeKind::LOD:
            chooser_->choose(c, i, {},
                             [&](const LodChooser::Shown& k) { visit(c, k.entry, n->child(k.child), m, false); });
            break;
        case NodeKind::Switch: {
            const auto* sw = static_cast<const Switch*>(n);
            size_t k = 0;
            for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++k)
                if (sw->isOn(k)) visit(c, j, n->child(k), m, false);
            break;
        }
        case NodeKind::Billboard: {
            const auto* bb = static_cast<const Billboard*>(n);
            const dvec3 eyeLocal(glm::inverse(m) * dvec4(0, 0, 0, 1));
            children(c, i, n, m * bb->rotationToward(eyeLocal));
            break;
        }
        case NodeKind::Instance: {
            auto* in = static_cast<Instance*>(n);
            // A paged detail's image holds its prototypes' images: looked up from the image that places this one.
            const FlatImage* p = in->prototype() ? scene_->prototypeImage(img, in->prototype()) : nullptr;
            if (!p || p->size() == 0) break;
            const dmat4 pm = m * in->matrix();
            Ctx sub;
            setupCtx(sub, *p, glm::translate(pm, p->origin));
            const Instance* outerInstance = instance_;
            const uint32_t outerPlacement = placement_;
            instance_ = in;
            placement_ = i;
            visit(sub, 0, in->prototype(), pm, false);
            instance_ = outerInstance;
            placement_ = outerPlacement;
            break;
        }
        case NodeKind::PagedLOD: {
            // The detail when attached and shown (as the LOD choice says), else the coarse children. The
            // detail's image is in this image's frame, shifted to its own origin.
            const FlatImage::Paged& p = img.paged[img.aux[i]];
            const auto* pl = static_cast<const PagedLOD*>(n);
            const bool fine = p.detail != nullptr && chooser_->detailWanted(c, i);
            if (!fine) {  // the entry's children are the node's but the detail
                size_t k = 0;
                for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++k) {
                    if (n->child(k) == pl->detail()) ++k;
                    visit(c, j, n->child(k), m, false);
                }
                break;
            }
            if (p.detail->size() == 0) break;
            Ctx sub;
            setupCtx(sub, *p.detail, c.imgToEye * glm::translate(dmat4(1.0), p.detail->origin - img.origin));
            visit(sub, 0, pl->detail(), m, false);
            break;
        }
        case NodeKind::Occluder: break;  // not geometry
        default: children(c, i, n, m); break;
    }
    path_.pop_back();
}

// A child's sphere from a Group's side-by-side columns (FlatImage::Wide) against the query: a cheap first
// pass over many children read from one place. NaN (invalid) bounds pass.
bool IntersectTraversal::wideTest(const Ctx& c, uint32_t w) const {
    const FlatImage& img = *c.img;
    const dvec3 centre(img.wcx[w], img.wcy[w], img.wcz[w]);
    double r = double(img.wr[w]) * (1.0 + 1e-9);
    if (cone_ && (mode_ == Mode::Nearest || mode_ == Mode::All)) {
        if (!c.cone.valid) return true;
        r = c.cone.sphereReach(centre, r);
    }
    dvec3 nearest;
    if (mode_ == Mode::Nearest || mode_ == Mode::All) {
        const double tMax = mode_ == Mode::Nearest && found_ ? best_->t : tMax_;
        const double tc = glm::dot(centre - c.o, c.d) / glm::dot(c.d, c.d);
        nearest = c.o + c.d * (tc < 0.0 ? 0.0 : (tc > tMax ? tMax : tc));
    } else {
        nearest = glm::clamp(centre, c.region.min, c.region.max);
    }
    const dvec3 e = centre - nearest;
    return !(glm::dot(e, e) > r * r);
}

void IntersectTraversal::children(Ctx& c, uint32_t i, Node* n, const dmat4& m) {
    const FlatImage& img = *c.img;
    const uint32_t end = img.end[i];
    const FlatImage::Wide* wide = img.kind[i] == NodeKind::Group && img.aux[i] ? &img.wides[img.aux[i] - 1] : nullptr;
    if (!wide && (mode_ != Mode::Nearest || end - i <= 3)) {
        size_t k = 0;
        for (uint32_t j = i + 1; j < end; j = img.end[j], ++k) visit(c, j, n->child(k), m, false);
        return;
    }
    // The children that meet the query (front to back for the nearest hit, stopping at the first whose
    // bound starts beyond the best hit so far).
    const size_t base = order_.size();
    double tNear;
    if (wide) {
        for (uint32_t k = 0; k < wide->count; ++k) {
            const uint32_t j = img.wideEntry[wide->first + k];
            if (wideTest(c, wide->first + k) && test(c, j, tNear)) order_.push_back({tNear, j, k});
        }
    } else {
        uint32_t k = 0;
        for (uint32_t j = i + 1; j < end; j = img.end[j], ++k)
            if (test(c, j, tNear)) order_.push_back({tNear, j, k});
    }
    if (mode_ == Mode::Nearest)
        std::sort(order_.begin() + long(base), order_.end(),
                  [](const Pending& a, const Pending& b) { return a.tNear < b.tNear; });
    const size_t count = order_.size() - base;
    for (size_t e = 0; e < count; ++e) {
        const Pending p = order_[base + e];
        if (mode_ == Mode::Nearest && found_ && p.tNear > best_->t) break;
        visit(c, p.entry, n->child(p.child), m, true);
    }
    order_.resize(base);
}

// The ray's hits on one geometry: the nearest (or all) of its triangles that the query's style shows.
void IntersectTraversal::rayGeometry(Node* n, const MeshBvh& bvh, const glm::dmat3& inv, const dvec3& t) {
    const Mesh& mesh = *static_cast<Geometry*>(n)->mesh();
    dvec3 p0, p1, p2;
    // The ray in the geometry's frame; its parameter t is the same in every frame (affine maps keep it).
    const dvec3 oL = inv * (o_ - t), dL = inv * d_;
    auto fill = [&](Hit& h, const MeshBvh::RayHit& r) {
        h.t = r.t;
        h.point = q_ + (o_ + d_ * r.t);
        h.distance = r.t * glm::length(d_);
        bvh.triangle(r.primitive, p0, p1, p2);
        const dvec3 nw = glm::transpose(inv) * glm::cross(p1 - p0, p2 - p0);
        const double len = glm::length(nw);
        h.normal = len > 0.0 ? nw / len : dvec3(0.0);
        h.primitive = r.primitive;
        h.u = r.u, h.v = r.v;
        h.path = path_;
        h.geometry = static_cast<const Geometry*>(n);
        h.instance = instance_;
        h.placement = placement_;
    };
    const MeshFeatures* f = opt_->style ? mesh.features() : nullptr;
    const bool styled = f && !f->sets.empty() && f->sets[0].source != FeatureIdSet::Source::Texture;
    auto shown = [&](const MeshBvh::RayHit& r) {
        return !styled || opt_->style->shown(*f, 0, f->idAt(0, mesh.index(size_t(r.primitive) * 3)));
    };
    if (mode_ == Mode::Nearest && !styled) {
        MeshBvh::RayHit r;
        if (bvh.nearest(oL, dL, found_ ? best_->t : tMax_, r) && (!found_ || r.t < best_->t)) {
            fill(*best_, r);
            found_ = true;
        }
        return;
    }
    rayHits_.clear();
    bvh.all(oL, dL, mode_ == Mode::Nearest && found_ ? best_->t : tMax_, rayHits_);
    const MeshBvh::RayHit* nearest = nullptr;
    for (const auto& r : rayHits_) {
        if (!shown(r)) continue;
        if (mode_ == Mode::All) {
            all_->emplace_back();
            fill(all_->back(), r);
        } else if ((!nearest || r.t < nearest->t) && (!found_ || r.t < best_->t)) {
            nearest = &r;
        }
    }
    if (nearest) {
        fill(*best_, *nearest);
        found_ = true;
    }
}

// `pose`: the image's pose of a posed Geometry (null: not posed). Its mesh is tested as posed, a skinned one in world
// coordinates whatever its path's matrix; hits name the triangles of the Geometry's mesh all the same.
void IntersectTraversal::geometry(Node* n, const dmat4& pathMatrix, const Pose* pose) {
    const auto* g = static_cast<const Geometry*>(n);
    const Mesh* mesh = g->mesh();
    if (!mesh) return;
    ref_ptr<const Pose> made;
    if (!pose && g->posed()) pose = (made = makePose(*g)).get();  // not in the image: worked out from the nodes
    Posed* as = pose ? &posed(*g, *pose) : nullptr;
    const dmat4 m = pose && pose->skinned() ? glm::translate(dmat4(1.0), -q_) : pathMatrix;
    if (as) mesh = as->mesh.get();
    if (mesh->primitive() != Primitive::Triangles) {
        // Spheres and swept spheres pass through points and lines: they have no surface to touch or stand on.
        if (!cone_ || !(mode_ == Mode::Nearest || mode_ == Mode::All)) return;
        if (as && !as->points) as->points = std::make_unique<PointBvh>(*mesh);
        rayPoints(n, *mesh, m, as ? as->points.get() : nullptr);
        return;
    }
    if (mesh->triangleCount() == 0) return;
    if (as && !as->triangles) as->triangles = std::make_unique<MeshBvh>(*mesh);
    const MeshBvh& bvh = as ? *as->triangles : cache_.get(*mesh);
    stats_.geometriesTested++;
    const glm::dmat3 a(m);
    const glm::dmat3 inv = glm::inverse(a);
    const dvec3 t(m[3]);
    dvec3 p0, p1, p2;
    if (mode_ == Mode::Nearest || mode_ == Mode::All) {
        rayGeometry(n, bvh, inv, t);
        return;
    }
    // Sphere modes: the triangles whose boxes meet the region, tested exactly in relative coordinates.
    const Box local = transformBox(glm::inverse(m), region_);
    bvh.overlapping(local, [&](uint32_t prim) {
        stats_.trianglesTested++;
        bvh.triangle(prim, p0, p1, p2);
        const dvec3 A = a * p0 + t, B = a * p1 + t, C = a * p2 + t;
        if (mode_ == Mode::Sphere) {
            const dvec3 cp = isect::closestPointOnTriangle(o_, A, B, C);
            const double dist = glm::length(o_ - cp);
            if (!(dist <= radius_)) return;
            Hit h;
            h.t = h.distance = dist;
            h.point = q_ + cp;
            const dvec3 nw = glm::cross(B - A, C - A);
            const double len = glm::length(nw);
            h.normal = len > 0.0 ? nw / len : dvec3(0.0);
            h.primitive = prim;
            isect::barycentric(cp, A, B, C, h.u, h.v);
            h.path = path_;
            h.geometry = static_cast<const Geometry*>(n);
            h.instance = instance_;
            h.placement = placement_;
            all_->push_back(std::move(h));
            return;
        }
        double tc;
        dvec3 point, normal;
        if (isect::sweepSphereTriangle(o_, d_, radius_, A, B, C, found_ ? sweep_->t : 1.0, tc, point, normal) &&
            (!found_ || tc < sweep_->t)) {
            sweep_->t = tc;
            sweep_->point = q_ + point;
            sweep_->normal = normal;
            sweep_->path = path_;
            sweep_->geometry = static_cast<const Geometry*>(n);
            sweep_->primitive = prim;
            found_ = true;
        }
    });
}

}  // namespace sg
