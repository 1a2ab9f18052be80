// Picking accuracy: each object drawn in its own flat colour (lighting off), then random pixels picked
// through the camera; the picked geometry must be the one drawn there, away from the id image's edges.
#pragma once
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/intersect/IntersectTraversal.h"

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace sg {
class Geometry;
}

namespace accuracy {

using IdMap = std::unordered_map<const sg::Geometry*, uint32_t>;

// Gives every Geometry below root (Instance prototypes and children not shown included) its own unlit
// material whose colour encodes its id (1, 2, ...; 0 is the background). Placements of one prototype share
// the prototype's ids. Call Scene::update() afterwards.
IdMap assignIdColors(sg::Node* root);

struct PickAgreement {
    uint64_t sampled = 0;       // pixels drawn at random
    uint64_t compared = 0;      // of those, away from id edges (the 8 neighbours have the same id)
    uint64_t agreed = 0;        // compared pixels where the pick found the geometry drawn (or nothing on background)
    uint64_t objectPixels = 0;  // compared pixels showing an object
    uint64_t coplanarTies = 0;  // agreed pixels where another geometry was hit at exactly the same distance
    std::string firstMismatch;  // view, pixel, drawn and picked ids
    double rate() const { return compared ? double(agreed) / double(compared) : 0.0; }
};

class PickHarness {
public:
    // Throws std::runtime_error when no OSMesa context can be made.
    PickHarness(int width, int height);
    // `pixelsPerView` random pixels of each view (views are resized to the harness's viewport).
    PickAgreement run(const sg::Scene& scene, const IdMap& ids, const std::vector<sg::Camera>& views, int pixelsPerView,
                      uint64_t seed);
    // The id image of one view (rows top to bottom).
    std::vector<uint32_t> idImage(const sg::Scene& scene, const sg::Camera& view);

private:
    bool isTie(const sg::Scene& scene, const sg::Camera& cam, const sg::QueryOptions& opt, int x, int y, double t,
               uint32_t drawn, const IdMap& ids);
    int w_, h_;
    sg::OsmesaContext ctx_;
    std::unique_ptr<sg::Renderer> renderer_;
    sg::CullTraversal cull_;
    sg::DrawList list_;
    sg::IntersectTraversal isect_;
};

}  // namespace accuracy
