// Small node types: data setters with their argument checks, and accept(); the visitor's defaults per kind.
#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/core/Assert.h"
#include "sg/core/NodeVisitor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sg {

size_t nodeBytes(NodeKind k) {
    switch (k) {
        case NodeKind::Group: return sizeof(Group);
        case NodeKind::Transform: return sizeof(Transform);
        case NodeKind::Geometry: return sizeof(Geometry);
        case NodeKind::LOD: return sizeof(LOD);
        case NodeKind::Switch: return sizeof(Switch);
        case NodeKind::Billboard: return sizeof(Billboard);
        case NodeKind::Instance: return sizeof(Instance);
        case NodeKind::BspGroup: return sizeof(BspGroup);
        case NodeKind::Occluder: return sizeof(Occluder);
        case NodeKind::PagedLOD: return sizeof(PagedLOD);
    }
    return sizeof(Node);
}

// --- NodeVisitor: each kind's default apply() forwards to its base kind's (here, where the kinds are complete).
void NodeVisitor::apply(Group& n) { apply(static_cast<Node&>(n)); }
void NodeVisitor::apply(Transform& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Geometry& n) { apply(static_cast<Node&>(n)); }
void NodeVisitor::apply(LOD& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Switch& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Billboard& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Instance& n) { apply(static_cast<Node&>(n)); }
void NodeVisitor::apply(BspGroup& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Occluder& n) { apply(static_cast<Node&>(n)); }
void NodeVisitor::apply(PagedLOD& n) { apply(static_cast<Group&>(n)); }

// --- Geometry
void Geometry::accept(NodeVisitor& v) { v.apply(*this); }
Geometry::~Geometry() = default;

void Geometry::setSkin(ref_ptr<Skin> skin) {
    if (skin && mesh_ && mesh_->influences() > 0 && mesh_->maxJoint() >= skin->size())
        throw std::invalid_argument("Geometry::setSkin(): " + describe() + "'s mesh names joint " +
                                    std::to_string(mesh_->maxJoint()) + ", the skin has " +
                                    std::to_string(skin->size()) + " joints");
    if (!skin && (!motion_ || motion_->weights.empty())) {
        motion_.reset();
    } else {
        if (!motion_) motion_ = std::make_unique<Motion>();
        motion_->skin = std::move(skin);
    }
    markDirty(kDirtyBound);
}

void Geometry::setMorphWeights(std::vector<float> weights) {
    const size_t targets = mesh_ ? mesh_->morphTargets().size() : 0;
    if (weights.size() > targets)
        throw std::invalid_argument("Geometry::setMorphWeights(): " + std::to_string(weights.size()) + " weights, " +
                                    describe() + "'s mesh has " + std::to_string(targets) + " morph targets");
    for (size_t i = 0; i < weights.size(); ++i)
        if (!std::isfinite(weights[i]))
            throw std::invalid_argument("Geometry::setMorphWeights(): weights[" + std::to_string(i) +
                                        "] is not finite");
    if (weights.empty() && (!motion_ || !motion_->skin)) {
        motion_.reset();
    } else {
        if (!motion_) motion_ = std::make_unique<Motion>();
        motion_->weights = std::move(weights);
    }
    markDirty(kDirtyBound);
}

const std::vector<float>& Geometry::morphWeights() const {
    static const std::vector<float> none;
    return motion_ ? motion_->weights : none;
}

// --- Switch
void Switch::addChild(ref_ptr<Node> child, bool on) {
    Group::addChild(std::move(child));
    on_.back() = on;
}
void Switch::setOn(size_t i, bool on) {
    if (i >= on_.size())
        throw std::out_of_range("Switch::setOn(): child " + std::to_string(i) + " of " + describe() +
                                " does not exist (" + std::to_string(on_.size()) + " children)");
    if (on_[i] == on) return;
    on_[i] = on;
    markDirty(kDirtyChoice);
}
void Switch::setAll(bool on) {
    if (std::all_of(on_.begin(), on_.end(), [on](bool b) { return b == on; })) return;
    on_.assign(on_.size(), on);
    markDirty(kDirtyChoice);
}
void Switch::setOnly(size_t i) {
    if (i >= on_.size())
        throw std::out_of_range("Switch::setOnly(): child " + std::to_string(i) + " of " + describe() +
                                " does not exist (" + std::to_string(on_.size()) + " children)");
    bool changed = false;
    for (size_t k = 0; k < on_.size(); ++k) {
        changed |= on_[k] != (k == i);
        on_[k] = k == i;
    }
    if (changed) markDirty(kDirtyChoice);
}
void Switch::childInserted(size_t i) {
    on_.insert(on_.begin() + std::ptrdiff_t(i), true);
    SG_ASSERT(on_.size() == numChildren(), "Switch::childInserted(): switch bits out of step with the children");
}
void Switch::childRemoved(size_t i) {
    on_.erase(on_.begin() + std::ptrdiff_t(i));
    SG_ASSERT(on_.size() == numChildren(), "Switch::childRemoved(): switch bits out of step with the children");
}
void Switch::accept(NodeVisitor& v) { v.apply(*this); }

// --- Billboard
void Billboard::setAxis(const dvec3& a) {
    if (!isFinite(a) || glm::length(a) == 0.0)
        throw std::invalid_argument("Billboard::setAxis(): " + describe() + ": axis must be finite and non-zero");
    axis_ = glm::normalize(a);
}

dmat4 Billboard::rotationToward(const dvec3& eyeLocal) const {
    const dvec3 a = axis_;
    dvec3 toEye = eyeLocal;
    if (mode_ == Mode::Axial) toEye -= glm::dot(toEye, a) * a;  // turn about the axis only
    const double len = glm::length(toEye);
    if (!(len > eps::kZeroLength)) return dmat4(1.0);  // eye on the axis: any orientation is right
    const dvec3 y = -toEye / len;                      // the children face -Y: -Y points at the eye
    dvec3 z = a - glm::dot(a, y) * y;
    if (glm::length(z) < eps::kParallel) z = std::abs(y.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    z = glm::normalize(z - glm::dot(z, y) * y);
    const dvec3 x = glm::cross(y, z);
    dmat4 r(1.0);
    r[0] = dvec4(x, 0.0);
    r[1] = dvec4(y, 0.0);
    r[2] = dvec4(z, 0.0);
    return r;
}
void Billboard::accept(NodeVisitor& v) { v.apply(*this); }

// --- Instance
Instance::~Instance() {
    if (proto_) proto_->removeParent(this);
}
void Instance::setPrototype(ref_ptr<Node> p) {
    if (!p) throw std::invalid_argument("Instance::setPrototype(): " + describe() + ": prototype is null");
    if (hasAncestorOrSelf(p.get()))
        throw std::invalid_argument("Instance::setPrototype(): placing " + p->describe() + " below " + describe() +
                                    " would make a cycle");
    if (proto_) proto_->removeParent(this);
    proto_ = std::move(p);
    proto_->addParent(this);
    markDirty(kDirtyStructure | kDirtyBound);
}
void Instance::setMatrix(const dmat4& m) {
    const std::string why = nonInvertibleAffine(m);
    if (!why.empty()) throw std::invalid_argument("Instance::setMatrix(): " + describe() + ": " + why);
    matrix_ = m;
    markDirty(kDirtyBound);
}
void Instance::accept(NodeVisitor& v) { v.apply(*this); }

// --- BspGroup
void BspGroup::order(const dvec3& eye, std::vector<uint32_t>& out) const {
    out.clear();
    if (nodes_.empty()) {  // not built yet: child order
        for (uint32_t i = 0; i < numChildren(); ++i) out.push_back(i);
        return;
    }
    // Iterative in-order walk: near side, the plane's own items, far side.
    struct Step {
        int32_t node;
        bool emitOnly;
        int32_t far;
    };
    std::vector<Step> stack{{0, false, -1}};
    while (!stack.empty()) {
        Step s = stack.back();
        stack.pop_back();
        const BspNode& n = nodes_[size_t(s.node)];
        if (s.emitOnly) {
            for (uint32_t k = 0; k < n.itemCount; ++k) out.push_back(items_[n.firstItem + k]);
            if (s.far >= 0) stack.push_back({s.far, false, -1});
            continue;
        }
        const bool eyeFront = n.plane.distance(eye) >= 0.0;
        const int32_t nearSide = eyeFront ? n.front : n.back, farSide = eyeFront ? n.back : n.front;
        stack.push_back({s.node, true, farSide});
        if (nearSide >= 0) stack.push_back({nearSide, false, -1});
    }
}
void BspGroup::accept(NodeVisitor& v) { v.apply(*this); }

// --- Occluder
void Occluder::setBox(const Box& b) {
    if (b.empty() || !isFinite(b.min) || !isFinite(b.max))
        throw std::invalid_argument("Occluder::setBox(): " + describe() + ": box is empty or not finite");
    box_ = b;
    polygon_.clear();
    shape_ = Shape::Box;
    markDirty(kDirtyBound);
}
void Occluder::setPolygon(std::vector<dvec3> v) {
    const std::string fn = "Occluder::setPolygon(): " + describe() + ": ";
    if (v.size() < 3) throw std::invalid_argument(fn + "needs at least 3 vertices, got " + std::to_string(v.size()));
    for (size_t i = 0; i < v.size(); ++i)
        if (!isFinite(v[i])) throw std::invalid_argument(fn + "vertex " + std::to_string(i) + " is not finite");
    // Newell normal; then every vertex on the plane and every turn the same way.
    dvec3 n(0.0);
    for (size_t i = 0; i < v.size(); ++i) n += glm::cross(v[i], v[(i + 1) % v.size()]);
    const double area2 = glm::length(n);
    if (!(area2 > 0.0)) throw std::invalid_argument(fn + "polygon has no area");
    n /= area2;
    double size = 0.0;
    for (size_t i = 1; i < v.size(); ++i) size = std::max(size, glm::length(v[i] - v[0]));
    for (size_t i = 0; i < v.size(); ++i) {
        if (std::abs(glm::dot(n, v[i] - v[0])) > eps::kCoplanar * size)
            throw std::invalid_argument(fn + "vertex " + std::to_string(i) + " is off the polygon's plane");
        const dvec3 e0 = v[(i + 1) % v.size()] - v[i], e1 = v[(i + 2) % v.size()] - v[(i + 1) % v.size()];
        if (glm::dot(glm::cross(e0, e1), n) < -eps::kRounding * size * size)
            throw std::invalid_argument(fn + "polygon is not convex at vertex " + std::to_string((i + 1) % v.size()));
    }
    box_ = Box{};
    for (const dvec3& p : v) box_.expand(p);
    polygon_ = std::move(v);
    shape_ = Shape::Polygon;
    markDirty(kDirtyBound);
}
void Occluder::setEyeOutside(const Box& b) {
    if (!b.empty() && (!isFinite(b.min) || !isFinite(b.max)))
        throw std::invalid_argument("Occluder::setEyeOutside(): " + describe() + ": box is not finite");
    eyeOutside_ = b;
    markDirty(kDirtyBound);  // the image notes which occluders carry conditions
}

void Occluder::setOpenings(std::vector<Plane> planes) {
    for (size_t k = 0; k < planes.size(); ++k) {
        const Plane& p = planes[k];
        if (!isFinite(p.n) || !std::isfinite(p.d) || std::abs(glm::length(p.n) - 1.0) > 1e-9)
            throw std::invalid_argument(
                "Occluder::setOpenings(): " + describe() + ": plane " + std::to_string(k) +
                (isFinite(p.n) && std::isfinite(p.d) ? " has a normal not of unit length" : " is not finite"));
    }
    openings_ = std::move(planes);
    markDirty(kDirtyBound);  // the image notes which occluders carry conditions
}

void Occluder::setBelowSurface(std::shared_ptr<const OccluderSurface> s) {
    if (s) {
        const std::string fn = "Occluder::setBelowSurface(): " + describe() + ": ";
        if (s->cellsX < 1 || s->cellsY < 1)
            throw std::invalid_argument(fn + "cells " + std::to_string(s->cellsX) + " x " + std::to_string(s->cellsY) +
                                        " are not at least 1 x 1");
        if (s->highest.size() != size_t(s->cellsX) * size_t(s->cellsY))
            throw std::invalid_argument(fn + std::to_string(s->highest.size()) + " heights for " +
                                        std::to_string(s->cellsX) + " x " + std::to_string(s->cellsY) + " cells");
        for (double h : s->highest)
            if (std::isnan(h)) throw std::invalid_argument(fn + "a cell's highest is NaN");
        if (!(isFinite(dvec3(s->min, 0.0)) && isFinite(dvec3(s->max, 0.0)) && s->min.x < s->max.x &&
              s->min.y < s->max.y))
            throw std::invalid_argument(fn + "the rectangle is empty or not finite");
    }
    belowSurface_ = std::move(s);
    markDirty(kDirtyBound);  // the image notes which occluders carry conditions
}

void Occluder::accept(NodeVisitor& v) { v.apply(*this); }

}  // namespace sg
