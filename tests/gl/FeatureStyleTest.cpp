// Per-feature colours (Renderer::setFeatureStyle): a feature's colour multiplies the base colour, a hidden feature is
// neither drawn nor picked, and a restyle or a highlight shows in the next frame with nothing reloaded. Each picture
// is compared pixel for pixel with the same scene built without the style (meshes cut and materials tinted by hand).
#include "RenderUtil.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/style/FeatureStyle.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

constexpr int kW = 120, kH = 90;

// Quads side by side along x facing +Z, quad i over x in [2i - n, 2i - n + 2) (each a feature, by vertex).
struct Quads {
    std::vector<vec3> positions, normals;
    std::vector<uint32_t> indices, ids;
    explicit Quads(const std::vector<int>& which, int n) {
        for (int i : which) {
            const float x0 = float(2 * i - n) * 0.5f, x1 = x0 + 0.9f;
            const uint32_t b = uint32_t(positions.size());
            positions.insert(positions.end(), {{x0, -0.5f, 0}, {x1, -0.5f, 0}, {x1, 0.5f, 0}, {x0, 0.5f, 0}});
            normals.insert(normals.end(), 4, vec3(0, 0, 1));
            indices.insert(indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
            ids.insert(ids.end(), 4, uint32_t(i));
        }
    }
    ref_ptr<Mesh> mesh() const {
        auto m = make<Mesh>();
        m->set(positions, normals, indices);
        return m;
    }
};

// A store with one class and a table of n rows (no columns: the style's rule needs only the ids here).
ref_ptr<PropertyStore> storeOf(uint64_t n) {
    auto s = make<PropertyStore>();
    ClassDef c;
    c.id = "part";
    s->schema.classes.push_back(c);
    PropertyTable t;
    t.name = "parts";
    t.classIndex = 0;
    t.count = n;
    s->addTable(t);
    return s;
}

ref_ptr<Mesh> featured(const Quads& q, const ref_ptr<PropertyStore>& store) {
    auto m = q.mesh();
    auto f = make<MeshFeatures>();
    FeatureIdSet set;
    set.source = FeatureIdSet::Source::Attribute;
    set.featureCount = uint32_t(store->tables()[0].count);
    set.propertyTable = 0;
    set.ids = q.ids;
    f->sets.push_back(set);
    f->store = store;
    m->setFeatures(f);
    return m;
}

size_t differing(const Image& a, const Image& b) {
    size_t n = 0;
    for (size_t i = 0; i + 3 < a.rgba.size() && i + 3 < b.rgba.size(); i += 4)
        if (a.rgba[i] != b.rgba[i] || a.rgba[i + 1] != b.rgba[i + 1] || a.rgba[i + 2] != b.rgba[i + 2]) ++n;
    return n;
}

struct FeatureStyleTest : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;
    Camera cam;
    ref_ptr<PropertyStore> store = storeOf(3);
    ref_ptr<FeatureStyle> style = make<FeatureStyle>();
    FeatureStyleTest() {
        cam.setLookAt(dvec3(0, 0, 4), dvec3(0.0), dvec3(0, 1, 0));
        cam.setPerspective(45.0, double(kW) / kH, 0.1, 100.0);
        cam.setViewport(kW, kH);
    }
    Image draw(const ref_ptr<Node>& root) { return testutil::drawGraph(renderer, root, cam); }
    // The scene as the style should show it, built by hand: the shown quads, each in its tinted material.
    Image expected(const std::vector<std::pair<int, vec3>>& shown) {
        auto g = make<Group>();
        for (const auto& [i, tint] : shown)
            g->addChild(make<Geometry>(Quads({i}, 3).mesh(), make<Material>(vec4(vec3(0.8f) * tint, 1.0f))));
        renderer.setFeatureStyle(nullptr);
        Image img = draw(g);
        renderer.setFeatureStyle(style);
        return img;
    }
};

}  // namespace

TEST_F(FeatureStyleTest, AFeaturesColourMultipliesTheBaseColourAndAlphaZeroHidesIt) {
    style->setRule([](const PropertyStore&, int, std::vector<uint8_t>& rgba) {
        rgba[0] = 255, rgba[1] = 0, rgba[2] = 0;  // feature 0 red
        rgba[7] = 0;                              // feature 1 hidden
    });
    renderer.setFeatureStyle(style);
    auto root = make<Geometry>(featured(Quads({0, 1, 2}, 3), store), make<Material>());
    const Image got = draw(root);
    const Image want = expected({{0, vec3(1, 0, 0)}, {2, vec3(1)}});
    EXPECT_EQ(differing(got, want), 0u);
    EXPECT_GT(differing(got, expected({{0, vec3(1)}, {1, vec3(1)}, {2, vec3(1)}})), 100u);  // the style shows
}

TEST_F(FeatureStyleTest, ARestyleAndAHighlightShowInTheNextFrameWithNothingReloaded) {
    renderer.setFeatureStyle(style);
    auto root = make<Geometry>(featured(Quads({0, 1, 2}, 3), store), make<Material>());
    EXPECT_EQ(differing(draw(root), expected({{0, vec3(1)}, {1, vec3(1)}, {2, vec3(1)}})), 0u);  // no rule: as is
    style->setRule([](const PropertyStore&, int, std::vector<uint8_t>& rgba) { rgba[3] = 0; });
    EXPECT_EQ(differing(draw(root), expected({{1, vec3(1)}, {2, vec3(1)}})), 0u);
    style->setHighlight(store.get(), 0, 2, vec4(0, 1, 0, 1));
    EXPECT_EQ(differing(draw(root), expected({{1, vec3(1)}, {2, vec3(0, 1, 0)}})), 0u);
    style->setHighlight(nullptr, 0, -1, vec4(1));
    EXPECT_EQ(differing(draw(root), expected({{1, vec3(1)}, {2, vec3(1)}})), 0u);
}

TEST_F(FeatureStyleTest, APickPassesThroughAHiddenFeatureToWhatIsBehindIt) {
    auto root = make<Group>();
    auto front = make<Geometry>(featured(Quads({0, 1, 2}, 3), store), make<Material>());
    auto back = make<Geometry>(Quads({1}, 3).mesh(), make<Material>());
    auto behind = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, -1)));
    behind->addChild(back);
    root->addChild(front);
    root->addChild(behind);
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    QueryOptions o;
    o.style = style.get();
    const double xMid = (2 * 1 - 3) * 0.5 + 0.45;  // the middle of quad 1
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(xMid, 0, 4), dvec3(0, 0, -1)}, o, h));
    EXPECT_EQ(h.geometry, front.get());  // shown
    style->setRule([](const PropertyStore&, int, std::vector<uint8_t>& rgba) { rgba[7] = 0; });
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(xMid, 0, 4), dvec3(0, 0, -1)}, o, h));
    EXPECT_EQ(h.geometry, back.get());  // through the hidden feature
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(xMid - 1.0, 0, 4), dvec3(0, 0, -1)}, o, h));
    EXPECT_EQ(h.geometry, front.get());  // feature 0 still hit
    o.style = nullptr;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(xMid, 0, 4), dvec3(0, 0, -1)}, o, h));
    EXPECT_EQ(h.geometry, front.get());  // without the style the hidden feature is there
}

TEST_F(FeatureStyleTest, NodesThatAreFeaturesAreColouredAndHiddenByTheirRow) {
    // Three Transforms over one shared quad mesh, each a feature (Node::setFeatures): the mesh cannot say which
    // feature it is, the node does (a city's buildings).
    auto sets = make<MeshFeatures>();
    FeatureIdSet set;
    set.source = FeatureIdSet::Source::Instance;
    set.featureCount = 3;
    set.propertyTable = 0;
    set.ids = {2, 0, 1};  // node k is feature ids[k]
    sets->sets.push_back(set);
    sets->store = store;
    const ref_ptr<Mesh> quad = Quads({0}, 3).mesh();
    auto mat = make<Material>();
    auto root = make<Group>();
    for (int k = 0; k < 3; ++k) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(k, 0, 0)));
        t->addChild(make<Geometry>(quad, mat));
        t->setFeatures(sets, uint32_t(k));
        root->addChild(t);
    }
    style->setRule([](const PropertyStore&, int, std::vector<uint8_t>& rgba) {
        rgba[0 * 4 + 1] = 0, rgba[0 * 4 + 2] = 0;  // feature 0 (node 1) red
        rgba[2 * 4 + 3] = 0;                       // feature 2 (node 0) hidden
    });
    renderer.setFeatureStyle(style);
    const Image got = draw(root);
    // Quads({i}) sits at x = i - 1.5: node k's quad is Quads({k}).
    const Image want = expected({{1, vec3(1, 0, 0)}, {2, vec3(1)}});
    EXPECT_EQ(differing(got, want), 0u);
    // Picks pass through the hidden node as through a hidden vertex feature.
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    QueryOptions o;
    Hit h;
    const Ray ray{dvec3(-1.5 + 0.45, 0, 4), dvec3(0, 0, -1)};
    EXPECT_TRUE(it.intersect(scene, ray, o, h));
    o.style = style.get();
    EXPECT_FALSE(it.intersect(scene, ray, o, h));
    // A new binding shows at the next update: node 0 becomes feature 0 (red).
    root->child(0)->setFeatures(sets, 1);
    EXPECT_EQ(differing(draw(root), expected({{0, vec3(1, 0, 0)}, {1, vec3(1, 0, 0)}, {2, vec3(1)}})), 0u);
}
