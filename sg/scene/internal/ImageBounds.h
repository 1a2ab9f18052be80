// Scene::Builder's bounds: an entry's bound from its node or its children's, and what a kind derives from them
// once its children are written (an LOD's centre, a PagedLOD's reach and detail, a wide Group's spheres, a
// Billboard's sphere, a BspGroup's tree). Inline: run once per entry by both the full build and the refit.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/Transform.h"
#include "sg/scene/internal/BspBuilder.h"
#include "sg/scene/internal/ImageBuilder.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sg {

inline void Scene::Builder::leafBound(uint32_t i, const Box& local, bool valid, const dmat4& m) {
    if (!valid) {
        img.setInvalid(i);
        return;
    }
    img.setBound(i, transformBox(m, local), glm::length(local.halfExtent()) * maxScale(m));
}

inline void Scene::Builder::boundFromChildren(uint32_t i) {
    Box b;
    bool invalid = false;
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) {
        if (img.flags[j] & FlatImage::kInvalid) invalid = true;
        if (img.flags[j] & (FlatImage::kEmpty | FlatImage::kInvalid)) continue;
        b.expand(img.box(j));
    }
    if (invalid) return img.setInvalid(i);
    double rad = 0.0;
    const dvec3 c = b.center();
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j])
        if (!(img.flags[j] & FlatImage::kEmpty)) rad = std::max(rad, glm::length(img.center(j) - c) + img.r[j]);
    img.setBound(i, b, rad);
}

// Entry i's bound grown to hold a world box and the sphere of radius `r` about that box's centre.
inline void Scene::Builder::expandBound(uint32_t i, const Box& add, double r) {
    const bool empty = img.flags[i] & FlatImage::kEmpty;
    Box b = add;
    if (!empty) b.expand(img.box(i));
    const dvec3 bc = b.center();
    double rad = r + glm::length(add.center() - bc);
    if (!empty) rad = std::max(rad, glm::length(img.center(i) - bc) + img.r[i]);
    img.setBound(i, b, rad);
}

// Largest distance of anything below `n` from the origin of the frame `m` maps from.
inline double Scene::Builder::localRadius(const Node* n, const dmat4& m) {
    switch (n->kind()) {
        case NodeKind::Geometry: {
            const Mesh* mesh = static_cast<const Geometry*>(n)->mesh();
            if (!mesh || mesh->box().empty()) return 0.0;
            if (!mesh->validBound()) return kInf;
            const Box b = transformBox(m, mesh->box());
            return glm::length(glm::max(glm::abs(b.min), glm::abs(b.max)));
        }
        case NodeKind::Transform: {
            double r = 0.0;
            const dmat4 mm = static_cast<const Transform*>(n)->apply(m);
            for (size_t i = 0; i < n->numChildren(); ++i) r = std::max(r, localRadius(n->child(i), mm));
            return r;
        }
        case NodeKind::Instance: {
            const auto* in = static_cast<const Instance*>(n);
            return in->prototype() ? localRadius(in->prototype(), m * in->matrix()) : 0.0;
        }
        default: {
            double r = 0.0;
            for (size_t i = 0; i < n->numChildren(); ++i) r = std::max(r, localRadius(n->child(i), m));
            return r;
        }
    }
}

// A billboard turns about its origin: bound it, and everything below it, by a sphere there.
inline void Scene::Builder::billboard(uint32_t i, Node* n, const dmat4& m) {
    if (img.flags[i] & FlatImage::kEmpty) return;
    const double rl = localRadius(n, dmat4(1.0));
    const dvec3 o(m[3]);
    const double rad = rl * maxScale(m);
    for (uint32_t j = i; j < img.end[i]; ++j) {
        if (!std::isfinite(rad)) {
            img.setInvalid(j);
        } else {
            img.setBound(j, Box{o - dvec3(rad), o + dvec3(rad)}, rad);
        }
        if (j > i) img.flags[j] |= FlatImage::kNoTest;
    }
}

inline void Scene::Builder::bsp(uint32_t i, Node* n, const dmat4& m) {
    auto* g = static_cast<BspGroup*>(n);
    const dmat4 inv = glm::inverse(m);
    std::vector<Box> boxes;
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j])
        boxes.push_back(img.flags[j] & (FlatImage::kEmpty | FlatImage::kInvalid) ? Box{}
                                                                                 : transformBox(inv, img.box(j)));
    buildBsp(*g, boxes);
}

// The LOD's centre in image coordinates: the user's centre through the frame, or the bound's centre.
inline void Scene::Builder::lodCenter(uint32_t i, const LOD* l, const dmat4& m) {
    FlatImage::Lod& lod = img.lods[img.aux[i]];
    const dvec3 c = l->userCenter() ? dvec3(m * dvec4(l->center(), 1.0)) - img.origin : img.center(i) - img.origin;
    lod.cx = float(c.x);
    lod.cy = float(c.y);
    lod.cz = float(c.z);
}

// A PagedLOD after its coarse children: its bound grows by the sphere its detail will take, its centre is
// placed like an LOD's, then its detail's own image is built (`rebuild`, or when missing or changed) in this
// image's frame and bounded too. The centre leaves the detail out, so that attaching it never moves the
// value that decides whether it is wanted.
inline void Scene::Builder::paged(uint32_t i, const PagedLOD* p, const dmat4& m, bool rebuild) {
    if (p->radius() > 0.0 && !(img.flags[i] & FlatImage::kInvalid)) {
        const dvec3 c(m * dvec4(p->center(), 1.0));
        expandBound(i, Box{c - dvec3(p->radius() * maxScale(m)), c + dvec3(p->radius() * maxScale(m))},
                    p->radius() * maxScale(m));
    }
    FlatImage::Paged& pg = img.paged[img.aux[i]];
    const dvec3 c = p->userCenter() ? dvec3(m * dvec4(p->center(), 1.0)) - img.origin : img.center(i) - img.origin;
    pg.lod.cx = float(c.x);
    pg.lod.cy = float(c.y);
    pg.lod.cz = float(c.z);
    pg.lod.reach = float(p->radius() * maxScale(m));
    pg.lod.fade = float(maxScale(m));
    pg.frame = m;
    Node* d = p->detail();
    if (!d) {
        pg.detail.reset();
        return;
    }
    if (rebuild || !pg.detail || d->dirtyBits()) detailImage(p, d, m, pg, rebuild);
    const FlatImage& di = *pg.detail;
    if (di.size() == 0 || (di.flags[0] & FlatImage::kEmpty)) return;
    if (di.flags[0] & FlatImage::kInvalid) return img.setInvalid(i);
    if (!(img.flags[i] & FlatImage::kInvalid)) expandBound(i, di.box(0), di.r[0]);
}

// A plain Group with many children over a large subtree: its children's spheres side by side.
inline void Scene::Builder::wide(uint32_t i, Node* n) {
    if (n->kind() != NodeKind::Group || n->numChildren() < kWideChildren || img.end[i] - i <= kWideEntries) return;
    if (fresh) {
        img.aux[i] = uint32_t(img.wides.size() + 1);
        img.wides.push_back({uint32_t(img.wideEntry.size()), uint32_t(n->numChildren())});
        for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) {
            img.wideEntry.push_back(j);
            img.wcx.push_back(0), img.wcy.push_back(0), img.wcz.push_back(0), img.wr.push_back(0);
        }
    }
    const FlatImage::Wide& w = img.wides[img.aux[i] - 1];
    for (uint32_t k = 0; k < w.count; ++k) {
        const uint32_t j = img.wideEntry[w.first + k];
        img.wcx[w.first + k] = img.cx[j];
        img.wcy[w.first + k] = img.cy[j];
        img.wcz[w.first + k] = img.cz[j];
        img.wr[w.first + k] = img.r[j];
    }
}

}  // namespace sg
