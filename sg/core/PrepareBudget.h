// PrepareBudget: what a frame may spend on preparing paged details for drawing (uploading their meshes and
// textures), as OpenSceneGraph's IncrementalCompileOperation: a time and a count of objects per frame. The pager
// makes one per update (PagerSettings::prepareMsPerFrame, prepareObjectsPerFrame) and hands it to its prepare
// function (Pager::setPrepare); Renderer::prepare() spends it.
#pragma once
#include <chrono>
#include <cstddef>
#include <cstdint>

namespace sg {

struct PrepareBudget {
    using Clock = std::chrono::steady_clock;

    PrepareBudget() = default;
    PrepareBudget(double ms, uint32_t objects) : ms(ms), objects(objects) {}

    double ms = 1.0;        // time the frame may spend, from `start`
    uint32_t objects = 20;  // objects (meshes, textures) it may upload
    Clock::time_point start = Clock::now();
    // Spent so far (spend() counts them).
    uint32_t objectsUsed = 0;
    size_t bytesUsed = 0;

    double elapsedMs() const { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }
    // Whether nothing more may be started this frame: the objects or the time are used up.
    bool exhausted() const { return objectsUsed >= objects || elapsedMs() >= ms; }
    void spend(uint32_t n, size_t bytes) {
        objectsUsed += n;
        bytesUsed += bytes;
    }
};

}  // namespace sg
