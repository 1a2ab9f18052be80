#include "sg/viewer/Threading.h"

#include "sg/core/Settings.h"

namespace sg {

namespace {
const EnumName<ThreadingModel> kModels[] = {{ThreadingModel::SingleThreaded, "single"},
                                            {ThreadingModel::DrawThread, "draw"},
                                            {ThreadingModel::CullThreadPerView, "cull-per-view"},
                                            {ThreadingModel::AppCullDraw, "app-cull-draw"}};
}  // namespace

const char* threadingModelName(ThreadingModel m) { return enumName(kModels, m); }
ThreadingModel parseThreadingModel(const std::string& name) {
    return parseEnum(kModels, name, "parseThreadingModel()", "a threading model");
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
