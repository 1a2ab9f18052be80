// The viewer's threading models by name: in the core library (no GL), so that a program's option parser can read
// them whichever GL library the program draws with.
#pragma once
#include <cstdint>
#include <string>

namespace sg {

// Which threads run a frame's stages (Performer's pfMultiprocess, OpenSceneGraph's threading models). The latency is
// the frames between a frame's app stage and its picture: frame() returns while that many frames are still in flight.
enum class ThreadingModel : uint8_t {
    SingleThreaded,     // every stage on the thread that calls frame(); latency 0
    DrawThread,         // the draw on a thread of its own, which owns the GL context, while the calling thread runs the
                        // next frame's app, update and cull (OSG's DrawThreadPerContext, Performer's APPCULL_DRAW);
                        // latency 1
    CullThreadPerView,  // as DrawThread, and each view culled on a thread of its own (OSG's
                        // CullThreadPerCameraDrawThreadPerContext); latency 1
    AppCullDraw,        // app, cull and draw of three consecutive frames at once, each stage on its own thread
                        // (Performer's APP_CULL_DRAW); latency 2
};
const char* threadingModelName(ThreadingModel m);
// Throws std::invalid_argument listing the valid names ("single", "draw", "cull-per-view", "app-cull-draw").
ThreadingModel parseThreadingModel(const std::string& name);
int threadingLatency(ThreadingModel m);

}  // namespace sg
