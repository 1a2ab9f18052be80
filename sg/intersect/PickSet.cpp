#include "sg/intersect/PickSet.h"

#include <stdexcept>
#include <string>

namespace sg {

Ray pixelRay(const Camera& cam, double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y))
        throw std::invalid_argument("pixelRay(): pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                    ") is not finite");
    // Through the eye-relative clip matrix, as the renderer draws: the eye's large coordinates stay out.
    const dmat4 inv = glm::inverse(cam.projection() * cam.viewRotation());
    const double nx = 2.0 * x / cam.width() - 1.0, ny = 1.0 - 2.0 * y / cam.height();
    const dvec4 a = inv * dvec4(nx, ny, -1.0, 1.0), b = inv * dvec4(nx, ny, 1.0, 1.0);
    const dvec3 nearRel = dvec3(a) / a.w, farRel = dvec3(b) / b.w;
    return Ray{cam.eye() + nearRel, farRel - nearRel, 1.0};
}

std::string pathString(const std::vector<Node*>& path) {
    std::string s;
    for (const Node* n : path) s += (s.empty() ? "" : " / ") + n->describe();
    return s;
}

void PickSet::add(Node* node) {
    if (!node) throw std::invalid_argument("PickSet::add(): node is null");
    nodes_[node] = node;
}

bool PickSet::remove(const Node* node) { return nodes_.erase(node) != 0; }

Node* PickSet::resolve(const std::vector<Node*>& path) const {
    for (auto it = path.rbegin(); it != path.rend(); ++it)
        if (nodes_.count(*it)) return *it;
    return nullptr;
}

PickSet::Result PickSet::pick(IntersectTraversal& t, const Scene& scene, const Camera& cam, double x, double y,
                              QueryOptions opt) const {
    if (!opt.camera) {
        opt.camera = &cam;
        opt.lod = LodChoice::AsDrawn;
    }
    Result r;
    r.hit = t.intersect(scene, pixelRay(cam, x, y), opt, r.nearest);
    if (r.hit) r.object = resolve(r.nearest.path);
    return r;
}

}  // namespace sg
