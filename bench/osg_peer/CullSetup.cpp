// CullSetup: a SceneView driven as osgViewer::Renderer drives it for one camera, and the check that its
// CullVisitor kept the cull settings.
#include <osgUtil/CullVisitor>
#include <osgUtil/SceneView>

#include <cstdio>

#include "Bench.h"

namespace osgbench {

using namespace osgcity;

// SceneView set up as osgViewer::Renderer would drive it for one camera.
osg::ref_ptr<osgUtil::SceneView> makeSceneView(osg::Node* scene, osg::FrameStamp* frameStamp, double zNear,
                                               unsigned cullingMode) {
    // setDefaults() creates the osg::State (no GL context is touched during
    // cull), the CullVisitor, the StateGraph and the RenderStage, plus the
    // standard global state set and headlight a viewer would also have.
    osg::ref_ptr<osgUtil::SceneView> sv = new osgUtil::SceneView;
    sv->setDefaults();
    sv->setFrameStamp(frameStamp);
    sv->setViewport(0, 0, kViewportW, kViewportH);
    sv->setProjectionMatrix(osg::Matrixd::perspective(kFovY, kAspect, zNear, kFar));
    sv->setSceneData(scene);
    // Cull settings must be set after setDefaults() (which resets them). The
    // SceneView is itself the CullSettings that cull() copies into its
    // CullVisitor (and CollectOccludersVisitor) every frame
    // (inheritCullSettings).
    sv->setCullingMode(cullingMode);
    sv->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    return sv;
}

// Guard against the settings being silently overridden.
bool checkInherited(const osgUtil::SceneView& sv, unsigned cullingMode) {
    const osgUtil::CullVisitor* cv = sv.getCullVisitor();
    if (unsigned(cv->getCullingMode()) != cullingMode ||
        cv->getComputeNearFarMode() != osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR) {
        std::fprintf(stderr,
                     "error: CullVisitor did not inherit the cull settings "
                     "(mode 0x%x, near/far mode %d)\n",
                     cv->getCullingMode(), int(cv->getComputeNearFarMode()));
        return false;
    }
    return true;
}

}  // namespace osgbench
