// The renderer skips the back faces of closed opaque meshes only where they cannot show: every picture is the one
// drawn with the culling off but for ties at silhouette edges (tests/BackFaceCompare.h), and the culling is counted
// where it applies (outside solids) and not where it must not (the eye inside a solid, the near plane cutting one, a
// mirror, cut-outs, open meshes, an orthographic camera).
#include "BackFaceCompare.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

constexpr int kW = 256, kH = 256;

struct BackFaces : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;
    uint64_t skipped = 0;  // with the culling on, in the last compare()

    // Draws the scene with the culling off, then on: the number of pixels that differ other than by a tie at a
    // silhouette edge (0 expected); ties are at most one pixel in 500.
    size_t compare(const ref_ptr<Node>& root, const Camera& cam, Image* picture = nullptr) {
        Scene scene(root);
        scene.update();
        DrawList list;
        CullStats stats;
        CullTraversal().cull(scene, cam, CullSettings{}, list, stats);
        renderer.setBackFaceCulling(false);
        renderer.draw(list, cam);
        EXPECT_EQ(renderer.lastStats().backFacesSkipped, 0u);
        const Image off = renderer.readColor();
        const std::vector<float> offDepth = renderer.readDepth();
        renderer.setBackFaceCulling(true);
        renderer.draw(list, cam);
        skipped = renderer.lastStats().backFacesSkipped;
        if (picture) *picture = off;
        const testutil::BackFaceDiff d =
            testutil::compareBackFaces(off, offDepth, renderer.readColor(), renderer.readDepth());
        EXPECT_LE(d.ties, size_t(kW * kH) / 500);
        return d.wrong;
    }
};

Camera perspective(const dvec3& eye, const dvec3& at, double zNear = 0.5) {
    Camera cam;
    cam.setLookAt(eye, at, dvec3(0, 1, 0));
    cam.setPerspective(50.0, 1.0, zNear, 100.0);
    cam.setViewport(kW, kH);
    return cam;
}

ref_ptr<Node> placed(const dmat4& m, const ref_ptr<Mesh>& mesh, const ref_ptr<Material>& mat) {
    auto t = make<Transform>(m);
    t->addChild(make<Geometry>(mesh, mat));
    return t;
}

// Pixels of the clear colour: where nothing was drawn.
size_t background(const Image& img) {
    const vec4 c = Renderer::kClearColor;
    size_t n = 0;
    for (size_t i = 0; i + 3 < img.rgba.size(); i += 4)
        n += std::abs(img.rgba[i] - c.r * 255.0f) < 2.0f && std::abs(img.rgba[i + 1] - c.g * 255.0f) < 2.0f &&
             std::abs(img.rgba[i + 2] - c.b * 255.0f) < 2.0f;
    return n;
}

}  // namespace

TEST_F(BackFaces, SolidsSeenFromOutsideSkipThemAndDrawTheSamePixels) {
    auto root = make<Group>();
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-0.4), dvec3(0.4), 3);
    for (int k = 0; k < 25; ++k) {
        const dmat4 m = glm::rotate(
            glm::rotate(glm::translate(dmat4(1.0), dvec3(k % 5 - 2.0, k / 5 - 2.0, -k * 0.1)), 0.3 * k, dvec3(1, 0, 0)),
            0.5 + 0.2 * k, dvec3(0, 1, 0));
        // Stretched and sheared: the winding is kept, the cofactor normals still right.
        const dmat4 s = glm::scale(dmat4(1.0), dvec3(1.0 + 0.1 * (k % 3), 1.0, 0.7));
        root->addChild(placed(m * s, box, make<Material>(vec4(0.2f + 0.03f * k, 0.6f, 0.9f - 0.03f * k, 1.0f))));
    }
    Image picture;
    EXPECT_EQ(compare(root, perspective(dvec3(0.5, 1.0, 8.0), dvec3(0.0)), &picture), 0u);
    EXPECT_EQ(skipped, 25u);
    EXPECT_LT(background(picture), size_t(kW * kH) * 3 / 4);  // the boxes fill the picture
}

TEST_F(BackFaces, AnEyeInsideASolidSeesItsInside) {
    auto root = make<Group>();
    root->addChild(placed(dmat4(1.0), makeBoxMesh(dvec3(-5), dvec3(5), 2), make<Material>(vec4(0.7f, 0.5f, 0.3f, 1))));
    root->addChild(placed(glm::translate(dmat4(1.0), dvec3(0, 0, -3)), makeBoxMesh(dvec3(-0.5), dvec3(0.5)),
                          make<Material>(vec4(0.2f, 0.8f, 0.3f, 1))));
    Image picture;
    EXPECT_EQ(compare(root, perspective(dvec3(0.0, 0.5, 2.0), dvec3(0.0, 0.0, -3.0)), &picture), 0u);
    EXPECT_EQ(skipped, 1u);              // the small box, not the room around the eye
    EXPECT_EQ(background(picture), 0u);  // the room's walls all round
}

TEST_F(BackFaces, ANearPlaneCuttingASolidShowsItsInside) {
    // The eye outside the box, 0.3 from its face, the near plane 0.5 ahead: the plane cuts the box open.
    auto root = make<Group>();
    root->addChild(placed(dmat4(1.0), makeBoxMesh(dvec3(-1), dvec3(1), 4), make<Material>(vec4(0.9f, 0.4f, 0.2f, 1))));
    Image picture;
    EXPECT_EQ(compare(root, perspective(dvec3(0.0, 0.0, 1.3), dvec3(0.0, 0.0, -1.0), 0.5), &picture), 0u);
    EXPECT_EQ(skipped, 0u);
    EXPECT_EQ(background(picture), 0u);  // the inside of the box fills the view
    // Backed off so that the near plane clears it: now it qualifies.
    EXPECT_EQ(compare(root, perspective(dvec3(0.0, 0.0, 3.0), dvec3(0.0, 0.0, -1.0), 0.5)), 0u);
    EXPECT_EQ(skipped, 1u);
}

TEST_F(BackFaces, MirrorsCutOutsBlendedOpenMeshesAndOrthographicViewsKeepThem) {
    auto root = make<Group>();
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-0.5), dvec3(0.5), 2);
    root->addChild(placed(glm::scale(glm::translate(dmat4(1.0), dvec3(-1.5, 0, 0)), dvec3(-1, 1, 1)), box,
                          make<Material>(vec4(0.9f, 0.3f, 0.3f, 1))));  // mirrored
    auto cut = make<Material>(vec4(0.3f, 0.9f, 0.3f, 0.4f));
    cut->alphaCutoff = 0.5f;  // every fragment cut: a solid that is not opaque
    root->addChild(placed(dmat4(1.0), box, cut));
    auto glass = make<Material>(vec4(0.3f, 0.5f, 0.9f, 0.5f));
    glass->physical = true;
    glass->blend = true;  // blended: its back faces show through its front ones
    root->addChild(placed(glm::translate(dmat4(1.0), dvec3(0.0, 1.2, 0.0)), box, glass));
    auto quad = make<Mesh>();
    quad->set({{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}}, {}, {0, 1, 2, 0, 2, 3});
    root->addChild(placed(glm::rotate(glm::translate(dmat4(1.0), dvec3(1.5, 0, 0)), 3.0, dvec3(0, 1, 0)), quad,
                          make<Material>(vec4(0.3f, 0.3f, 0.9f, 1))));  // seen from behind
    const Camera cam = perspective(dvec3(0.3, 0.8, 5.0), dvec3(0.0));
    Image picture;
    EXPECT_EQ(compare(root, cam, &picture), 0u);
    EXPECT_EQ(skipped, 0u);
    EXPECT_LT(background(picture), size_t(kW * kH));  // the mirrored box and the quad's back show

    Camera ortho = cam;
    ortho.setProjection(glm::ortho(-3.0, 3.0, -3.0, 3.0, 0.5, 100.0));
    auto solid = make<Group>();
    solid->addChild(placed(dmat4(1.0), box, make<Material>()));
    EXPECT_EQ(compare(solid, ortho), 0u);
    EXPECT_EQ(skipped, 0u);
}
