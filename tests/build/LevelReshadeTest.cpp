// sg::LevelReshader through generateLevels: the coarse levels of a faceted model keep each face's normal and colour
// (the simplifier's kept vertices carry other faces' attributes), and the colour shares redo them from new colours.
#include "sg/build/LevelReshade.h"
#include "sg/build/LodGenerator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

using namespace sg;

namespace {

// A 10 m cube centred on the origin, each face a 10 x 10 grid of its own colour and vertices, studded with 25 small
// boxes of the face's colour: closed pieces the topology-keeping simplifier cannot reduce, so it clusters.
ref_ptr<Mesh> studdedCube(const vec4 colors[6]) {
    std::vector<vec3> pos, nrm;
    std::vector<vec4> col;
    std::vector<uint32_t> idx;
    auto quad = [&](const vec3 q[4], const vec3& n, const vec4& c) {
        const uint32_t b = uint32_t(pos.size());
        for (int k = 0; k < 4; ++k) pos.push_back(q[k]), nrm.push_back(n), col.push_back(c);
        const bool ccw = glm::dot(glm::cross(q[1] - q[0], q[2] - q[0]), n) > 0.0f;
        if (ccw)
            idx.insert(idx.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
        else
            idx.insert(idx.end(), {b, b + 2, b + 1, b, b + 3, b + 2});
    };
    auto box = [&](const vec3& mn, const vec3& mx, const vec4& c) {
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
                const int u = (axis + 1) % 3, w = (axis + 2) % 3;
                vec3 n(0.0f), q[4];
                n[axis] = side ? 1.0f : -1.0f;
                for (int k = 0; k < 4; ++k) {
                    q[k][axis] = side ? mx[axis] : mn[axis];
                    q[k][u] = (k == 1 || k == 2) ? mx[u] : mn[u];
                    q[k][w] = k >= 2 ? mx[w] : mn[w];
                }
                quad(q, n, c);
            }
    };
    // Face f: axis f / 2, side f % 2; (u, w) the other two axes, q(a, b) the point at face coordinates a, b.
    for (int f = 0; f < 6; ++f) {
        const int axis = f / 2, u = (axis + 1) % 3, w = (axis + 2) % 3;
        const float side = f % 2 ? 5.0f : -5.0f;
        vec3 n(0.0f);
        n[axis] = side > 0.0f ? 1.0f : -1.0f;
        auto at = [&](float a, float b, float lift) {
            vec3 p(0.0f);
            p[axis] = side + lift * n[axis];
            p[u] = a, p[w] = b;
            return p;
        };
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 10; ++i) {
                const float a = -5.0f + i, b = -5.0f + j;
                const vec3 q[4] = {at(a, b, 0), at(a + 1, b, 0), at(a + 1, b + 1, 0), at(a, b + 1, 0)};
                quad(q, n, colors[f]);
            }
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) {
                const float a = -4.0f + 2.0f * i, b = -4.0f + 2.0f * j;
                box(glm::min(at(a, b, 0.0f), at(a + 0.3f, b + 0.3f, 0.3f)),
                    glm::max(at(a, b, 0.0f), at(a + 0.3f, b + 0.3f, 0.3f)), colors[f]);
            }
    }
    auto m = make<Mesh>();
    m->set(std::move(pos), std::move(nrm), std::move(idx), {}, std::move(col));
    return m;
}

const vec4 kFaceColors[6] = {vec4(1, 0, 0, 1), vec4(0, 1, 0, 1), vec4(0, 0, 1, 1),
                             vec4(1, 1, 0, 1), vec4(0, 1, 1, 1), vec4(1, 0, 1, 1)};

// Corners of a level's triangles that lie on a cube face and do not carry that face's normal and colour.
int wrongCorners(const Mesh& m, int* checked = nullptr) {
    int wrong = 0;
    for (uint32_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t v[3] = {m.index(3 * t), m.index(3 * t + 1), m.index(3 * t + 2)};
        const vec3 p[3] = {m.positions()[v[0]], m.positions()[v[1]], m.positions()[v[2]]};
        const vec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
        if (!(glm::length(c) > 0.0f)) continue;
        const vec3 n = glm::normalize(c);
        for (int f = 0; f < 6; ++f) {
            const int axis = f / 2;
            const float side = f % 2 ? 5.0f : -5.0f;
            bool on = n[axis] * side > 4.995f;
            for (const vec3& q : p) on = on && std::abs(q[axis] - side) < 1e-4f;
            if (!on) continue;
            if (checked) *checked += 3;
            for (uint32_t k : v) {
                const vec4 d = glm::abs(m.colors()[k] - kFaceColors[f]);
                if (glm::dot(m.normals()[k], n) < 0.999f || std::max({d.r, d.g, d.b, d.a}) > 1e-4f) ++wrong;
            }
        }
    }
    return wrong;
}

}  // namespace

TEST(LevelReshade, CoarseLevelsOfABoxKeepEachFacesNormalAndColour) {
    const ref_ptr<Mesh> cube = studdedCube(kFaceColors);
    LevelShading reshaded;
    reshaded.reshade = true;
    const std::vector<LodLevel> plain = generateLevels(cube, {0.3f, 0.06f});
    const std::vector<LodLevel> levels =
        generateLevels(cube, {0.3f, 0.06f}, std::numeric_limits<float>::infinity(), reshaded);
    ASSERT_EQ(levels.size(), 3u);
    int plainWrong = 0, checked = 0;
    for (size_t l = 1; l < levels.size(); ++l) {
        ASSERT_NE(levels[l].mesh, cube);
        ASSERT_LT(levels[l].triangles, cube->triangleCount());
        EXPECT_EQ(levels[l].triangles, levels[l].mesh->triangleCount());
        EXPECT_EQ(levels[l].error, plain[l].error);  // the geometry is the simplifier's: the same error
        plainWrong += wrongCorners(*plain[l].mesh);
        EXPECT_EQ(wrongCorners(*levels[l].mesh, &checked), 0) << "level " << l;
    }
    EXPECT_GT(checked, 36);  // corners of triangles on the cube's faces were checked
    // Without reshading the simplifier's kept vertices put other faces' normals and colours on the cube's faces.
    EXPECT_GT(plainWrong, 0);
}

TEST(LevelReshade, ColourSharesRedoTheColoursFromNewDetailedColours) {
    const ref_ptr<Mesh> cube = studdedCube(kFaceColors);
    LevelShading reshaded;
    reshaded.reshade = true;
    const std::vector<LodLevel> levels =
        generateLevels(cube, {0.06f}, std::numeric_limits<float>::infinity(), reshaded);
    ASSERT_EQ(levels.size(), 2u);
    ASSERT_EQ(levels[0].colors.start.size(), cube->positions().size() + 1);  // level 0: each vertex its own
    // All the detailed colours grey: every coarse colour becomes that grey (weights sum to 1).
    const std::vector<vec4> grey(cube->positions().size(), vec4(0.25f, 0.25f, 0.25f, 1.0f));
    Mesh& m = *levels[1].mesh;
    applyColorShare(levels[1].colors, grey, m);
    for (const vec4& c : m.colors())
        for (int k = 0; k < 4; ++k) ASSERT_NEAR(c[k], grey[0][k], 1e-5f);
    // A share made for another mesh, or reading colours the detailed level lacks, names the function.
    try {
        applyColorShare(levels[1].colors, std::vector<vec4>(3), m, "caller()");
        ADD_FAILURE() << "no throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("caller(): the detailed level has 3 colours", 0), 0u) << e.what();
    }
    EXPECT_THROW(applyColorShare(levels[0].colors, grey, m), std::invalid_argument);
}
