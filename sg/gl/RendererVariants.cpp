// Renderer: the shader variants a graph's draws take, compiled and readied ahead of the frames that draw them
// (prepareVariants, and prepare() for paged details), so that no frame compiles a program.
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/DrawUseWalk.h"
#include "sg/gl/internal/GpuCache.h"
#include "sg/gl/internal/Shaders.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <utility>

namespace sg {

std::vector<Renderer::DrawUse> Renderer::drawUses(const Node& root) {
    std::vector<DrawUse> uses;
    DrawUseWalk(root).run([&](DrawUse u) { uses.push_back(std::move(u)); }, [] { return false; });
    return uses;
}

// The same shadings draw() gives the use's runs (runShading): whole, dissolving where an LOD can fade it (any
// fade below 1 takes the same variant), and its outline's.
void Renderer::coldKeys(const DrawUse& u, std::vector<uint64_t>& cold) const {
    const Mesh& mesh = *u.mesh;
    if (mesh.primitiveCount() == 0) return;  // never drawn
    const GpuMesh g = describeMesh(mesh);
    const Material* mat = u.material.get();
    const bool blend = mat && mat->blend;
    // As gpuSkinned(): more joints than the GPU's block holds are skinned on the CPU, and drawn unskinned.
    const bool skinned = u.joints > 0 && u.joints <= uint32_t(kMaxJoints) && g.influences > 0;
    auto add = [&](const Shading& s) {
        const uint64_t k = warmKey(variantKey(s), blend);
        if (!warmed_.count(k) && std::find(cold.begin(), cold.end(), k) == cold.end()) cold.push_back(k);
    };
    for (const float fade : {1.0f, 0.5f}) {
        if (fade < 1.0f && !u.fades) break;
        const Shading s = runShading(g, mesh, mat, fade, skinned);
        add(s);
        if (g.outlineCount > 0) add(outlineShading(s));
    }
}

size_t Renderer::prepareVariants(const std::vector<DrawUse>& uses, const Camera& camera) {
    const size_t before = variants_.size();
    // One use for each variant not ready yet: a scene of many Geometries and few variants draws a handful.
    std::vector<const DrawUse*> draw;
    std::unordered_set<uint64_t> claimed;
    std::vector<uint64_t> cold;
    for (const DrawUse& u : uses) {
        if (!u.mesh) continue;
        cold.clear();
        coldKeys(u, cold);
        bool fresh = false;
        for (const uint64_t k : cold) fresh = claimed.insert(k).second || fresh;
        if (fresh) draw.push_back(&u);
    }
    if (!draw.empty()) warmDraw(draw, camera);
    return variants_.size() - before;
}

// A draw as the frame's draws are made (the same runs, state, textures and framebuffer), so that a software
// rasterizer compiles the code they will take; each item's vertices all lie at one point behind the eye, so that
// no pixel is reached but the viewport's clear.
void Renderer::warmDraw(const std::vector<const DrawUse*>& uses, const Camera& camera) {
    DrawList list;
    std::vector<ref_ptr<Pose>> poses;  // alive through the draw
    const double behind = 2.0 * (std::abs(camera.nearDistance()) + 1.0) + 1.0;
    glm::mat4x3 model(0.0f);
    model[3] = vec3(-camera.viewDirection() * behind);
    for (const DrawUse* u : uses) {
        for (int fading = 0; fading < (u->fades ? 2 : 1); ++fading) {
            const uint32_t i = uint32_t(list.items.size());
            DrawItem it;
            it.mesh = u->mesh.get();
            it.material = u->material.get();
            it.model = model;
            list.items.push_back(it);
            if (fading) list.fades.emplace_back(i, 0.5f);
            if (u->joints > 0 && u->joints <= uint32_t(kMaxJoints)) {
                ref_ptr<Pose> pose = make<Pose>();
                pose->joints.assign(u->joints, glm::mat4x3(0.0f));  // every vertex skinned to the anchor
                list.poses.emplace_back(i, pose.get());
                poses.push_back(std::move(pose));
            }
        }
    }
    // Not the frame's: no occlusion boxes after the items, and its compiles are not counted as the frame's.
    struct Restore {
        Renderer& r;
        AfterItems after;
        ~Restore() {
            r.afterItems_ = std::move(after);
            r.warming_ = false;
        }
    } restore{*this, std::move(afterItems_)};
    afterItems_ = nullptr;
    warming_ = true;
    draw(list, camera, Viewport{0, 0, 1, 1});
    std::vector<uint64_t> cold;
    for (const DrawUse* u : uses) coldKeys(*u, cold);
    warmed_.insert(cold.begin(), cold.end());
}

}  // namespace sg
