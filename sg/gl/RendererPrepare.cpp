// Renderer: the GPU cache seen from outside: uploads and shader variants ahead of a detail's first draw within a
// budget (prepare), and the release of what is no longer drawn.
#include "sg/gl/Renderer.h"

#include "nodes/Geometry.h"

#include "sg/gl/internal/DrawUseWalk.h"
#include "sg/gl/internal/GpuCache.h"

namespace sg {

bool Renderer::prepare(const Node& root, PrepareBudget& budget) {
    ++prepareCalls_;
    auto found = prepareLists_.find(&root);
    if (found == prepareLists_.end()) {  // the first call for this detail: list what draw() would upload
        PrepareList list;
        list.root = &root;
        list.walk = std::make_shared<DrawUseWalk>(root);
        found = prepareLists_.emplace(&root, std::move(list)).first;
    }
    PrepareList& list = found->second;
    list.touched = prepareCalls_;
    // Listing a detail of many thousand nodes takes milliseconds too: it goes on within the time budget, the
    // items listed so far upload meanwhile.
    if (list.walk) {
        const bool listed = list.walk->run([&](DrawUse u) { list.items.push_back(std::move(u)); },
                                           [&] { return budget.elapsedMs() >= budget.ms; });
        if (listed) list.walk.reset();
    }
    // What was uploaded by earlier calls keeps its grace while this detail waits (GpuCache::prepareMesh).
    for (size_t i = 0; i < list.next; ++i) cache_->prepareMesh(list.items[i].mesh.get());
    std::vector<uint64_t> cold;
    for (; list.next < list.items.size(); ++list.next) {
        const DrawUse& u = list.items[list.next];
        const Mesh* m = u.mesh.get();
        const Material* mat = u.material.get();
        // The same copies draw() would take: the mesh, and its material's texture when it has UVs.
        // (A physical material's other textures upload on first draw.)
        const bool physical = mat && mat->physical;
        const auto& uvs = physical && mat->texCoord == 1 ? m->uvs1() : m->uvs();
        const Texture* tex = mat && !uvs.empty() && uvs.size() == m->positions().size() ? mat->texture.get() : nullptr;
        const bool cut = mat && mat->alphaCutoff > 0.0f;
        // Its shader variants, drawn after its copies (the draw uploads nothing more): what a software rasterizer
        // takes 40-80 ms over, as the budget's time counts.
        cold.clear();
        coldKeys(u, cold);
        const bool needs = !cache_->hasMesh(m) || (tex && !cache_->hasTexture(tex, cut, physical)) || !cold.empty();
        if (needs && budget.exhausted()) break;
        if (cache_->prepareMesh(m)) budget.spend(1, m->bytes());
        if (tex && cache_->prepareTexture(tex, cut, physical)) budget.spend(1, tex->rgba().size());
        if (!cold.empty()) warmDraw({&u}, lastCamera_);
    }
    const bool done = !list.walk && list.next == list.items.size();
    if (done) prepareLists_.erase(found);
    // Lists of details dropped before they were prepared.
    for (auto it = prepareLists_.begin(); it != prepareLists_.end();)
        it = prepareCalls_ - it->second.touched > kPrepareForget ? prepareLists_.erase(it) : std::next(it);
    return done;
}

void Renderer::releaseUnused() { cache_->releaseUnused(); }
void Renderer::releaseOrphans() { cache_->releaseOrphans(); }

void Renderer::clear() {
    cache_->clear();
    cpuSkinned_.clear();
}

size_t Renderer::cachedMeshes() const { return cache_->meshCount(); }

size_t Renderer::cachedTextures() const { return cache_->textureCount(); }

size_t Renderer::samplerCount() const { return cache_->samplerCount(); }

}  // namespace sg
