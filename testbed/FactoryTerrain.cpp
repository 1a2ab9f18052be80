// The factory's terrain: the height field (a flat yard in rolling hills, the stream's channel), its tiles through
// sg::buildTerrain, the ground height for walking, and the coarse levels' colours after baked light.
#include "testbed/FactoryBuild.h"

#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "sg/build/LodGenerator.h"
#include "sg/build/TerrainBuilder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace scenes {

namespace factory {

namespace {

// The terrain's height field: heights at the (n + 1)^2 points of a grid of n x n cells over the square
// [-half, half]^2, each cell split along its (i, j)-(i+1, j+1) diagonal.
struct HeightField {
    int n = 0;
    double half = 0.0, cell = 0.0;
    std::vector<double> h;
    double at(int i, int j) const { return h[size_t(j) * size_t(n + 1) + size_t(i)]; }
    // At grid coordinates (gx, gy) in [0, n]^2: the plane of the cell's triangle that holds the point.
    double interpolate(double gx, double gy) const {
        const int i = std::min(int(gx), n - 1), j = std::min(int(gy), n - 1);
        const double u = gx - i, v = gy - j;
        const double h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
        return u >= v ? h00 + u * (h10 - h00) + v * (h11 - h10) : h00 + v * (h01 - h00) + u * (h11 - h01);
    }
};

// Grass, darker in the hollows, browner on the stream banks and the high ground.
vec4 grassColor(double z) {
    const float g = float(std::clamp(z / 30.0, -0.1, 1.0));
    const float bank = z < -0.3 ? 1.0f : 0.0f;
    return glm::mix(vec4(0.33f + 0.15f * g, 0.55f - 0.1f * g, 0.22f, 1.0f), vec4(0.45f, 0.38f, 0.25f, 1.0f), bank);
}

// Levels per terrain tile: the full grid, then 2, 4 and 8 times coarser (fewer for a tile too small to have them
// all).
constexpr int kTerrainLevels = 4;

}  // namespace

// Terrain: a flat yard (radius ~210 m) in rolling hills, a stream channel cut through both.
void addTerrain(FactorySite& site) {
    const FactoryParams& prm = site.prm;
    Factory& f = site.f;
    const ref_ptr<Group>& outside = site.outside;
    for (double& p : site.ph) p = site.rng.uniform(0, 6.28);
    auto ground = [&](double x, double y) {
        const double dx = (x - site.streamX(y)) / 8.0;
        const double cut = std::abs(dx) < 1.0 ? 1.8 * (1.0 - dx * dx) * (1.0 - dx * dx) : 0.0;
        return site.hills(x, y) - cut;
    };
    auto field = std::make_shared<HeightField>();
    field->n = prm.terrainCells;
    field->half = prm.siteSize / 2.0;
    field->cell = prm.siteSize / field->n;
    const int N = field->n;
    const double half = site.half = field->half, cell = field->cell;
    field->h.resize(size_t(N + 1) * size_t(N + 1));
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) field->h[size_t(j) * (N + 1) + i] = ground(-half + i * cell, -half + j * cell);
    // The finest level's surface: each cell split along its (i, j)-(i+1, j+1) diagonal, as the mesh is.
    f.terrainHeight = [field](double x, double y) {
        const int n = field->n;
        double gx = (x + field->half) / field->cell, gy = (y + field->half) / field->cell;
        // Vertices are stored in float: one on the edge may land a rounding step outside it.
        const double slack = 1e-5 * n;
        if (!(gx >= -slack && gy >= -slack && gx <= n + slack && gy <= n + slack)) return 0.0;
        return field->interpolate(std::clamp(gx, 0.0, double(n)), std::clamp(gy, 0.0, double(n)));
    };
    // Each tile an LOD of its levels (sg::buildTerrain), in the site's frame like the rest of the factory.
    TerrainParams tp;
    tp.tileSamples = N / prm.terrainTiles + 1;
    tp.levels = kTerrainLevels;
    tp.pixelError = prm.pixelError;
    tp.pixelsPerRadian = kDefaultPixelsPerRadian;
    tp.material = texturedMaterial(factoryGrassTexture(prm.seed), 8.0f);
    tp.flat = true;
    tp.originInVertices = true;
    tp.uv = [](const dvec3& p) { return vec2(float(p.x), float(p.y)) / kFactoryGrassMetres; };
    tp.color = [](const dvec3& p) { return grassColor(p.z); };
    f.terrain = buildTerrain(field->h, N + 1, cell, dvec3(-half, -half, 0.0), tp).root;
    for (size_t t = 0; t < f.terrain->numChildren(); ++t) {
        LOD& lod = static_cast<LOD&>(*f.terrain->child(t));
        lod.setName("terrain tile");
        lod.setTransition(float(prm.fadeFraction * lod.range(0).max));
    }
    outside->addChild(f.terrain);
}

}  // namespace factory

using namespace sg;

void shareTerrainColors(Factory& f) {
    for (size_t t = 0; t < f.terrain->numChildren(); ++t) {
        Node& tile = *f.terrain->child(t);
        const Mesh& fine = *static_cast<Geometry&>(*tile.child(0)).mesh();
        const std::vector<vec3>& fp = fine.positions();
        const std::vector<vec4>& fc = fine.colors();
        const int side = int(std::lround(std::sqrt(double(fp.size())))), per = side - 1;
        const std::vector<int> cells = terrainLevelCells(per, factory::kTerrainLevels);
        if (per < 1 || fc.size() != fp.size() || cells.size() != tile.numChildren())
            throw std::invalid_argument("scenes::shareTerrainColors(): terrain tile " + std::to_string(t) +
                                        " is not as buildFactory() made it");
        const double x0 = fp[0].x, y0 = fp[0].y, step = (double(fp[size_t(per)].x) - x0) / per;
        LOD& lod = static_cast<LOD&>(tile);
        for (size_t level = 1; level < tile.numChildren(); ++level) {
            Mesh& m = *static_cast<Geometry&>(*tile.child(level)).mesh();
            // Half the level's spacing, in cells: the neighbourhood an inner vertex stands for.
            const int r = int(std::lround(0.5 * per / cells[level]));
            std::vector<vec4> col(m.positions().size());
            // The level's light as an error in metres, for the LOD budget's valuation: a shadow's edge that
            // a coarse vertex blurs over its neighbourhood counts as an edge that far out of place, scaled by
            // how much the colour changes there (the worst channel's difference from the mean, 0-1). The
            // geometry can be exact (a flat yard) while the shadow of the building beside it is lost.
            float worst = 0.0f;
            for (size_t v = 0; v < col.size(); ++v) {
                const int li = int(std::lround((m.positions()[v].x - x0) / step)),
                          lj = int(std::lround((m.positions()[v].y - y0) / step));
                if (li == 0 || lj == 0 || li == per || lj == per) {  // the shared border: exactly the finest
                    col[v] = fc[size_t(lj * side + li)];
                    continue;
                }
                vec4 sum(0.0f);
                int n = 0;
                for (int j = std::max(0, lj - r); j <= std::min(per, lj + r); ++j)
                    for (int i = std::max(0, li - r); i <= std::min(per, li + r); ++i, ++n)
                        sum += fc[size_t(j * side + i)];
                col[v] = sum / float(n);
                for (int j = std::max(0, lj - r); j <= std::min(per, lj + r); ++j)
                    for (int i = std::max(0, li - r); i <= std::min(per, li + r); ++i) {
                        const vec4 d = glm::abs(fc[size_t(j * side + i)] - col[v]);
                        worst = std::max({worst, d.r, d.g, d.b});
                    }
            }
            const float light = worst * float(step * per / cells[level]);
            lod.setError(level, std::max({lod.error(level), lod.error(level - 1), light}));
            std::vector<uint32_t> idx(m.indexCount());
            for (size_t i = 0; i < idx.size(); ++i) idx[i] = m.index(i);
            m.set(m.positions(), m.normals(), std::move(idx), m.uvs(), std::move(col));
        }
    }
}

}  // namespace scenes
