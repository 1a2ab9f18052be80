// OcclusionBench: the occlusion mode's set-up and frame loop. Each frame culls OSG's city with occluders
// (shadow-volume occlusion on), the same city without occluders (frustum only) and the occluder city with
// SHADOW_OCCLUSION_CULLING cleared; with --with-sgkit, sgkit's own occluder city too, with and without its
// occlusion tree. The occluders are described in sgbench_osg.cpp.
#include <osg/CollectOccludersVisitor>
#include <osg/FrameStamp>
#include <osgUtil/CullVisitor>
#include <osgUtil/SceneView>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iterator>
#include <vector>

#ifdef SGBENCH_WITH_SGKIT
#include "sg/cull/CullTraversal.h"
#include "testbed/City.h"

#include <memory>
#endif

#include "Occlusion.h"

namespace osgbench {

namespace {

using namespace osgcity;

class MarkingCollector : public osg::CollectOccludersVisitor {
public:
    explicit MarkingCollector(CullMarks* marks) : marks_(marks) {}
    void reset() override {
        marks_->collectStart = Clock::now();
        marks_->collected = true;
        osg::CollectOccludersVisitor::reset();
    }

private:
    CullMarks* marks_;
};

class MarkingCullVisitor : public osgUtil::CullVisitor {
public:
    MarkingCullVisitor(const osgUtil::CullVisitor& cv, CullMarks* marks) : osgUtil::CullVisitor(cv), marks_(marks) {}
    void reset() override {
        marks_->cullStart = Clock::now();
        osgUtil::CullVisitor::reset();
    }

private:
    CullMarks* marks_;
};

// One configuration's cull of frame f; every frame runs each configuration's step once.
using Step = std::function<void(int, bool)>;

osg::Matrixd pathView(bool street, int n, int f) { return street ? streetView(n, f) : orbitView(n, f); }

// The city with occluders, and the same city without them (sharing every mesh).
void buildScenes(OcclusionRun& run, const OcclusionOptions& o) {
    const auto buildStart = Clock::now();
    run.meshes = buildMeshes(o.occluders);
    run.occScene = buildCity(o.n, run.meshes, true, float(o.occluderRange));
    const auto buildEnd = Clock::now();
    run.plainScene = buildCity(o.n, run.meshes, false);
    run.buildSeconds = std::chrono::duration<double>(buildEnd - buildStart).count();
}

// One SceneView per configuration, each with its own (warm) render graph pools.
void setUpOsgCulls(OcclusionRun& run, const OcclusionOptions& o) {
    run.frameStamp = new osg::FrameStamp;
    const unsigned occlusionMode = kFrustumCulling | osg::CullSettings::SHADOW_OCCLUSION_CULLING;
    run.osgConfigs = {
        {"occlusion", &run.occScene, occlusionMode, nullptr, {}, {}, {}},
        {"frustum", &run.plainScene, kFrustumCulling, nullptr, {}, {}, {}},
        {"occluders_ignored", &run.occScene, kFrustumCulling, nullptr, {}, {}, {}},
    };
    for (OsgConfig& c : run.osgConfigs) {
        c.sv = makeSceneView(c.scene->root.get(), run.frameStamp.get(), run.zNear, c.mode);
        // SceneView::cull collects the occluders in view with this visitor whenever the scene holds
        // OccluderNodes (whatever the culling mode), then hands them to the CullVisitor.
        osg::ref_ptr<osg::CollectOccludersVisitor> cov = new MarkingCollector(&c.marks);
        cov->setMaximumNumberOfActiveOccluders(o.maxOccluders);
        cov->setMinimumShadowOccluderVolume(float(o.minVolume));
        c.sv->setCollectOccludersVisitor(cov.get());
        c.sv->setCullVisitor(new MarkingCullVisitor(*c.sv->getCullVisitor(), &c.marks));
    }
}

Step osgStep(OsgConfig* cp, bool street, int n) {
    return [cp, street, n](int f, bool timed) {
        cp->sv->setViewMatrix(pathView(street, n, f));
        cp->marks.collected = false;
        const auto t0 = Clock::now();
        cp->sv->cull();
        const auto t1 = Clock::now();
        if (!timed) return;
        cp->s.ms.push_back(msBetween(t0, t1));
        if (cp->marks.collected) cp->s.collectMs.push_back(msBetween(cp->marks.collectStart, cp->marks.cullStart));
        const DrawCount dc = countStage(*cp->sv->getRenderStage(), *cp->scene);
        cp->s.geometries += double(dc.leaves);
        cp->s.triangles += double(dc.triangles);
        cp->s.occluders += double(cp->sv->getCullVisitor()->getOccluderList().size());
        cp->keys = leafKeys(*cp->sv->getRenderStage());
    };
}

#ifdef SGBENCH_WITH_SGKIT
// Settings as `sgbench occlusion`: mode On, the defaults otherwise.
void setUpSgkit(SgkitOcclusion& peer, int n) {
    peer.frustum.occlusion.mode = sg::OcclusionMode::Off;
    peer.occlusion = peer.frustum;
    peer.occlusion.occlusion.mode = sg::OcclusionMode::EveryFrame;
    peer.occlusion.occlusion.method = sg::OcclusionMethod::Tree;
    peer.scene = std::make_unique<sg::Scene>(scenes::buildCity({n, true}));
    peer.scene->update();
}

Step sgkitStep(SgkitOcclusion& peer, sg::CullTraversal* t, const sg::CullSettings* set, Series* s, bool street, int n) {
    const sg::Scene* scene = peer.scene.get();
    sg::DrawList* list = &peer.list;
    return [=](int f, bool timed) {
        const sg::Camera cam = street ? scenes::cityStreetCamera(n, f) : scenes::cityOrbitCamera(n, f);
        sg::CullStats st;
        const auto t0 = Clock::now();
        t->cull(*scene, cam, *set, *list, st);
        const auto t1 = Clock::now();
        if (!timed) return;
        s->ms.push_back(msBetween(t0, t1));
        s->geometries += double(st.geometries);
        s->triangles += double(st.triangles);
        s->occluders += double(st.occludersUsed);
    };
}
#endif

// The configurations culled each frame: OSG's, then sgkit's when it is compared.
std::vector<Step> makeSteps(OcclusionRun& run, const OcclusionOptions& o) {
    std::vector<Step> steps;
    for (OsgConfig& c : run.osgConfigs) steps.push_back(osgStep(&c, o.street, o.n));
#ifdef SGBENCH_WITH_SGKIT
    SgkitOcclusion& peer = run.sgkit;
    if (peer.scene) {
        steps.push_back(sgkitStep(peer, &peer.cullFrustum, &peer.frustum, &peer.f, o.street, o.n));
        steps.push_back(sgkitStep(peer, &peer.cullOcclusion, &peer.occlusion, &peer.o, o.street, o.n));
    }
#endif
    return steps;
}

// The untimed warm-up pass over the path, then the timed ones. The steps run in an order that rotates from
// frame to frame so that none always runs first (or right after another one) in a frame. False when the
// cull settings did not hold.
bool cullFrames(OcclusionRun& run, int passes, const std::vector<Step>& steps) {
    unsigned frameNumber = 0;
    for (int pass = 0; pass <= passes; ++pass) {
        const bool timed = pass > 0;  // pass 0 is the untimed warm-up
        for (int f = 0; f < run.frames; ++f) {
            ++frameNumber;
            run.frameStamp->setFrameNumber(frameNumber);
            run.frameStamp->setReferenceTime(frameNumber / 60.0);
            run.frameStamp->setSimulationTime(frameNumber / 60.0);
            const size_t first = size_t(frameNumber) % steps.size();
            for (size_t k = 0; k < steps.size(); ++k) steps[(first + k) % steps.size()](f, timed);

            if (pass == 0 && f == 0)
                for (const OsgConfig& c : run.osgConfigs)
                    if (!checkInherited(*c.sv, c.mode)) return false;
            if (timed) {
                const std::vector<LeafKey>& occKeys = run.osgOcc().keys;
                const std::vector<LeafKey>& offKeys = run.osgOff().keys;
                std::vector<LeafKey> extra;
                std::set_difference(occKeys.begin(), occKeys.end(), offKeys.begin(), offKeys.end(),
                                    std::back_inserter(extra));
                run.notSubset += extra.size();
            }
        }
    }
    return true;
}

}  // namespace

int runOcclusion(const OcclusionOptions& o) {
    OcclusionRun run;
    run.frames = o.street ? kStreetFrames : kFrames;
    run.zNear = o.street ? kStreetNear : kNear;
    buildScenes(run, o);
    setUpOsgCulls(run, o);
#ifdef SGBENCH_WITH_SGKIT
    if (o.withSgkit) setUpSgkit(run.sgkit, o.n);
#else
    if (o.withSgkit) usage("--with-sgkit: this build has no sgkit (configure it inside the sgkit project)");
#endif

    const std::vector<Step> steps = makeSteps(run, o);
    if (!cullFrames(run, o.passes, steps)) return 1;
    if (run.osgOff().s.geometries <= 0.0) {
        std::fprintf(stderr, "error: the cull produced no draw leaves on the path\n");
        return 1;
    }
    reportOcclusion(o, run);
    std::fflush(stdout);
    return 0;
}

}  // namespace osgbench
