#include "sg/build/LodGenerator.h"

#include "nodes/Geometry.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace sg {

namespace {

[[noreturn]] void fail(const char* fn, const std::string& why) {
    throw std::invalid_argument(std::string(fn) + ": " + why);
}

std::string num(double v) { return std::to_string(v); }

void checkInput(const char* fn, const Mesh* mesh, const std::vector<float>& ratios, float maxError) {
    if (!mesh) fail(fn, "mesh is null");
    if (mesh->triangleCount() == 0) fail(fn, "mesh has no triangles");
    // Every position, used or not: meshopt_simplifyScale measures them all.
    const std::vector<vec3>& p = mesh->positions();
    for (size_t i = 0; i < p.size(); ++i)
        if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z))
            fail(fn, "positions[" + std::to_string(i) + "] = (" + num(p[i].x) + ", " + num(p[i].y) + ", " +
                         num(p[i].z) + ") is not finite");
    for (size_t i = 0; i < ratios.size(); ++i) {
        const float r = ratios[i];
        const std::string name = "ratios[" + std::to_string(i) + "] = " + num(r);
        if (!(r > 0.0f && r < 1.0f)) fail(fn, name + " is not in (0, 1)");
        if (i > 0 && !(r < ratios[i - 1]))
            fail(fn, name + " is not below ratios[" + std::to_string(i - 1) + "] = " + num(ratios[i - 1]) +
                         " (ratios must decrease)");
    }
    if (!(maxError >= 0.0f)) fail(fn, "maxError " + num(maxError) + " is negative or NaN");
}

// Indices of one level (into the input's vertices) and meshoptimizer's relative error for them.
struct Simplified {
    std::vector<uint32_t> indices;
    float relError = 0.0f;
};

Simplified simplify(const std::vector<uint32_t>& indices, const std::vector<vec3>& positions, size_t target,
                    float relLimit) {
    // Simplification sees positions only: meshoptimizer 0.18 has no attribute-aware simplifier (that came in
    // 0.20). Its output indexes the input's vertices, so normals, UVs and colours stay with their vertex,
    // unchanged and not interpolated; vertices that share a position but not their attributes (a UV or
    // normal seam) are recognised as a seam, which is only collapsed along itself and so stays closed.
    const float* pos = &positions[0].x;
    const size_t n = positions.size(), stride = sizeof(vec3);
    Simplified s;
    s.indices.resize(indices.size());  // the worst case is no reduction at all
    size_t count = meshopt_simplify(s.indices.data(), indices.data(), indices.size(), pos, n, stride, target, relLimit,
                                    0, &s.relError);
    // It keeps the topology and so may stall well above the target (a tiny mesh, seams at every vertex).
    // Then the topology-ignoring simplifier is used if it gets closer: it may open seams, but the level is
    // near the size that was asked for. Its error estimate is its own (grid-based), still relative to the
    // scale. It clusters vertices on a grid and may overshoot to no triangle at all: then a larger target.
    if (count > target + target / 10) {
        std::vector<uint32_t> sloppy(indices.size());
        for (size_t t = target; t < count; t *= 2) {
            float sloppyError = 0.0f;
            const size_t c = meshopt_simplifySloppy(sloppy.data(), indices.data(), indices.size(), pos, n, stride, t,
                                                    relLimit, &sloppyError);
            if (c == 0) continue;
            if (c < count) {
                s.indices.swap(sloppy);
                s.relError = sloppyError;
                count = c;
            }
            break;
        }
    }
    s.indices.resize(count);
    return s;
}

// A mesh of the vertices `indices` uses (positions with their normals, UVs and colours), in first-use order.
ref_ptr<Mesh> compactMesh(const Mesh& src, std::vector<uint32_t> indices) {
    const size_t n = src.positions().size();
    std::vector<uint32_t> remap(n);
    const size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), n);
    meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), remap.data());
    auto take = [&](const auto& from) {
        std::remove_const_t<std::remove_reference_t<decltype(from)>> to;
        if (from.empty()) return to;  // attributes the input does not have stay absent
        to.resize(used);
        meshopt_remapVertexBuffer(to.data(), from.data(), n, sizeof(from[0]), remap.data());
        return to;
    };
    auto m = make<Mesh>();
    m->set(take(src.positions()), take(src.normals()), std::move(indices), take(src.uvs()), take(src.colors()));
    return m;
}

std::vector<LodLevel> levelsFor(const char* fn, const ref_ptr<Mesh>& mesh, const std::vector<float>& ratios,
                                float maxError, const LevelShading& shading) {
    checkInput(fn, mesh.get(), ratios, maxError);
    const Mesh& m = *mesh;
    std::vector<uint32_t> indices(m.indexCount());
    for (size_t i = 0; i < indices.size(); ++i) indices[i] = m.index(i);

    // meshoptimizer works with errors relative to the mesh's extent: this factor converts both ways.
    const std::vector<vec3>& positions = m.positions();
    const float scale = meshopt_simplifyScale(&positions[0].x, positions.size(), sizeof(vec3));
    float relLimit = FLT_MAX;  // no limit (also for a mesh of one point, where every error is 0)
    if (std::isfinite(maxError) && scale > 0.0f) relLimit = std::min(maxError / scale, FLT_MAX);

    std::vector<LodLevel> levels;
    levels.reserve(ratios.size() + 1);
    levels.push_back(LodLevel{mesh, 0.0f, m.triangleCount(), {}});
    std::unique_ptr<LevelReshader> reshader;
    if (shading.reshade) {
        reshader = std::make_unique<LevelReshader>(m, shading.params);
        levels.back().colors = identityColorShare(m.positions().size());
    }
    size_t simplified = m.triangleCount();  // the last level's count as simplified (before reshading)
    for (const float ratio : ratios) {
        // Each level from the full mesh, so that its error is measured against level 0, not the level before.
        const size_t target = std::max<size_t>(3, size_t(double(ratio) * double(indices.size())) / 3 * 3);
        Simplified s = simplify(indices, positions, target, relLimit);
        // A level that ends up no smaller than the one before (the simplifier stalled at both) repeats that
        // one: the same mesh, error and count, so that triangle counts never grow along the levels.
        if (s.indices.size() / 3 >= simplified) {
            levels.push_back(levels.back());
            continue;
        }
        simplified = s.indices.size() / 3;
        // Never below the previous level's error: a coarser level claiming more accuracy than a finer one
        // would put the switch distances out of order. Raising an error only moves its switch farther out.
        const float error = std::max(s.relError * scale, levels.back().error);
        ref_ptr<Mesh> level = compactMesh(m, std::move(s.indices));
        LevelColorShare colors;
        if (reshader) colors = reshader->reshade(*level);
        const uint32_t triangles = level->triangleCount();
        levels.push_back(LodLevel{std::move(level), error, triangles, std::move(colors)});
    }
    return levels;
}

}  // namespace

std::vector<LodLevel> generateLevels(const ref_ptr<Mesh>& mesh, const std::vector<float>& ratios, float maxError,
                                     const LevelShading& shading) {
    return levelsFor("generateLevels()", mesh, ratios, maxError, shading);
}

namespace {

void checkView(const char* fn, double pixelError, double pixelsPerRadian) {
    if (!(pixelError > 0.0 && std::isfinite(pixelError)))
        fail(fn, "pixelError " + num(pixelError) + " is not positive and finite");
    if (!(pixelsPerRadian > 0.0 && std::isfinite(pixelsPerRadian)))
        fail(fn, "pixelsPerRadian " + num(pixelsPerRadian) + " is not positive and finite");
}

ref_ptr<LOD> lodOf(const std::vector<LodLevel>& levels, const ref_ptr<Material>& material, double pixelError,
                   double pixelsPerRadian) {
    // Level i is good enough from the distance where its error subtends pixelError pixels (small angles:
    // pixels = error * pixelsPerRadian / distance). Rounded up to the next float, so that at the switch
    // distance the projected error is at most pixelError, not a rounding above it.
    const float kFar = FLT_MAX;
    std::vector<float> from(levels.size(), 0.0f);
    for (size_t i = 1; i < levels.size(); ++i) {
        const double d = double(levels[i].error) * pixelsPerRadian / pixelError;
        float f = d < double(kFar) ? float(d) : kFar;
        if (double(f) < d && f < kFar) f = std::nextafter(f, kFar);
        from[i] = f;
    }
    auto lod = make<LOD>();
    for (size_t i = 0; i < levels.size(); ++i) {
        lod->addChild(make<Geometry>(levels[i].mesh, material), from[i], i + 1 < levels.size() ? from[i + 1] : kFar);
        lod->setError(i, levels[i].error);
    }
    return lod;
}

}  // namespace

ref_ptr<LOD> makeLod(ref_ptr<Mesh> mesh, ref_ptr<Material> material, const std::vector<float>& ratios,
                     double pixelError, double pixelsPerRadian) {
    const char* fn = "makeLod()";
    checkView(fn, pixelError, pixelsPerRadian);
    const std::vector<LodLevel> levels = levelsFor(fn, mesh, ratios, std::numeric_limits<float>::infinity(), {});
    return lodOf(levels, material, pixelError, pixelsPerRadian);
}

ref_ptr<LOD> makeLod(const std::vector<LodLevel>& levels, ref_ptr<Material> material, double pixelError,
                     double pixelsPerRadian) {
    const char* fn = "makeLod()";
    checkView(fn, pixelError, pixelsPerRadian);
    if (levels.empty()) fail(fn, "no levels");
    for (size_t i = 0; i < levels.size(); ++i) {
        if (!levels[i].mesh) fail(fn, "levels[" + std::to_string(i) + "].mesh is null");
        if (i > 0 && !(levels[i].error >= levels[i - 1].error))
            fail(fn, "levels[" + std::to_string(i) + "].error " + num(levels[i].error) + " is below the level before");
    }
    return lodOf(levels, material, pixelError, pixelsPerRadian);
}

}  // namespace sg
