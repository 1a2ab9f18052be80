// sgbench_osg: OpenSceneGraph 3.6 peer for sgkit's cull benchmark.
//
// What it measures
//   Wall-clock time of OpenSceneGraph's cull traversal (osgUtil::SceneView::cull)
//   for the canonical benchmark scene `city` (N x N cells) along the canonical
//   `orbit` camera path (120 frames). No graphics context exists and nothing is
//   drawn: only the CPU work a viewer's cull thread performs per frame is timed.
//   SceneView::cull is the same call osgViewer::Renderer makes each frame: it
//   resets the CullVisitor, RenderStage and StateGraph, traverses the scene
//   (frustum tests, LOD selection, matrix stack, RenderLeaf/StateGraph
//   construction), sorts the render bins and prunes the state graph.
//
// What makes it fair
//   * The scene graph follows the shared scene definition exactly: root ->
//     8x8-cell tiles -> cell Group -> {MatrixTransform -> LOD -> 2 Geodes,
//     MatrixTransform -> Geode}, with one shared osg::Geometry per distinct
//     building height and level of detail plus one shared car Geometry.
//   * Culling mode is VIEW_FRUSTUM_SIDES_CULLING | NEAR_PLANE_CULLING |
//     FAR_PLANE_CULLING. OSG's default (DEFAULT_CULLING) tests only the four
//     side planes and additionally enables small-feature, shadow-occlusion and
//     cluster culling; the peer must reject the same things our toolkit rejects
//     (all six frustum planes, nothing else).
//   * Compute-near-far is DO_NOT_COMPUTE_NEAR_FAR: the path uses fixed
//     near = 1 and far = 3000, so OSG must not spend time computing (or
//     clamping to) per-drawable depth ranges that our toolkit does not compute.
//   * Bounding spheres are computed during the build (as part of build_s), so
//     neither timed pass pays for lazy bound computation; a full untimed
//     warm-up pass additionally warms caches and OSG's RenderLeaf/StateGraph
//     pools, just as they would be warm in a running viewer.
//   * Verification of the result (counting RenderLeafs and triangles) is done
//     outside the timed region.
//
// Usage: sgbench_osg [--n N] [--frames-passes K] [--with-sgkit]
// --with-sgkit (when built inside the sgkit project) also builds sgkit's city and culls it right after
// OpenSceneGraph on every frame: the per-frame time ratio is then free of this machine's speed drift.
//   N: city size (default 316). K: number of timed passes over the path after
//   the warm-up pass (default 1); statistics are taken over all K*120 frames.
// Output: one JSON object on stdout; diagnostics go to stderr.

#include <osg/FrameStamp>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/LOD>
#include <osg/MatrixTransform>
#include <osg/Notify>
#include <osg/PrimitiveSet>
#include <osg/Version>
#include <osgUtil/CullVisitor>
#include <osgUtil/RenderBin>
#include <osgUtil/RenderLeaf>
#include <osgUtil/RenderStage>
#include <osgUtil/SceneView>
#include <osgUtil/StateGraph>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include <unistd.h>

#ifdef SGBENCH_WITH_SGKIT
#include "scenes/City.h"
#include "sg/CullTraversal.h"

#include <memory>
#endif

namespace {

// ---------------------------------------------------------------------------
// Scene definition constants (units metres, +Z up).

constexpr double kCellSize = 20.0;
constexpr double kFootprint = 12.0;         // building footprint, centred in the cell
constexpr double kCarSize[3] = {4.0, 2.0, 1.5};
constexpr double kCarOffset = 1.0;           // car minimum corner at (20i+1, 20j+1, 0)
constexpr unsigned kMinHeight = 10;
constexpr unsigned kHeightCount = 51;        // heights 10..60
constexpr int kTileCells = 8;                // tiles group 8x8 cells
constexpr float kDetailFar = 250.0f;         // detailed LOD: [0, 250)
constexpr float kCoarseFar = 2500.0f;        // coarse LOD:   [250, 2500)
constexpr int kDetailSubdiv = 10;            // 10x10 quads per face -> 1200 triangles

// Orbit path and camera.
constexpr int kFrames = 120;
constexpr int kViewportW = 1280;
constexpr int kViewportH = 720;
constexpr double kFovY = 60.0;
constexpr double kAspect = 16.0 / 9.0;
constexpr double kNear = 1.0;
constexpr double kFar = 3000.0;

unsigned buildingHeight(uint32_t i, uint32_t j) {
    // Unsigned 32-bit arithmetic, exactly as in the scene definition.
    return kMinHeight + ((i * 73856093u) ^ (j * 19349663u)) % kHeightCount;
}

// ---------------------------------------------------------------------------
// Geometry: an axis-aligned box [lo, hi] whose faces are each split into
// subdiv x subdiv quads, as indexed triangles with outward per-vertex normals
// (counter-clockwise winding seen from outside).

osg::ref_ptr<osg::Geometry> makeBox(const osg::Vec3& lo, const osg::Vec3& hi, int subdiv) {
    const osg::Vec3 d = hi - lo;
    struct Face {
        osg::Vec3 origin, u, v, normal;
    };
    // u x v == normal for each face, which makes the quads wind outward.
    const Face faces[6] = {
        {{hi.x(), lo.y(), lo.z()}, {0, d.y(), 0}, {0, 0, d.z()}, {1, 0, 0}},    // +X
        {{lo.x(), hi.y(), lo.z()}, {0, -d.y(), 0}, {0, 0, d.z()}, {-1, 0, 0}},  // -X
        {{hi.x(), hi.y(), lo.z()}, {-d.x(), 0, 0}, {0, 0, d.z()}, {0, 1, 0}},   // +Y
        {{lo.x(), lo.y(), lo.z()}, {d.x(), 0, 0}, {0, 0, d.z()}, {0, -1, 0}},   // -Y
        {{lo.x(), lo.y(), hi.z()}, {d.x(), 0, 0}, {0, d.y(), 0}, {0, 0, 1}},    // +Z
        {{lo.x(), hi.y(), lo.z()}, {d.x(), 0, 0}, {0, -d.y(), 0}, {0, 0, -1}},  // -Z
    };

    const int side = subdiv + 1;
    osg::ref_ptr<osg::Vec3Array> vertices = new osg::Vec3Array;
    osg::ref_ptr<osg::Vec3Array> normals = new osg::Vec3Array;
    osg::ref_ptr<osg::DrawElementsUShort> triangles = new osg::DrawElementsUShort(GL_TRIANGLES);
    vertices->reserve(6 * side * side);
    normals->reserve(6 * side * side);
    triangles->reserve(6 * subdiv * subdiv * 6);

    for (const Face& f : faces) {
        const unsigned base = vertices->size();
        for (int b = 0; b < side; ++b) {
            for (int a = 0; a < side; ++a) {
                vertices->push_back(f.origin + f.u * (float(a) / subdiv) + f.v * (float(b) / subdiv));
                normals->push_back(f.normal);
            }
        }
        for (int b = 0; b < subdiv; ++b) {
            for (int a = 0; a < subdiv; ++a) {
                const unsigned short v00 = base + b * side + a;
                const unsigned short v10 = v00 + 1;
                const unsigned short v11 = v10 + side;
                const unsigned short v01 = v00 + side;
                triangles->push_back(v00); triangles->push_back(v10); triangles->push_back(v11);
                triangles->push_back(v00); triangles->push_back(v11); triangles->push_back(v01);
            }
        }
    }

    osg::ref_ptr<osg::Geometry> geom = new osg::Geometry;
    geom->setVertexArray(vertices.get());
    geom->setNormalArray(normals.get(), osg::Array::BIND_PER_VERTEX);
    geom->addPrimitiveSet(triangles.get());
    return geom;
}

unsigned triangleCount(const osg::Geometry& geom) {
    unsigned n = 0;
    for (unsigned p = 0; p < geom.getNumPrimitiveSets(); ++p)
        n += geom.getPrimitiveSet(p)->getNumIndices() / 3;
    return n;
}

// ---------------------------------------------------------------------------
// Scene construction.

struct Scene {
    osg::ref_ptr<osg::Group> root;
    uint64_t nodes = 0;
    // Triangles per shared Geometry, used only to verify cull output.
    std::unordered_map<const osg::Drawable*, unsigned> triangles;
};

Scene buildCity(int n) {
    Scene scene;
    const float half = float(kFootprint / 2);

    // Shared geometry: one detailed and one coarse box per distinct height,
    // one car. Buildings are centred on their transform in x,y, z from 0 to h.
    std::vector<osg::ref_ptr<osg::Geometry>> detailed(kHeightCount), coarse(kHeightCount);
    for (unsigned k = 0; k < kHeightCount; ++k) {
        const float h = float(kMinHeight + k);
        detailed[k] = makeBox({-half, -half, 0}, {half, half, h}, kDetailSubdiv);
        coarse[k] = makeBox({-half, -half, 0}, {half, half, h}, 1);
        scene.triangles[detailed[k].get()] = triangleCount(*detailed[k]);
        scene.triangles[coarse[k].get()] = triangleCount(*coarse[k]);
    }
    osg::ref_ptr<osg::Geometry> car =
        makeBox({0, 0, 0}, {float(kCarSize[0]), float(kCarSize[1]), float(kCarSize[2])}, 1);
    scene.triangles[car.get()] = triangleCount(*car);

    scene.root = new osg::Group;
    scene.nodes = 1;
    const int tiles = (n + kTileCells - 1) / kTileCells;
    for (int ti = 0; ti < tiles; ++ti) {
        for (int tj = 0; tj < tiles; ++tj) {
            osg::ref_ptr<osg::Group> tile = new osg::Group;
            scene.root->addChild(tile.get());
            ++scene.nodes;
            const int iEnd = std::min(n, (ti + 1) * kTileCells);
            const int jEnd = std::min(n, (tj + 1) * kTileCells);
            for (int i = ti * kTileCells; i < iEnd; ++i) {
                for (int j = tj * kTileCells; j < jEnd; ++j) {
                    const unsigned h = buildingHeight(uint32_t(i), uint32_t(j));
                    const unsigned k = h - kMinHeight;
                    const double x0 = kCellSize * i, y0 = kCellSize * j;

                    osg::ref_ptr<osg::Group> cell = new osg::Group;

                    osg::ref_ptr<osg::MatrixTransform> buildingXf = new osg::MatrixTransform(
                        osg::Matrixd::translate(x0 + kCellSize / 2, y0 + kCellSize / 2, 0.0));
                    osg::ref_ptr<osg::LOD> lod = new osg::LOD;
                    // The range is measured from the eye to a user-defined centre
                    // (the middle of the building), not to the bounding-sphere
                    // centre. The LOD's radius is left unset so its bound is the
                    // union of its children's bounds, which is the same box sphere.
                    lod->setCenterMode(osg::LOD::USER_DEFINED_CENTER);
                    lod->setCenter(osg::Vec3(0.0f, 0.0f, float(h) / 2.0f));
                    lod->setRangeMode(osg::LOD::DISTANCE_FROM_EYE_POINT);
                    osg::ref_ptr<osg::Geode> detailGeode = new osg::Geode;
                    detailGeode->addDrawable(detailed[k].get());
                    osg::ref_ptr<osg::Geode> coarseGeode = new osg::Geode;
                    coarseGeode->addDrawable(coarse[k].get());
                    // OSG's LOD selects child c when min <= distance < max.
                    lod->addChild(detailGeode.get(), 0.0f, kDetailFar);
                    lod->addChild(coarseGeode.get(), kDetailFar, kCoarseFar);
                    buildingXf->addChild(lod.get());

                    osg::ref_ptr<osg::MatrixTransform> carXf = new osg::MatrixTransform(
                        osg::Matrixd::translate(x0 + kCarOffset, y0 + kCarOffset, 0.0));
                    osg::ref_ptr<osg::Geode> carGeode = new osg::Geode;
                    carGeode->addDrawable(car.get());
                    carXf->addChild(carGeode.get());

                    cell->addChild(buildingXf.get());
                    cell->addChild(carXf.get());
                    tile->addChild(cell.get());
                    scene.nodes += 7;  // cell, 2 transforms, LOD, 3 geodes
                }
            }
        }
    }

    // Compute every bounding sphere now (OSG computes them lazily on first
    // use), so the cull passes never pay for it.
    scene.root->getBound();
    return scene;
}

// ---------------------------------------------------------------------------
// Orbit camera path.

osg::Matrixd orbitView(int n, int frame) {
    const double a = 2.0 * M_PI * frame / kFrames;
    const osg::Vec3d c(10.0 * n, 10.0 * n, 0.0);
    const osg::Vec3d eye = c + osg::Vec3d(5.0 * n * std::cos(a), 5.0 * n * std::sin(a), 40.0);
    osg::Vec3d d(-std::sin(a), std::cos(a), -0.15);
    d.normalize();
    return osg::Matrixd::lookAt(eye, eye + d, osg::Vec3d(0.0, 0.0, 1.0));
}

// ---------------------------------------------------------------------------
// Verification: walk the render graph the cull produced and count the draw
// leaves (one RenderLeaf per selected Geometry instance) and their triangles.

struct DrawCount {
    uint64_t leaves = 0;
    uint64_t triangles = 0;
};

void countLeaf(const osgUtil::RenderLeaf* leaf, const Scene& scene, DrawCount& out) {
    ++out.leaves;
    auto it = scene.triangles.find(leaf->getDrawable());
    if (it != scene.triangles.end()) out.triangles += it->second;
}

void countBin(const osgUtil::RenderBin& bin, const Scene& scene, DrawCount& out) {
    // State-sorted bins keep leaves in their StateGraphs; depth-sorted bins
    // move them to the RenderLeafList. A leaf is in exactly one of the two.
    for (const osgUtil::StateGraph* sg : bin.getStateGraphList())
        for (const auto& leaf : sg->_leaves) countLeaf(leaf.get(), scene, out);
    for (const osgUtil::RenderLeaf* leaf : bin.getRenderLeafList()) countLeaf(leaf, scene, out);
    for (const auto& child : bin.getRenderBinList()) countBin(*child.second, scene, out);
}

DrawCount countStage(const osgUtil::RenderStage& stage, const Scene& scene) {
    DrawCount out;
    for (const auto& pre : stage.getPreRenderList()) countBin(*pre.second, scene, out);
    countBin(stage, scene, out);
    for (const auto& post : stage.getPostRenderList()) countBin(*post.second, scene, out);
    return out;
}

// ---------------------------------------------------------------------------
// Utilities.

double rssBytes() {
    long pages = 0, resident = 0;
    FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0.0;
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
    return double(resident) * double(sysconf(_SC_PAGESIZE));
}

// Route all OSG notifications to stderr so stdout carries only the JSON.
class StderrNotifyHandler : public osg::NotifyHandler {
public:
    void notify(osg::NotifySeverity, const char* message) override { std::fputs(message, stderr); }
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return (v.size() % 2) ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double percentile95(std::vector<double> v) {
    // Nearest-rank percentile.
    std::sort(v.begin(), v.end());
    size_t rank = size_t(std::ceil(0.95 * double(v.size())));
    return v[std::max<size_t>(rank, 1) - 1];
}

[[noreturn]] void usage(const char* msg) {
    std::fprintf(stderr, "error: %s\nusage: sgbench_osg [--n N] [--frames-passes K] [--with-sgkit]\n", msg);
    std::exit(2);
}

long parsePositive(const char* s, const char* what) {
    char* end = nullptr;
    long v = std::strtol(s, &end, 10);
    if (!end || *end != '\0' || v <= 0) usage((std::string("invalid value for ") + what).c_str());
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    int n = 316;
    int passes = 1;
    bool withSgkit = false;
    for (int a = 1; a < argc; ++a) {
        if (!std::strcmp(argv[a], "--n") && a + 1 < argc)
            n = int(parsePositive(argv[++a], "--n"));
        else if (!std::strcmp(argv[a], "--with-sgkit"))
            withSgkit = true;
        else if (!std::strcmp(argv[a], "--frames-passes") && a + 1 < argc)
            passes = int(parsePositive(argv[++a], "--frames-passes"));
        else
            usage((std::string("unknown or incomplete argument: ") + argv[a]).c_str());
    }

    osg::setNotifyHandler(new StderrNotifyHandler);

    // --- Build ---------------------------------------------------------------
    const double rssBefore = rssBytes();
    const auto buildStart = std::chrono::steady_clock::now();
    Scene scene = buildCity(n);
    const auto buildEnd = std::chrono::steady_clock::now();
    const double rssAfter = rssBytes();
    const double buildSeconds = std::chrono::duration<double>(buildEnd - buildStart).count();

#ifdef SGBENCH_WITH_SGKIT
    // In-process comparison: sgkit's own city, culled right after OpenSceneGraph's on every frame, so
    // that both see the same machine speed (this machine's speed drifts for seconds at a time).
    std::unique_ptr<sg::Scene> sgScene;
    sg::CullTraversal sgCull;
    sg::DrawList sgList;
    std::vector<double> sgMs, ratio;
    double sgGeometries = 0.0;
    if (withSgkit) {
        sgScene = std::make_unique<sg::Scene>(scenes::buildCity({n, false}));
        sgScene->update();
    }
#else
    if (withSgkit) usage("--with-sgkit: this build has no sgkit (configure it inside the sgkit project)");
#endif

    // --- Cull setup ------------------------------------------------------------
    // SceneView is what osgViewer::Renderer drives per camera; setDefaults()
    // creates the osg::State (no GL context is touched during cull), the
    // CullVisitor, the StateGraph and the RenderStage, plus the standard
    // global state set and headlight a viewer would also have.
    osg::ref_ptr<osgUtil::SceneView> sceneView = new osgUtil::SceneView;
    sceneView->setDefaults();
    osg::ref_ptr<osg::FrameStamp> frameStamp = new osg::FrameStamp;
    sceneView->setFrameStamp(frameStamp.get());
    sceneView->setViewport(0, 0, kViewportW, kViewportH);
    sceneView->setProjectionMatrix(osg::Matrixd::perspective(kFovY, kAspect, kNear, kFar));
    sceneView->setSceneData(scene.root.get());

    // Cull settings must be set after setDefaults() (which resets them). The
    // SceneView is itself the CullSettings that cull() copies into its
    // CullVisitor every frame (CullVisitor::inheritCullSettings).
    const unsigned cullingMode = osg::CullSettings::VIEW_FRUSTUM_SIDES_CULLING |
                                 osg::CullSettings::NEAR_PLANE_CULLING |
                                 osg::CullSettings::FAR_PLANE_CULLING;
    sceneView->setCullingMode(cullingMode);
    sceneView->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);

    // --- Warm-up + timed passes -----------------------------------------------
    std::vector<double> frameMs;
    frameMs.reserve(size_t(passes) * kFrames);
    double geometriesSum = 0.0, trianglesSum = 0.0;
    unsigned frameNumber = 0;

    for (int pass = 0; pass <= passes; ++pass) {
        const bool timed = pass > 0;  // pass 0 is the untimed warm-up
        for (int f = 0; f < kFrames; ++f) {
            sceneView->setViewMatrix(orbitView(n, f));
            ++frameNumber;
            frameStamp->setFrameNumber(frameNumber);
            frameStamp->setReferenceTime(frameNumber / 60.0);
            frameStamp->setSimulationTime(frameNumber / 60.0);

            const auto t0 = std::chrono::steady_clock::now();
            sceneView->cull();
            const auto t1 = std::chrono::steady_clock::now();

            if (pass == 0 && f == 0) {
                // Guard against the settings being silently overridden.
                const osgUtil::CullVisitor* cv = sceneView->getCullVisitor();
                if (cv->getCullingMode() != cullingMode ||
                    cv->getComputeNearFarMode() != osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR) {
                    std::fprintf(stderr, "error: CullVisitor did not inherit the cull settings "
                                         "(mode 0x%x, near/far mode %d)\n",
                                 cv->getCullingMode(), int(cv->getComputeNearFarMode()));
                    return 1;
                }
            }

#ifdef SGBENCH_WITH_SGKIT
            if (sgScene) {
                const sg::Camera cam = scenes::cityOrbitCamera(n, f);
                sg::CullStats st;
                const auto s0 = std::chrono::steady_clock::now();
                sgCull.cull(*sgScene, cam, sg::CullSettings{}, sgList, st);
                const auto s1 = std::chrono::steady_clock::now();
                if (timed) {
                    sgMs.push_back(std::chrono::duration<double, std::milli>(s1 - s0).count());
                    ratio.push_back(std::chrono::duration<double>(t1 - t0).count() / std::chrono::duration<double>(s1 - s0).count());
                    sgGeometries += double(st.geometries);
                }
            }
#endif
            if (timed) {
                frameMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
                const DrawCount dc = countStage(*sceneView->getRenderStage(), scene);
                geometriesSum += double(dc.leaves);
                trianglesSum += double(dc.triangles);
            }
        }
    }

    const double timedFrames = double(frameMs.size());
    const double geometriesMean = geometriesSum / timedFrames;
    if (geometriesMean <= 0.0) {
        std::fprintf(stderr, "error: the cull produced no draw leaves on the orbit path\n");
        return 1;
    }

    std::printf("{\"peer\":\"openscenegraph\",\"osg_version\":\"%s\",\"n\":%d,\"path\":\"orbit\","
                "\"frames\":%d,\"cull_ms_median\":%.4f,\"cull_ms_p95\":%.4f,"
                "\"geometries_mean\":%.2f,\"triangles_mean\":%.1f,\"build_s\":%.4f,"
                "\"rss_mb\":%.2f,\"nodes\":%llu,\"bytes_per_node\":%.2f",
                osgGetVersion(), n, kFrames, median(frameMs), percentile95(frameMs),
                geometriesMean, trianglesSum / timedFrames, buildSeconds,
                rssAfter / (1024.0 * 1024.0), (unsigned long long)scene.nodes,
                (rssAfter - rssBefore) / double(scene.nodes));
#ifdef SGBENCH_WITH_SGKIT
    if (sgScene)
        std::printf(",\"sgkit_cull_ms_median\":%.4f,\"sgkit_geometries_mean\":%.2f,\"osg_over_sgkit_per_frame_median\":%.3f",
                    median(sgMs), sgGeometries / double(sgMs.size()), median(ratio));
#endif
    std::printf("}\n");
    std::fflush(stdout);

    // Skip tearing the scene down. Each shared Geometry keeps its parent Geodes
    // in a std::vector and osg::Node::removeParent erases from it one entry at a
    // time, so destroying the graph is quadratic in the number of instances
    // (minutes at N=1000, where the car Geometry has a million parents). Nothing
    // is measured after this point, so let the OS reclaim the memory.
    std::_Exit(0);
}
