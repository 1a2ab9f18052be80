#include "factory/Site.h"

#include "testbed/FactoryLighting.h"

#include <cstdio>

namespace factory {

scenes::Factory buildSite(const Options& o) {
    std::fprintf(stderr, "factory: building the site...\n");
    scenes::Factory f = scenes::buildFactory();
    if (o.lighting) {
        std::fprintf(stderr, "factory: lighting (sun, soft shadows, ambient occlusion)...\n");
        const std::string dir = o.cacheDir.empty() ? sg::VertexLightBaker::defaultCacheDir() : o.cacheDir;
        const scenes::FactoryLightingStats ls = scenes::bakeFactoryLighting(f, dir);
        std::fprintf(stderr, "factory: lighting %s in %.1f s (%llu vertices of %d meshes; cache %s)\n",
                     ls.cached ? "read from the cache" : "baked", ls.ms / 1000.0, (unsigned long long)ls.vertices,
                     ls.targets, dir.c_str());
    }
    return f;
}

}  // namespace factory
