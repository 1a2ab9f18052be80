#include "factory/Walkthrough.h"

#include "nodes/Geometry.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/io/ImageIO.h"
#include "testbed/FactoryLighting.h"

#include <algorithm>
#include <cstdlib>
#include <set>
#include <utility>

namespace factory {

namespace {
constexpr int kWarmupFrames = 40;  // per mode, before the timed path

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

Walkthrough::Walkthrough(scenes::Factory& f, sg::Scene& scene, const scenes::WalkPath& path, int width, int height)
    : f_(f), scene_(scene), path_(path), width_(width), height_(height) {
    if (renderer_.softwareRasterizer()) sg::keepFreedMemory();  // the walk is a frame loop: its frames are measured
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
    renderer_.setLight(scenes::factoryLight(-1));
}

void Walkthrough::showWorkshop(int workshop) {
    if (workshop == shown_) return;
    scenes::setFactoryEye(f_, workshop);
    renderer_.setLight(scenes::factoryLight(workshop));
    scene_.update();
    shown_ = workshop;
}

sg::Image Walkthrough::render(int frame, const sg::CullSettings& set, sg::CullStats& stats) {
    const scenes::PathFrame& p = path_.frames.at(size_t(frame));
    showWorkshop(p.workshop);
    const sg::Camera cam = scenes::pathCamera(p, width_, height_);
    refCull_.cull(scene_, cam, set, list_, stats);
    renderer_.draw(list_, cam);
    return renderer_.readColor();
}

std::vector<double> Walkthrough::sameView(int frame, int draws) {
    const scenes::PathFrame& p = path_.frames.at(size_t(frame));
    showWorkshop(p.workshop);
    return scenes::timeSameView(renderer_, scene_, scenes::pathCamera(p, width_, height_), draws);
}

std::vector<ModeRun> Walkthrough::run(const std::vector<sg::LodPolicy>& modes, double budgetMs, bool limitRate,
                                      bool compare, const std::function<void(size_t, int, const sg::Image&)>& onFrame) {
    sg::CullSettings full;  // the reference: every LOD at its finest level
    full.lodScale = 1e-9;
    std::vector<ModeRun> out(modes.size());
    std::vector<std::unique_ptr<scenes::LodRun>> runs;
    for (size_t k = 0; k < modes.size(); ++k) {
        out[k].mode = modes[k];
        out[k].budgetMs = budgetMs;
        scenes::LodRun::Settings set;
        set.method = modes[k];
        set.budgetMs = budgetMs;
        set.limitRate = limitRate && modes[k] != sg::LodPolicy::Static;  // static aims at no frame time
        set.threading = threading_;
        set.bindContext = bindContext_;
        runs.push_back(std::make_unique<scenes::LodRun>(renderer_, set));
    }
    const int n = int(path_.frames.size());
    auto frame = [&](size_t k, int i) -> const scenes::LodFrame& {
        const scenes::PathFrame& p = path_.frames[size_t(i)];
        runs[k]->frame(scene_, scenes::pathCamera(p, width_, height_), [&] { showWorkshop(p.workshop); });
        // The next frame is another method's (its own viewer), or the comparison's draw here: both need the
        // context on this thread. Stopped, the frame is drawn and last() is its own.
        return threading_ == sg::ThreadingModel::SingleThreaded ? runs[k]->last() : runs[k]->stopThreads();
    };
    for (size_t k = 0; k < modes.size(); ++k)  // the warm-up: the stress scale and the model settle on the path
        for (int i = 0; i < std::min(n, kWarmupFrames); ++i) frame(k, i);
    for (int i = 0; i < n; ++i)
        for (size_t k = 0; k < modes.size(); ++k) {
            const scenes::LodFrame& f = frame(k, i);
            FrameRecord r;
            r.frame = i;
            r.cullMs = f.cullMs;
            r.drawMs = f.drawMs;
            r.workMs = f.workMs;
            r.frameMs = f.frameMs;
            r.predictedMs = f.stats.lodPredictedMs;
            r.triangles = f.stats.triangles;
            r.geometries = f.stats.geometries;
            r.vertices = vertices(runs[k]->list());
            if (compare || onFrame) {
                const sg::Image got = renderer_.readColor();
                if (onFrame) onFrame(k, i, got);
                if (compare) {
                    sg::CullStats rs;
                    r.mae = sg::meanAbsoluteError(got, render(i, full, rs));
                }
            }
            out[k].frames.push_back(r);
        }
    return out;
}

}  // namespace factory
