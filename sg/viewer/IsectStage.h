// IsectStage: Performer's ISECT process. Picking and the viewpoint collider's moves asked for in a frame are answered
// on a thread of their own, against the scene as that frame's update left it, while the frame is culled and drawn;
// the answers reach the application at the start of the next frame (latency one frame), before its events. The
// synchronous queries (IntersectTraversal, ViewpointCollider::move) stay callable from the app stage as before.
#pragma once
#include "sg/core/Camera.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/intersect/ViewpointCollider.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sg {

class StageThread;

struct IsectAnswer {
    uint64_t frame = 0;      // the frame whose scene answered
    bool hit = false;        // intersect(): whether the ray hit
    Hit nearest;             // intersect(): the nearest hit
    dvec3 position{0.0};     // move(): where the viewpoint got to
    ViewpointStats contact;  // move(): the collider's stats for it
    std::string error;       // a refused query (a non-finite value, a stale scene): why; nothing else is set
};

class IsectStage {
public:
    using Done = std::function<void(const IsectAnswer&)>;
    IsectStage();
    ~IsectStage();  // waits for the queries in hand; their answers are dropped
    IsectStage(const IsectStage&) = delete;
    IsectStage& operator=(const IsectStage&) = delete;

    // Asked in the app stage (an event or app callback, or between frames); options.camera, when set, is copied.
    void intersect(const Ray& ray, const QueryOptions& options, Done done);
    // The collider is used on the ISECT thread until the answer arrives: the application leaves it alone till then.
    void move(ViewpointCollider& collider, const dvec3& from, const dvec3& step, Done done);
    // Queries asked and not answered yet.
    size_t pending() const { return queued_.size() + running_.size(); }
    // The ISECT thread's time on the queries answered last (those of the frame before), ms: off every stage.
    double lastMs() const { return lastMs_; }
    uint64_t answered() const { return answered_; }

private:
    friend class Viewer;
    struct Query {
        Ray ray;
        QueryOptions options;
        std::unique_ptr<Camera> camera;
        ViewpointCollider* collider = nullptr;
        dvec3 from{0.0}, step{0.0};
        Done done;
        IsectAnswer answer;
    };
    // After the update of `frame`: the queued queries start on the ISECT thread. The scene is not written until
    // finish() returns.
    void start(const Scene& scene, uint64_t frame);
    // Waits for them and runs their done callbacks on the calling thread (the application's).
    void finish();
    void answer(const Scene& scene, Query& q);

    std::vector<std::unique_ptr<Query>> queued_, running_;
    IntersectTraversal traversal_;
    std::unique_ptr<StageThread> thread_;
    double lastMs_ = 0.0, runMs_ = 0.0;
    uint64_t answered_ = 0;
};

}  // namespace sg
