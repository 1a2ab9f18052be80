#include "sg/viewer/Threading.h"

#include <stdexcept>

namespace sg {

const char* threadingModelName(ThreadingModel m) {
    switch (m) {
        case ThreadingModel::SingleThreaded: return "single";
        case ThreadingModel::DrawThread: return "draw";
        case ThreadingModel::CullThreadPerView: return "cull-per-view";
        case ThreadingModel::AppCullDraw: return "app-cull-draw";
    }
    return "?";
}

ThreadingModel parseThreadingModel(const std::string& name) {
    for (ThreadingModel m : {ThreadingModel::SingleThreaded, ThreadingModel::DrawThread,
                             ThreadingModel::CullThreadPerView, ThreadingModel::AppCullDraw})
        if (name == threadingModelName(m)) return m;
    throw std::invalid_argument("parseThreadingModel(): '" + name +
                                "' is not a threading model (single, draw, cull-per-view, app-cull-draw)");
}

int threadingLatency(ThreadingModel m) {
    switch (m) {
        case ThreadingModel::SingleThreaded: return 0;
        case ThreadingModel::DrawThread:
        case ThreadingModel::CullThreadPerView: return 1;
        case ThreadingModel::AppCullDraw: return 2;
    }
    return 0;
}

}  // namespace sg
