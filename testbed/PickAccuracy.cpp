#include "testbed/PickAccuracy.h"

#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "sg/intersect/PickSet.h"
#include "testbed/RandomScene.h"

#include <unordered_set>

namespace accuracy {

using namespace sg;

namespace {
void assign(Node* n, IdMap& ids, std::unordered_set<const Node*>& seen) {
    if (!seen.insert(n).second) return;
    if (n->kind() == NodeKind::Geometry) {
        auto* g = static_cast<Geometry*>(n);
        const uint32_t id = uint32_t(ids.size() + 1);
        ids[g] = id;
        auto m = make<Material>(
            vec4(float(id & 255) / 255.0f, float((id >> 8) & 255) / 255.0f, float((id >> 16) & 255) / 255.0f, 1.0f));
        m->unlit = true;
        g->setMaterial(m);
        return;
    }
    for (size_t i = 0; i < n->numChildren(); ++i)
        assign(n->child(i), ids, seen);  // an Instance's child is its prototype
}
}  // namespace

IdMap assignIdColors(Node* root) {
    IdMap ids;
    std::unordered_set<const Node*> seen;
    assign(root, ids, seen);
    return ids;
}

// Coplanar overlapping faces (boxes side by side on one floor) are hit at the same distance; the depth
// test shows whichever was drawn first. The drawn one among the hits at the picked distance is right.
bool PickHarness::isTie(const Scene& scene, const Camera& cam, const QueryOptions& opt, int x, int y, double t,
                        uint32_t drawn, const IdMap& ids) {
    std::vector<Hit> all;
    isect_.intersectAll(scene, pixelRay(cam, x + 0.5, y + 0.5), opt, all);
    for (const Hit& h : all) {
        if (h.t > t * (1.0 + 1e-12)) break;
        auto it = ids.find(h.geometry);
        if (it != ids.end() && it->second == drawn) return true;
    }
    return false;
}

PickHarness::PickHarness(int w, int h) : w_(w), h_(h), ctx_(w, h), renderer_(std::make_unique<Renderer>()) {}

std::vector<uint32_t> PickHarness::idImage(const Scene& scene, const Camera& view) {
    CullSettings s;
    s.occlusion.mode = OcclusionMode::Off;
    CullStats st;
    cull_.cull(scene, view, s, list_, st);
    renderer_->draw(list_, view, vec4(0.0f, 0.0f, 0.0f, 1.0f));
    const Image img = renderer_->readColor();
    std::vector<uint32_t> ids(size_t(img.width) * size_t(img.height));
    for (size_t p = 0; p < ids.size(); ++p)
        ids[p] = uint32_t(img.rgba[4 * p]) | uint32_t(img.rgba[4 * p + 1]) << 8 | uint32_t(img.rgba[4 * p + 2]) << 16;
    return ids;
}

PickAgreement PickHarness::run(const Scene& scene, const IdMap& ids, const std::vector<Camera>& views,
                               int pixelsPerView, uint64_t seed) {
    scenes::Rng rng(seed);
    PickAgreement r;
    for (size_t v = 0; v < views.size(); ++v) {
        Camera cam = views[v];
        cam.setViewport(w_, h_);
        const std::vector<uint32_t> img = idImage(scene, cam);
        QueryOptions opt;
        opt.camera = &cam;
        opt.lod = LodChoice::AsDrawn;
        for (int k = 0; k < pixelsPerView; ++k) {
            const int x = 1 + rng.below(w_ - 2), y = 1 + rng.below(h_ - 2);
            r.sampled++;
            const uint32_t drawn = img[size_t(y) * size_t(w_) + size_t(x)];
            bool edge = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) edge |= img[size_t(y + dy) * size_t(w_) + size_t(x + dx)] != drawn;
            if (edge) continue;
            r.compared++;
            if (drawn) r.objectPixels++;
            Hit h;
            uint32_t picked = 0;
            if (isect_.intersect(scene, pixelRay(cam, x + 0.5, y + 0.5), opt, h)) {
                auto it = ids.find(h.geometry);
                picked = it == ids.end() ? ~0u : it->second;
            }
            if (picked != drawn && drawn && picked && isTie(scene, cam, opt, x, y, h.t, drawn, ids)) {
                r.coplanarTies++;
                picked = drawn;
            }
            if (picked == drawn) {
                r.agreed++;
            } else if (r.firstMismatch.empty()) {
                r.firstMismatch = "view " + std::to_string(v) + " pixel (" + std::to_string(x) + ", " +
                                  std::to_string(y) + ") drawn " + std::to_string(drawn) + " picked " +
                                  std::to_string(picked);
            }
        }
    }
    return r;
}

}  // namespace accuracy
