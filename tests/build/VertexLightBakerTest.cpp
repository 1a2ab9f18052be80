// VertexLightBaker: a box on a ground plate, lit by a sun from +x at 45 degrees: shadow, ambient
// occlusion at the box's foot, no direct light on faces turned away, determinism, the disk cache.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/build/VertexLightBaker.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace sg;

namespace {
struct Site {
    ref_ptr<Mesh> ground = makeBoxMesh(dvec3(-10, -10, -1), dvec3(10, 10, 0), 20);
    ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1, -1, 0), dvec3(1, 1, 2), 2);
    ref_ptr<Group> root = make<Group>();
    Scene scene{root};
    Site() {
        root->addChild(make<Geometry>(ground, make<Material>()));
        root->addChild(make<Geometry>(box, make<Material>()));
        scene.update();
    }
    std::vector<BakeTarget> targets() const { return {{ground, dmat4(1.0)}, {box, dmat4(1.0)}}; }
};

VertexLightParams params() {
    VertexLightParams p;
    p.sunDirection = dvec3(1, 0, 1);
    p.sunSamples = 8;
    p.aoSamples = 32;
    p.aoDistance = 3.0;
    return p;
}

// The vertex at `pos` whose normal is `nrm`.
size_t vertexAt(const Mesh& m, const vec3& pos, const vec3& nrm) {
    for (size_t i = 0; i < m.positions().size(); ++i)
        if (glm::length(m.positions()[i] - pos) < 1e-5f && glm::length(m.normals()[i] - nrm) < 1e-5f) return i;
    ADD_FAILURE() << "no vertex at " << pos.x << " " << pos.y << " " << pos.z;
    return 0;
}

std::filesystem::path freshDir(const std::string& name) {
    const auto d = std::filesystem::temp_directory_path() / ("sgkit-vlb-" + name);
    std::filesystem::remove_all(d);
    return d;
}
}  // namespace

TEST(VertexLightBaker, ShadowAwayFromTheSunAndOcclusionAtTheFoot) {
    Site s;
    const auto light = VertexLightBaker::compute(s.scene, s.targets(), params());
    ASSERT_EQ(light.size(), 2u);
    const Mesh& g = *s.ground;
    const vec3 up(0, 0, 1);
    const size_t shadowed = vertexAt(g, vec3(-2, 0, 0), up), lit = vertexAt(g, vec3(6, 0, 0), up);
    const size_t foot = vertexAt(g, vec3(2, 0, 0), up), far = vertexAt(g, vec3(8, 8, 0), up);
    // Open ground sees the whole sun (n.l is the renderer's, per fragment).
    EXPECT_EQ(light[0].sun[lit], 1.0f);
    EXPECT_LT(light[0].sun[shadowed], 0.2f);
    // Sunlit but beside the wall: the box hides part of the sky.
    EXPECT_EQ(light[0].sun[foot], 1.0f);
    EXPECT_LT(light[0].ao[foot], light[0].ao[far] - 0.1f);
    EXPECT_FLOAT_EQ(light[0].ao[far], 1.0f);
    // The box's -x face looks away from the sun; its +x face gets it all.
    const size_t back = vertexAt(*s.box, vec3(-1, 0, 1), vec3(-1, 0, 0));
    const size_t front = vertexAt(*s.box, vec3(1, 0, 1), vec3(1, 0, 0));
    EXPECT_EQ(light[1].sun[back], 0.0f);
    EXPECT_EQ(light[1].sun[front], 1.0f);
}

TEST(VertexLightBaker, DeterministicWhateverTheThreads) {
    Site s;
    VertexLightParams p = params();
    const auto a = VertexLightBaker::compute(s.scene, s.targets(), p);
    p.threads = 1;
    const auto b = VertexLightBaker::compute(s.scene, s.targets(), p);
    for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].sun, b[i].sun);
        EXPECT_EQ(a[i].ao, b[i].ao);
    }
}

TEST(VertexLightBaker, ShadeKeepsOcclusionInTheColourAndTheSunInAlpha) {
    Site s;
    const auto light = VertexLightBaker::compute(s.scene, s.targets(), params());
    const auto c = VertexLightBaker::shade(*s.ground, light[0]);
    const size_t shadowed = vertexAt(*s.ground, vec3(-2, 0, 0), vec3(0, 0, 1));
    const size_t foot = vertexAt(*s.ground, vec3(2, 0, 0), vec3(0, 0, 1));
    const size_t far = vertexAt(*s.ground, vec3(8, 8, 0), vec3(0, 0, 1));
    // The ground has no colours: its albedo is white.
    EXPECT_FLOAT_EQ(c[far].r, 1.0f);
    EXPECT_FLOAT_EQ(c[foot].g, light[0].ao[foot]);
    EXPECT_LT(c[foot].g, 0.95f);
    EXPECT_EQ(c[foot].a, 1.0f);
    EXPECT_LT(c[shadowed].a, 0.2f);
    EXPECT_EQ(c[shadowed].a, light[0].sun[shadowed]);
    VertexLight wrong = light[0];
    wrong.ao.pop_back();
    EXPECT_THROW(VertexLightBaker::shade(*s.ground, wrong), std::invalid_argument);
}

TEST(VertexLightBaker, BadInputRefused) {
    Site s;
    VertexLightParams p = params();
    p.sunDirection = dvec3(0.0);
    try {
        VertexLightBaker::compute(s.scene, s.targets(), p);
        FAIL() << "no exception for a zero sun direction";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("VertexLightBaker::compute(): ", 0), 0u) << e.what();
    }
    EXPECT_THROW(VertexLightBaker::compute(s.scene, {{nullptr, dmat4(1.0)}}, params()), std::invalid_argument);
}

TEST(VertexLightBaker, CacheRoundTripsAndCorruptFilesAreRebaked) {
    const auto dir = freshDir("cache").string();
    std::vector<vec4> ground, box;
    std::string path;
    {
        Site s;
        path = VertexLightBaker::cachePath(s.targets(), params(), 7, dir);
        EXPECT_FALSE(VertexLightBaker::bakeCached(s.scene, s.targets(), params(), 7, dir));
        ground = s.ground->colors();
        box = s.box->colors();
        ASSERT_EQ(ground.size(), s.ground->positions().size());
        ASSERT_TRUE(std::filesystem::exists(path));
    }
    {
        Site s;
        EXPECT_TRUE(VertexLightBaker::bakeCached(s.scene, s.targets(), params(), 7, dir));
        EXPECT_EQ(s.ground->colors(), ground);
        EXPECT_EQ(s.box->colors(), box);
    }
    {  // another key or other parameters: another file
        Site s;
        EXPECT_NE(VertexLightBaker::cachePath(s.targets(), params(), 8, dir), path);
        VertexLightParams p = params();
        p.aoSamples = 16;
        EXPECT_NE(VertexLightBaker::cachePath(s.targets(), p, 7, dir), path);
    }
    {  // flipped bytes in the colours: rebaked, the same colours, the file repaired
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(200);
        const char junk[8] = {'\x7f', '\x7f', '\x7f', '\x7f', '\x7f', '\x7f', '\x7f', '\x7f'};
        f.write(junk, 8);
    }
    {
        Site s;
        EXPECT_FALSE(VertexLightBaker::bakeCached(s.scene, s.targets(), params(), 7, dir));
        EXPECT_EQ(s.ground->colors(), ground);
    }
    {
        Site s;
        EXPECT_TRUE(VertexLightBaker::bakeCached(s.scene, s.targets(), params(), 7, dir));
    }
    std::filesystem::resize_file(path, 100);  // truncated
    {
        Site s;
        EXPECT_FALSE(VertexLightBaker::bakeCached(s.scene, s.targets(), params(), 7, dir));
        EXPECT_EQ(s.box->colors(), box);
    }
    std::filesystem::remove_all(dir);
}

// The edge of a bank: flat ground that bends down at 45 degrees along x = 0, as a grid with smooth normals. The
// mean centroid of the edge vertices' triangles lies under them, deeper than the offset; sampled from there the
// edge came out black (a row of dark teeth along the factory's stream). Its light is the open ground's.
TEST(VertexLightBaker, TheEdgeOfABankIsLitLikeTheGroundBesideIt) {
    std::vector<vec3> pos, nrm;
    std::vector<uint32_t> idx;
    const int n = 8;  // cells a side, 3 m each, from x = -12
    auto height = [](double x) { return x > 0.0 ? -x : 0.0; };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = -12.0 + 3.0 * i, y = -12.0 + 3.0 * j;
            pos.emplace_back(x, y, height(x));
            const double dz = height(x + 3.0) - height(x - 3.0);  // central differences, as the terrain's
            nrm.emplace_back(glm::normalize(dvec3(-dz, 0.0, 6.0)));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = b + uint32_t(n + 1), d = c - 1;
            idx.insert(idx.end(), {a, b, c, a, c, d});
        }
    auto bank = make<Mesh>();
    bank->set(std::move(pos), std::move(nrm), std::move(idx));
    auto root = make<Group>();
    root->addChild(make<Geometry>(bank, make<Material>()));
    Scene scene(root);
    scene.update();
    VertexLightParams p;
    p.sunDirection = dvec3(-1, 0, 2);  // from the flat side
    p.sunSamples = 8;
    p.aoSamples = 32;
    p.aoDistance = 3.0;
    p.offset = 0.05;
    const auto light = VertexLightBaker::compute(scene, {{bank, dmat4(1.0)}}, p);
    const size_t flat = size_t(4 * (n + 1) + 2), edge = size_t(4 * (n + 1) + 4);  // (-6, 0) and (0, 0)
    ASSERT_EQ(bank->positions()[edge], vec3(0.0f));
    EXPECT_EQ(light[0].sun[flat], 1.0f);
    EXPECT_EQ(light[0].sun[edge], 1.0f);
    EXPECT_GT(light[0].ao[edge], 0.9f);  // nothing stands over a convex edge
}
