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
    return p;
}

DirectionalLight factoryLight(int workshop) {
    if (workshop < 0) {
        // Daylight: a warm sun, and a bluish sky for the ambient term (the baked occlusion scales it).
        return DirectionalLight::sun(vec3(factoryLightParams().sunDirection), vec3(0.50f, 0.54f, 0.62f),
                                     vec3(0.78f, 0.74f, 0.66f));
    }
    // Inside a workshop: the north-light glazing of the sawtooth roof, from above and the north, cooler
    // and softer than the sun; no baked shadows there (nothing inside is baked).
    return DirectionalLight::sun(vec3(0.0f, 0.5f, 0.87f), vec3(0.48f, 0.5f, 0.54f), vec3(0.55f, 0.56f, 0.58f));
}

FactoryLightingStats bakeFactoryLighting(Factory& f, const std::string& cacheDir, uint32_t seed) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<BakeTarget> targets;
    // The colours now carry occlusion and sun visibility, which only a bakedLight material reads so. One
    // copy per material keeps the draw batches as they were.
    std::map<Material*, ref_ptr<Material>> baked;
    auto add = [&](Node* n, const dmat4& world) {
        if (n->kind() != NodeKind::Geometry) return;
        auto* g = static_cast<Geometry*>(n);
        targets.push_back({ref_ptr<Mesh>(g->mesh()), world});
        if (!g->material()) return;
        ref_ptr<Material>& m = baked[g->material()];
        if (!m) {
            const Material& from = *g->material();
            m = make<Material>(from.baseColor, from.texture);
            m->unlit = from.unlit;
            m->alphaCutoff = from.alphaCutoff;
            m->specular = from.specular;
            m->shininess = from.shininess;
            m->bakedLight = true;
        }
        g->setMaterial(m);
    };
    // The finest level of every tile is baked; its coarse levels take their light from it afterwards. Rays of
    // their own would start under the ground wherever a coarse surface dips below the fine one (black
    // patches), and a shadow caught by one coarse vertex would spread over its whole fan.
    for (size_t i = 0; i < f.terrain->numChildren(); ++i) add(f.terrain->child(i)->child(0), dmat4(1.0));
    // A building's detailed level likewise: a coarse level's vertices would sample the light on its simplified
    // faces, which run behind the detailed walls (black from its switch distance on).
    for (const FactoryBuilding& b : f.buildings) {
        add(b.lod->child(0), b.place->matrix());
        add(b.roof.get(), b.place->matrix());
    }
    FactoryLightingStats st;
    st.targets = int(targets.size());
    for (const BakeTarget& t : targets) st.vertices += t.mesh->positions().size();
    // The shadows are cast by the outside as the day shows it: interiors off, whatever the caller had set.
    setFactoryEye(f, -1);
    Scene scene(f.root);
    scene.update();
    st.cached = VertexLightBaker::bakeCached(scene, targets, factoryLightParams(), seed, cacheDir);
    shareTerrainColors(f);
    shareBuildingColors(f);
    std::vector<Node*> lods;
    for (size_t i = 0; i < f.terrain->numChildren(); ++i) lods.push_back(f.terrain->child(i));
    for (const FactoryBuilding& b : f.buildings) lods.push_back(b.lod.get());
    for (Node* lod : lods) {
        for (size_t k = 1; k < lod->numChildren(); ++k) {
            auto* g = static_cast<Geometry*>(lod->child(k));
            g->setMaterial(static_cast<Geometry*>(lod->child(0))->material());
            st.vertices += g->mesh()->positions().size();
        }
    }
    st.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return st;
}

}  // namespace scenes
