#include "testbed/FactoryLighting.h"

#include "nodes/Geometry.h"

#include <chrono>
#include <cmath>
#include <map>

using namespace sg;

namespace scenes {

VertexLightParams factoryLightParams() {
    VertexLightParams p;
    const double elev = 40.0 * M_PI / 180.0, azim = 225.0 * M_PI / 180.0;  // from the south-west
    p.sunDirection = dvec3(std::cos(elev) * std::cos(azim), std::cos(elev) * std::sin(azim), std::sin(elev));
    p.sunAngularRadius = 0.03;
    p.sunSamples = 8;
    p.aoSamples = 16;
    p.aoDistance = 10.0;
    p.sunDistance = 2000.0;
    p.offset = 0.05;
    p.ambient = 0.55f;
    p.direct = 0.65f;
    return p;
}

FactoryLightingStats bakeFactoryLighting(Factory& f, const std::string& cacheDir, uint32_t seed) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<BakeTarget> targets;
    // The baked colours hold all the light: drawn unlit, else the renderer's own light would shade them
    // twice. One unlit copy per material keeps the draw batches as they were.
    std::map<Material*, ref_ptr<Material>> unlit;
    auto add = [&](Node* n, const dmat4& world) {
        if (n->kind() != NodeKind::Geometry) return;
        auto* g = static_cast<Geometry*>(n);
        targets.push_back({ref_ptr<Mesh>(g->mesh()), world});
        if (!g->material()) return;
        ref_ptr<Material>& m = unlit[g->material()];
        if (!m) {
            m = make<Material>(g->material()->baseColor, g->material()->texture);
            m->alphaCutoff = g->material()->alphaCutoff;
            m->unlit = true;
        }
        g->setMaterial(m);
    };
    // The finest level of every tile is baked; its coarse levels take their light from it afterwards. Rays of
    // their own would start under the ground wherever a coarse surface dips below the fine one (black
    // patches), and a shadow caught by one coarse vertex would spread over its whole fan.
    for (size_t i = 0; i < f.terrain->numChildren(); ++i) add(f.terrain->child(i)->child(0), dmat4(1.0));
    for (const FactoryBuilding& b : f.buildings)
        for (size_t i = 0; i < b.lod->numChildren(); ++i) add(b.lod->child(i), b.place->matrix());
    FactoryLightingStats st;
    st.targets = int(targets.size());
    for (const BakeTarget& t : targets) st.vertices += t.mesh->positions().size();
    // The shadows are cast by the outside as the day shows it: interiors off, whatever the caller had set.
    setFactoryEye(f, -1);
    Scene scene(f.root);
    scene.update();
    st.cached = VertexLightBaker::bakeCached(scene, targets, factoryLightParams(), seed, cacheDir);
    shareTerrainColors(f);
    for (size_t i = 0; i < f.terrain->numChildren(); ++i) {
        Node* tile = f.terrain->child(i);
        for (size_t k = 1; k < tile->numChildren(); ++k) {
            auto* g = static_cast<Geometry*>(tile->child(k));
            g->setMaterial(static_cast<Geometry*>(tile->child(0))->material());
            st.vertices += g->mesh()->positions().size();
        }
    }
    st.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return st;
}

}  // namespace scenes
