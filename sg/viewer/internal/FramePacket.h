// Viewer::Packet: one frame on its way through the viewer's stages (ViewerFrame.cpp, ViewerCullDraw.cpp,
// ViewerThreads.cpp, ViewerPaging.cpp each fill or read a part of it).
// Internal header: not installed (an internal/ folder); its shape may change freely.
#pragma once
#include "sg/viewer/Viewer.h"

#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace sg {

// One frame on its way through the stages: what the cull made of each view, and what its draw reads. The thread that
// holds it is the only one that touches it; it is handed over through StageThread, which orders the writes.
struct Viewer::Packet {
    FrameInfo info;
    StageTimes times;
    Clock::time_point start;
    struct ViewFrame {
        View* view = nullptr;
        Camera camera;
        CullSettings settings;  // the view's, as frameSettings() makes them of what the application set
        CullControls controls;  // the viewer's: the image of the last update, under AppCullDraw
        Renderer::Viewport viewport{};
        vec4 clear{0.0f};
        bool finished = false;  // finished after its draw (timed)
        DrawList list;
        CullStats stats;
        // The look-ahead cull, when View::prefetchSeconds asks for one and the camera moves.
        std::optional<Camera> ahead;
        CullStats aheadStats;
        RenderStats render;
        double cullMs = 0.0, drawMs = 0.0, gpuMs = -1.0;
        std::thread::id cullThread;
    };
    std::vector<ViewFrame> views;
    size_t viewCount = 0;  // views[0, viewCount) are this frame's (the rest are kept for their lists' memory)
    // The meshes, materials and poses the lists point at, held while the frame is in flight: the app stage of a later
    // frame may drop them from the graph (or the pager unload them) before this frame's draw is done.
    std::vector<ref_ptr<const Referenced>> keep;
    bool finishAll = true;  // ViewerSettings::finish, as it was when the frame started
    bool drawOverlay = false;
    std::string overlay;  // the stats text, made on the application thread (it reads the history)
    bool culled = false, drawn = false;
    Clock::time_point drawEnd;
    // The pager's details to upload on the draw thread within the budget, whether each got done, and those the
    // pager dropped after asking (pipelined models: Viewer::prepareOnDraw).
    std::vector<ref_ptr<Node>> upload;
    std::vector<char> uploadDone;
    std::vector<ref_ptr<const Node>> forget;
    PrepareBudget uploadBudget;
    // A scene's first frame: the Geometries its draws can take their shader variants from, listed on the application
    // thread (Renderer::drawUses) and compiled on the draw thread before the views' draw (Renderer::prepareVariants).
    bool prepareVariants = false;
    std::vector<Renderer::DrawUse> variantUses;
};

}  // namespace sg
