// sgview's parts without GL: command line, cameras, --info counts.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "sgview/Info.h"
#include "sgview/Options.h"
#include "sgview/ViewCamera.h"
#include "testbed/City.h"
#include "testbed/Office.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace sg;
using namespace sgview;

namespace {

Options parse(std::vector<const char*> args) {
    args.insert(args.begin(), "sgview");
    return parseOptions(int(args.size()), args.data());
}

// The UsageError message of a bad command line ("" when it parses).
std::string error(std::vector<const char*> args) {
    try {
        parse(std::move(args));
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(SgviewOptions, ParsesTheHeadlessCommand) {
    const Options o = parse({"--headless", "--scene", "city", "--n", "8", "--frames", "2", "--out", "x.png", "--camera",
                             "1,2,3,4,5,6,0,0,1", "--size", "320x240", "--strategy", "sphere", "--occlusion", "off"});
    EXPECT_TRUE(o.headless);
    EXPECT_EQ(o.scene, "city");
    EXPECT_EQ(o.n, 8);
    EXPECT_EQ(o.frames, 2);
    EXPECT_EQ(o.out, "x.png");
    ASSERT_TRUE(o.camera.has_value());
    EXPECT_EQ(o.camera->eye, dvec3(1, 2, 3));
    EXPECT_EQ(o.camera->center, dvec3(4, 5, 6));
    EXPECT_EQ(o.camera->up, dvec3(0, 0, 1));
    EXPECT_EQ(o.width, 320);
    EXPECT_EQ(o.height, 240);
    EXPECT_EQ(o.strategy, CullStrategy::Sphere);
    EXPECT_EQ(o.occlusion, OcclusionMode::Off);
}

TEST(SgviewOptions, Defaults) {
    const Options city = parse({"--scene", "city"});
    EXPECT_EQ(city.n, 32);
    EXPECT_EQ(city.frames, 0);  // window: until closed
    EXPECT_EQ(parse({"--scene", "office"}).n, 6);
    EXPECT_EQ(parse({"--headless", "--scene", "city"}).frames, 1);
    const Options files = parse({"a.gltf", "b.glb"});
    EXPECT_EQ(files.files, (std::vector<std::string>{"a.gltf", "b.glb"}));
}

TEST(SgviewOptions, BadValuesNameTheOptionAndTheValue) {
    EXPECT_EQ(error({"--scene", "city", "--bogus"}), "unknown option '--bogus'");
    EXPECT_NE(error({"--scene", "city", "--camera", "1,2,3"}).find("--camera '1,2,3': expected eye,center,up"),
              std::string::npos);
    EXPECT_NE(error({"--scene", "city", "--camera", "1,2,3,4,5,6,0,0,1,"}).find("--camera '1,2,3,4,5,6,0,0,1,'"),
              std::string::npos);
    EXPECT_NE(error({"--scene", "city", "--camera", "1,2,3,4,5,6,0,0,nan"}).find("--camera"), std::string::npos);
    // Nine numbers that make no camera: the reason is Camera::setLookAt's.
    const std::string same = error({"--scene", "city", "--camera", "1,1,1,1,1,1,0,0,1"});
    EXPECT_NE(same.find("--camera '1,1,1,1,1,1,0,0,1': Camera::setLookAt()"), std::string::npos) << same;
    const std::string parallel = error({"--scene", "city", "--camera", "0,0,5,0,0,0,0,0,1"});  // up along the view
    EXPECT_NE(parallel.find("Camera::setLookAt(): up is zero or parallel"), std::string::npos) << parallel;
    for (const char* size : {"0x10", "10x0", "12", "10x10x", "x10", "-5x10", "10 x10", "99999x10", "+5x5", ""})
        EXPECT_NE(error({"--scene", "city", "--size", size}).find(std::string("--size '") + size + "': expected WxH"),
                  std::string::npos)
            << size;
    EXPECT_NE(error({"--scene", "city", "--frames", "-1"}).find("--frames '-1': expected an integer"),
              std::string::npos);
    EXPECT_NE(error({"--scene", "city", "--frames", "2x"}).find("--frames '2x'"), std::string::npos);
    EXPECT_NE(error({"--scene", "city", "--n", "abc"}).find("--n 'abc'"), std::string::npos);
    EXPECT_NE(error({"--scene", "park"})
                  .find("--scene 'park': the built-in scenes are city, office, factory, materials and figures"),
              std::string::npos);
    EXPECT_NE(error({"--scene", "city", "--strategy", "fast"}).find("--strategy 'fast': parseStrategy()"),
              std::string::npos);
    EXPECT_NE(error({"--scene", "city", "--occlusion", "maybe"}).find("--occlusion 'maybe'"), std::string::npos);
    EXPECT_EQ(error({"--scene", "city", "--size"}), "--size needs a value");
}

TEST(SgviewOptions, ContradictionsAreRefused) {
    EXPECT_NE(error({}).find("nothing to show"), std::string::npos);
    EXPECT_NE(error({"a.gltf", "--scene", "city"}).find("either FILE... or --scene"), std::string::npos);
    EXPECT_NE(error({"a.gltf", "--n", "4"}).find("--n sizes a built-in scene"), std::string::npos);
    EXPECT_NE(error({"--scene", "city", "--out", "x.png"}).find("--out in the window needs --frames K"),
              std::string::npos);
    EXPECT_EQ(error({"--scene", "city", "--frames", "3", "--out", "x.png"}), "");
    EXPECT_EQ(parse({"--scene", "city"}).out, "");  // the window writes nothing unless asked
    EXPECT_EQ(parse({"--scene", "city", "--headless"}).out, "sgview.png");
    EXPECT_EQ(error({"--help"}), "");
}

// The network options: headers kept in order, a header that is not "Name: value" refused, the cache's two forms.
TEST(SgviewOptions, NetworkOptions) {
    const Options o = parse({"http://h/tileset.json", "--header", "Authorization: Bearer x", "--header", "X-A: 1",
                             "--ca-file", "ca.pem", "--cache", "/tmp/c"});
    EXPECT_EQ(o.headers, (std::vector<std::string>{"Authorization: Bearer x", "X-A: 1"}));
    EXPECT_EQ(o.caFile, "ca.pem");
    EXPECT_EQ(o.cacheDir, "/tmp/c");
    EXPECT_FALSE(o.noCache);
    EXPECT_TRUE(parse({"http://h/tileset.json", "--no-cache"}).noCache);
    EXPECT_NE(error({"t.json", "--header", "Bearer x"}).find("expected \"Name: value\""), std::string::npos);
    EXPECT_NE(error({"t.json", "--cache", "/c", "--no-cache"}).find("give one"), std::string::npos);
    EXPECT_NE(error({"--scene", "city", "--header", "A: b"}).find("for a tileset's URL"), std::string::npos);
}

TEST(SgviewCamera, AutoCameraKeepsTheWholeBoundInView) {
    const Box b{dvec3(0, 0, 0), dvec3(640, 640, 60)};
    for (const dvec3& up : {dvec3(0, 0, 1), dvec3(0, 1, 0)})
        for (const auto& [w, h] : {std::pair{1280, 720}, std::pair{300, 900}}) {
            const Camera cam = autoCamera(b, up, w, h);
            int touching = 0;  // corners within 10% of an edge: framed, not lost in the middle
            for (int k = 0; k < 8; ++k) {
                const dvec3 p((k & 1 ? b.max : b.min).x, (k & 2 ? b.max : b.min).y, (k & 4 ? b.max : b.min).z);
                const dvec4 clip = cam.projection() * cam.view() * dvec4(p, 1.0);
                ASSERT_GT(clip.w, 0.0);
                const double x = clip.x / clip.w, y = clip.y / clip.w, z = clip.z / clip.w;
                EXPECT_LE(std::abs(x), 1.0);
                EXPECT_LE(std::abs(y), 1.0);
                EXPECT_GT(z, -1.0);  // between the planes
                EXPECT_LT(z, 1.0);
                touching += std::max(std::abs(x), std::abs(y)) > 0.9;
            }
            EXPECT_GE(touching, 1);
            EXPECT_NEAR(glm::dot(cam.viewDirection(), glm::normalize(b.center() - cam.eye())), 1.0, 1e-12);
            EXPECT_GT(glm::dot(cam.eye() - b.center(), up), 0.0);  // from above
        }
}

TEST(SgviewCamera, ClipPlanesHoldTheBound) {
    const Box b{dvec3(-1, -2, -3), dvec3(1, 2, 3)};
    const double r = glm::length(b.halfExtent());
    double n = 0, f = 0;
    clipPlanes(b, dvec3(0, 0, 100), n, f);
    EXPECT_GE(f, 100 + r);
    EXPECT_LE(n, 100 - r);
    EXPECT_GT(n, 0.0);
    clipPlanes(b, dvec3(0), n, f);  // inside: near is far / 10^4
    EXPECT_GE(f, r);
    EXPECT_DOUBLE_EQ(n, f * 1e-4);
}

namespace {

// The test's own count of the nodes below `n` by kind (the built-in scenes share no node).
void countKinds(const Node& n, std::array<uint64_t, kNodeKinds>& kinds) {
    kinds[size_t(n.kind())]++;
    for (size_t i = 0; i < n.numChildren(); ++i) countKinds(*n.child(i), kinds);
}

}  // namespace

TEST(SgviewInfo, EveryNodeKindIsCountedAPagedOneToo) {
    auto root = make<Group>();
    auto paged = make<PagedLOD>();
    paged->setFile("detail.glb");
    paged->addChild(make<Geometry>(makeBoxMesh(dvec3(0), dvec3(1)), make<Material>()));
    root->addChild(paged);
    Scene scene(root);
    scene.update();
    const SceneInfo info = computeInfo(*root, scene);
    EXPECT_EQ(info.kinds[size_t(NodeKind::PagedLOD)], 1u);
    EXPECT_EQ(info.kinds[size_t(NodeKind::Geometry)], 1u);
    EXPECT_EQ(info.nodes, 3u);
}

TEST(SgviewInfo, CityCountsMatchTheBuilder) {
    const int n = 8;
    const auto root = scenes::buildCity({n, false});
    Scene scene(root);
    scene.update();
    const SceneInfo info = computeInfo(*root, scene);
    std::array<uint64_t, kNodeKinds> kinds{};
    countKinds(*root, kinds);
    EXPECT_EQ(info.kinds, kinds);
    EXPECT_EQ(info.nodes, scenes::cityNodeCount(n));
    EXPECT_EQ(info.paths, scenes::cityNodeCount(n));
    EXPECT_EQ(info.kinds[size_t(NodeKind::LOD)], uint64_t(n * n));
    EXPECT_EQ(info.kinds[size_t(NodeKind::Geometry)], uint64_t(3 * n * n));  // two levels and a car per cell
    // Full detail: each building's 10 x 10-split box (1200 triangles) and its car (12).
    EXPECT_EQ(info.triangles, uint64_t(n * n * (1200 + 12)));
    EXPECT_EQ(info.materials, 2u);
    EXPECT_TRUE(info.boundValid);
    EXPECT_LE(info.bound.min.x, 1.0);
    EXPECT_GE(info.bound.max.x, 20.0 * (n - 1) + 16.0);
    EXPECT_GE(info.bound.max.z, 59.0 - 1e-3);
    EXPECT_GT(info.meshBytes, 0u);
    EXPECT_EQ(info.imageBytes, scene.bytes());
}

TEST(SgviewInfo, OfficeCountsMatchTheBuilder) {
    scenes::OfficeCounts c;
    const auto root = scenes::buildOffice(3, &c);
    Scene scene(root);
    scene.update();
    const SceneInfo info = computeInfo(*root, scene);
    const uint64_t boxes = uint64_t(c.rooms + c.wallBoxes + c.furnitureBoxes);  // floors, walls, furniture
    EXPECT_EQ(info.kinds[size_t(NodeKind::Geometry)], boxes);
    EXPECT_EQ(info.kinds[size_t(NodeKind::Transform)], boxes);
    EXPECT_EQ(info.kinds[size_t(NodeKind::Occluder)], uint64_t(c.wallBoxes));
    EXPECT_EQ(info.kinds[size_t(NodeKind::Group)], uint64_t(c.rooms + 1));
    EXPECT_EQ(info.triangles, boxes * 12);
    EXPECT_EQ(info.materials, 4u);
}

TEST(SgviewInfo, SharedNodesCountOnceTrianglesPerPath) {
    auto g = make<Geometry>(makeBoxMesh(dvec3(0), dvec3(1)), make<Material>());  // 12 triangles
    auto a = make<Group>(), b = make<Group>(), root = make<Group>();
    a->addChild(g);
    b->addChild(g);
    root->addChild(a);
    root->addChild(b);
    root->addChild(make<Instance>(a, glm::translate(dmat4(1.0), dvec3(5, 0, 0))));
    auto lod = make<LOD>();  // only the finest child counts
    lod->addChild(make<Geometry>(makeBoxMesh(dvec3(0), dvec3(1), 2), nullptr), 0.0f, 10.0f);  // 48
    lod->addChild(make<Geometry>(makeBoxMesh(dvec3(0), dvec3(1), 4), nullptr), 10.0f, 20.0f);
    root->addChild(lod);
    auto sw = make<Switch>();  // only the children that are on
    sw->addChild(g, false);
    sw->addChild(make<Geometry>(makeBoxMesh(dvec3(0), dvec3(1), 3), nullptr), true);  // 108
    root->addChild(sw);
    Scene scene(root);
    scene.update();
    const SceneInfo info = computeInfo(*root, scene);
    EXPECT_EQ(info.nodes, 10u);  // root, a, b, g, the instance, the LOD and its 2, the switch and its 1 (g once)
    EXPECT_EQ(info.kinds[size_t(NodeKind::Geometry)], 4u);
    EXPECT_EQ(info.kinds[size_t(NodeKind::Instance)], 1u);
    // Per path: root, a+g, b+g, instance+a+g, lod+2, switch+g+1.
    EXPECT_EQ(info.paths, 1u + 2 + 2 + 3 + 3 + 3);
    EXPECT_EQ(info.triangles, 3u * 12 + 48 + 108);
    EXPECT_EQ(info.meshes, 4u);
    EXPECT_EQ(info.materials, 1u);
}
