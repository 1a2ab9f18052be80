// IntersectTraversal's rays against points and lines: the hits within the options' cone, through each mesh's
// PointBvh.
#include "nodes/Geometry.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/style/FeatureStyle.h"

namespace sg {

namespace {
// The vertex whose features a hit shows (the style hides by it, as featuresAt() reads it): a point's own, a
// segment's nearer end.
uint32_t hitVertex(const Mesh& mesh, uint32_t primitive, double u) {
    if (mesh.primitive() != Primitive::Lines) return primitive;
    return mesh.index(2 * size_t(primitive) + (u > 0.5 ? 1 : 0));
}
}  // namespace

void IntersectTraversal::fillPointHit(Hit& h, Node* n, const PointBvh::ConeHit& r) const {
    h.t = r.t;
    h.point = q_ + r.point;
    h.distance = glm::length(r.point - o_);  // the point is beside the ray, not on it
    h.normal = dvec3(0.0);
    h.primitive = r.primitive;
    h.u = r.u, h.v = 0.0;
    h.path = path_;
    h.geometry = static_cast<const Geometry*>(n);
    h.instance = instance_;
    h.placement = placement_;
}

// The ray's hits on one geometry of points or lines: the nearest along the ray (or all) that the query's style
// shows. The cone is tested in the query's frame: its size is the query's whatever the geometry's scale.
void IntersectTraversal::rayPoints(Node* n, const Mesh& mesh, const dmat4& m, const PointBvh* given) {
    if (mesh.primitiveCount() == 0) return;
    const PointBvh& bvh = given ? *given : pointCache_.get(mesh);
    stats_.geometriesTested++;
    PointBvh::Cone cone{o_, d_, tMax_, opt_->coneWidth, opt_->coneSlope, glm::dmat3(m), dvec3(m[3])};
    if (mode_ == Mode::Nearest && found_) cone.tMax = best_->t;
    const MeshFeatures* f = opt_->style ? mesh.features() : nullptr;
    const bool styled = f && !f->sets.empty() && f->sets[0].source != FeatureIdSet::Source::Texture;
    auto shown = [&](const PointBvh::ConeHit& r) {
        return !styled || opt_->style->shown(*f, 0, f->idAt(0, hitVertex(mesh, r.primitive, r.u)));
    };
    if (mode_ == Mode::Nearest && !styled) {
        PointBvh::ConeHit r;
        if (bvh.nearest(cone, r) && (!found_ || r.t < best_->t)) {
            fillPointHit(*best_, n, r);
            found_ = true;
        }
        return;
    }
    coneHits_.clear();
    bvh.all(cone, coneHits_);
    const PointBvh::ConeHit* nearest = nullptr;
    for (const auto& r : coneHits_) {
        if (!shown(r)) continue;
        if (mode_ == Mode::All) {
            all_->emplace_back();
            fillPointHit(all_->back(), n, r);
        } else if ((!nearest || r.t < nearest->t) && (!found_ || r.t < best_->t)) {
            nearest = &r;
        }
    }
    if (nearest) {
        fillPointHit(*best_, n, *nearest);
        found_ = true;
    }
}

}  // namespace sg
