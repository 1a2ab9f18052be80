#include "factory/Walkthrough.h"

#include "nodes/Geometry.h"
#include "sg/lod/LodStress.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <set>
#include <utility>

namespace factory {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }
// Every (mesh, material) under `n`: all children of Switches and LODs, and Instances' prototypes.
void allGeometry(sg::Node& n, std::set<std::pair<const sg::Mesh*, const sg::Material*>>& out) {
    if (n.kind() == sg::NodeKind::Geometry) {
        const auto& g = static_cast<const sg::Geometry&>(n);
        if (g.mesh()) out.insert({g.mesh(), g.material()});
    }
    for (size_t i = 0; i < n.numChildren(); ++i) allGeometry(*n.child(i), out);
}
uint64_t vertices(const sg::DrawList& list) {
    uint64_t n = 0;
    for (const sg::DrawItem& it : list.items) n += it.mesh->positions().size();
    return n;
}
}  // namespace

const char* modeName(LodMode m) {
    switch (m) {
        case LodMode::Static: return "static";
        case LodMode::Budget: return "budget";
        case LodMode::Stress: return "stress";
    }
    return "?";
}

Walkthrough::Walkthrough(scenes::Factory& f, sg::Scene& scene, const WalkPath& path, int width, int height)
    : f_(f), scene_(scene), path_(path), width_(width), height_(height) {
    // Every mesh and texture the path may draw goes to the GPU now, as an application loads its database
    // before it walks it: else each is uploaded in the first frame that sees it (the workshop's interior at
    // the door, coarse levels as the eye draws away), and those frames stall.
    std::set<std::pair<const sg::Mesh*, const sg::Material*>> all;
    allGeometry(*f_.root, all);
    // Drawn looking at the sky through a sliver of depth: uploaded, and next to nothing rasterised.
    sg::Camera sky;
    sky.setViewport(width_, height_);
    sky.setPerspective(60.0, double(width_) / height_, 0.1, 0.2);
    sky.setLookAt(sg::dvec3(0.0, 0.0, 1e4), sg::dvec3(0.0, 0.0, 2e4), sg::dvec3(0.0, 1.0, 0.0));
    // One mesh per draw: the whole site in one draw left the software rasteriser slower on every later frame.
    for (const auto& [mesh, material] : all) {
        sg::DrawItem it;
        it.mesh = mesh;
        it.material = material;
        list_.clear();
        list_.add(it);
        renderer_.draw(list_, sky);
    }
    renderer_.finish();
    list_.clear();
}

void Walkthrough::showWorkshop(int workshop) {
    if (workshop == shown_) return;
    scenes::setFactoryEye(f_, workshop);
    scene_.update();
    shown_ = workshop;
}

sg::Image Walkthrough::render(int frame, const sg::CullSettings& set, sg::CullStats& stats) {
    const PathFrame& p = path_.frames.at(size_t(frame));
    showWorkshop(p.workshop);
    const sg::Camera cam = pathCamera(p, width_, height_);
    refCull_.cull(scene_, cam, set, list_, stats);
    renderer_.draw(list_, cam);
    return renderer_.readColor();
}

std::vector<double> Walkthrough::sameView(int frame, int draws) {
    const PathFrame& p = path_.frames.at(size_t(frame));
    showWorkshop(p.workshop);
    const sg::Camera cam = pathCamera(p, width_, height_);
    sg::CullSettings set;
    sg::CullStats st;
    std::vector<double> ms;
    for (int i = 0; i < draws + 3; ++i) {  // the first draws upload meshes: not timed
        const auto t0 = Clock::now();
        cull_.cull(scene_, cam, set, list_, st);
        renderer_.draw(list_, cam);
        renderer_.finish();
        if (i >= 3) ms.push_back(msSince(t0));
    }
    return ms;
}

ModeRun Walkthrough::run(LodMode mode, double budgetMs, bool compare,
                         const std::function<void(int, const sg::Image&)>& onFrame) {
    ModeRun out;
    out.mode = mode;
    out.budgetMs = budgetMs;
    sg::DrawCostModel model;
    sg::LodStress::Params sp;
    sp.budgetMs = budgetMs;
    sg::LodStress stress(sp);
    sg::CullSettings full;  // the reference: every LOD at its finest level
    full.lodScale = 1e-9;
    double lastCullMs = 0.0;
    sg::CullStats st;
    // One frame: switch state, cull, draw, finish; then the method learns from the measured time.
    auto frame = [&](int i, FrameRecord& r) {
        const PathFrame& p = path_.frames[size_t(i)];
        const sg::Camera cam = pathCamera(p, width_, height_);
        sg::CullSettings set;
        if (mode == LodMode::Stress) set.lodScale = stress.scale();
        if (mode == LodMode::Budget) {
            set.lodBudget.enabled = true;
            set.lodBudget.model = &model;
            set.lodBudget.budgetMs = std::max(1.0, budgetMs - lastCullMs);  // the cull's own time comes off
        }
        const auto t0 = Clock::now();
        showWorkshop(p.workshop);
        cull_.cull(scene_, cam, set, list_, st);
        r.cullMs = msSince(t0);
        const auto t1 = Clock::now();
        renderer_.draw(list_, cam);
        renderer_.finish();
        r.drawMs = msSince(t1);
        r.frameMs = msSince(t0);
        lastCullMs = r.cullMs;
        if (mode == LodMode::Stress) stress.update(r.frameMs);
        model.update({double(st.triangles), double(st.geometries), st.lodPixels}, r.drawMs);
        r.frame = i;
        r.triangles = st.triangles;
        r.geometries = st.geometries;
        r.vertices = vertices(list_);
    };
    const int n = int(path_.frames.size());
    FrameRecord warm;
    for (int i = 0; i < std::min(n, 40); ++i) frame(i, warm);
    for (int i = 0; i < n; ++i) {
        FrameRecord r;
        frame(i, r);
        if (compare || onFrame) {
            const sg::Image got = renderer_.readColor();
            if (onFrame) onFrame(i, got);
            if (compare) {
                sg::CullStats rs;
                r.mae = sg::meanAbsoluteError(got, render(i, full, rs));
            }
        }
        out.frames.push_back(r);
    }
    return out;
}

}  // namespace factory
