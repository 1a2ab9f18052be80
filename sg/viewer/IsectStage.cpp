#include "sg/viewer/IsectStage.h"

#include "sg/viewer/internal/StageThread.h"

#include <chrono>
#include <exception>

namespace sg {

IsectStage::IsectStage() = default;

IsectStage::~IsectStage() {
    if (thread_) thread_->wait();
}

void IsectStage::intersect(const Ray& ray, const QueryOptions& options, Done done) {
    auto q = std::make_unique<Query>();
    q->ray = ray;
    q->options = options;
    if (options.camera) {
        q->camera = std::make_unique<Camera>(*options.camera);
        q->options.camera = q->camera.get();
    }
    q->done = std::move(done);
    queued_.push_back(std::move(q));
}

void IsectStage::move(ViewpointCollider& collider, const dvec3& from, const dvec3& step, Done done) {
    auto q = std::make_unique<Query>();
    q->collider = &collider;
    q->from = from;
    q->step = step;
    q->done = std::move(done);
    queued_.push_back(std::move(q));
}

// A refused query answers with its reason, as the synchronous call would have thrown it.
void IsectStage::answer(const Scene& scene, Query& q) {
    try {
        if (q.collider) {
            q.answer.position = q.collider->move(scene, q.from, q.step);
            q.answer.contact = q.collider->lastStats();
        } else {
            q.answer.hit = traversal_.intersect(scene, q.ray, q.options, q.answer.nearest);
        }
    } catch (const std::exception& e) {
        q.answer = IsectAnswer{};
        q.answer.error = e.what();
    } catch (...) {
        q.answer = IsectAnswer{};
        q.answer.error = "an exception that is not a std::exception";
    }
}

void IsectStage::start(const Scene& scene, uint64_t frame) {
    if (queued_.empty()) return;
    running_ = std::move(queued_);
    queued_.clear();
    if (!thread_) thread_ = std::make_unique<StageThread>();
    thread_->run([this, &scene, frame] {
        const auto t0 = std::chrono::steady_clock::now();
        for (auto& q : running_) {
            q->answer.frame = frame;
            answer(scene, *q);
        }
        runMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    });
}

void IsectStage::finish() {
    if (running_.empty()) return;
    thread_->wait();
    lastMs_ = runMs_;  // read here, once the thread is done with it
    std::vector<std::unique_ptr<Query>> done = std::move(running_);
    running_.clear();
    for (auto& q : done) {
        ++answered_;
        if (q->done) q->done(q->answer);
    }
}

}  // namespace sg
