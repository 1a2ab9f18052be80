#include "sg/gl/OcclusionQueries.h"

#include "sg/gl/internal/GlProgram.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sg {

namespace {

// The box only reaches the depth test: no colour is written.
const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 aPos;
uniform mat4 uViewProj;
void main() { gl_Position = uViewProj * vec4(aPos, 1.0); }
)";
const char* kFragment = R"(#version 330 core
out vec4 fragColor;
void main() { fragColor = vec4(1.0); }
)";

// The 12 triangles of a box whose corners are numbered x + 2y + 4z (0: min, 1: max on each axis). Both windings
// are drawn (face culling is off), so that a box around the eye's side of the near plane still shows its far faces.
constexpr uint8_t kCube[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                               2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};

// The box grows by this share of its size on each side: the corners are rounded in float on another path than the
// vertices of the mesh inside it, and the silhouette of a box mesh's box must not end a hair inside the mesh's.
// (In depth a millimetre at hundreds of metres is below the depth buffer's step: the polygon offset in issue()
// covers that.)
constexpr double kGrow = 1e-3;

int64_t mm(double v) { return std::llround(v * 1000.0); }

// The rest of the list, renumbered: the cull's sort order, fades, parts and poses of the items kept. newIndex: list's
// item
// -> drawn's, ~0u where it was left out.
void renumberRest(const DrawList& list, const std::vector<uint32_t>& newIndex, DrawList& drawn) {
    for (uint32_t i : list.order)
        if (i < newIndex.size() && newIndex[i] != ~0u) drawn.order.push_back(newIndex[i]);
    for (const auto& [i, f] : list.fades)
        if (i < newIndex.size() && newIndex[i] != ~0u) drawn.fades.push_back({newIndex[i], f});
    if (!list.parts.empty()) {
        drawn.ranges = list.ranges;
        for (DrawList::Part p : list.parts)
            if (p.item < newIndex.size() && newIndex[p.item] != ~0u) {
                p.item = newIndex[p.item];
                drawn.parts.push_back(p);
            }
    }
    for (const auto& [i, pose] : list.poses)
        if (i < newIndex.size() && newIndex[i] != ~0u) drawn.poses.push_back({newIndex[i], pose});
}

}  // namespace

OcclusionQueries::OcclusionQueries() {
    program_ = buildGlProgram(kVertex, kFragment, "OcclusionQueries::OcclusionQueries()");
    uViewProj_ = glGetUniformLocation(program_, "uViewProj");
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vertices_);
    glGenBuffers(1, &indices_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vertices_);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(vec3), nullptr);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_);  // the vertex array keeps the binding
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

OcclusionQueries::~OcclusionQueries() {
    if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
    glDeleteBuffers(1, &indices_);
    glDeleteBuffers(1, &vertices_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteProgram(program_);
}

OcclusionQueries::Key OcclusionQueries::keyOf(const DrawItem& item, const dvec3& eye) {
    // The draw list carries no id of the geometry, and its matrices are eye-relative: the world place is the one
    // thing the same item keeps from view to view.
    const dvec3 at = dvec3(item.model[3]) + eye;
    uint64_t basis = 0xcbf29ce484222325ull;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            basis = (basis ^ uint64_t(std::llround(double(item.model[c][r]) * 1e5))) * 0x100000001b3ull;
    return {item.mesh, item.material, mm(at.x), mm(at.y), mm(at.z), basis};
}

size_t OcclusionQueries::KeyHash::operator()(const Key& k) const {
    uint64_t h = uint64_t(reinterpret_cast<uintptr_t>(k.mesh)) * 0x9E3779B97F4A7C15ull;
    h ^= uint64_t(reinterpret_cast<uintptr_t>(k.material)) * 0xC2B2AE3D27D4EB4Full;
    h ^= uint64_t(k.x) * 0x165667B19E3779F9ull ^ uint64_t(k.y) * 0x27D4EB2F165667C5ull ^
         uint64_t(k.z) * 0x94D049BB133111EBull;
    return size_t(h ^ k.basis ^ (h >> 29));
}

void OcclusionQueries::reset() {
    seen_.clear();
    pendingKeys_.clear();
}

void OcclusionQueries::draw(Renderer& renderer, const DrawList& list, const Camera& camera, const vec4& clearColor) {
    select(list, camera, drawn_);
    renderer.setAfterItems([this](const mat4& viewProj, bool reverse) { issue(viewProj, reverse); });
    try {
        renderer.draw(drawn_, camera, clearColor);
    } catch (...) {
        renderer.setAfterItems({});
        throw;
    }
    renderer.setAfterItems({});
}

void OcclusionQueries::select(const DrawList& list, const Camera& camera, DrawList& drawn) {
    // Last frame's results. The frame was finished or at least flushed since: GL_QUERY_RESULT waits only for
    // what is still drawing. Two items at one key share the verdict: seen if either was.
    seen_.clear();
    for (size_t q = 0; q < pendingKeys_.size(); ++q) {
        GLuint any = 0;
        glGetQueryObjectuiv(queries_[q], GL_QUERY_RESULT, &any);
        seen_[pendingKeys_[q]] |= any != 0;
    }
    pendingKeys_.clear();

    // A box the near plane cuts could lose the very faces that show it: boxes within reach of the near plane's
    // corners (the farthest point of it from the eye) are drawn unqueried, as OcclusionQueryNode does for the
    // eye inside the bound.
    double nearReach = 0.0;
    const auto frustum = camera.eyeCorners();
    for (int k = 0; k < 4; ++k) nearReach = std::max(nearReach, glm::length(frustum[size_t(k)]));
    nearReach *= 1.0 + 1e-6;

    stats_ = Stats{};
    keys_.clear();
    corners_.clear();
    drawn.clear();
    std::vector<uint32_t> newIndex(list.items.size(), ~0u);  // list's item -> drawn's, ~0u: left out
    std::vector<int64_t> partOf;
    if (!list.parts.empty()) {
        partOf.assign(list.items.size(), -1);
        for (size_t p = 0; p < list.parts.size(); ++p)
            if (list.parts[p].item < list.items.size()) partOf[list.parts[p].item] = int64_t(p);
    }
    // Posed items (DrawList::poses) are drawn unqueried: their mesh's box is not where the pose puts its vertices, and
    // their place moves with the pose.
    std::vector<bool> posed;
    if (!list.poses.empty()) {
        posed.assign(list.items.size(), false);
        for (const auto& [i, pose] : list.poses)
            if (i < posed.size() && pose) posed[i] = true;
    }
    for (size_t i = 0; i < list.items.size(); ++i) {
        const DrawItem& it = list.items[i];
        // The mesh's box in the eye-relative frame: centre moved, half extent through |M|.
        const Box& b = it.mesh->box();
        // No vertex: nothing to query (nor to draw, but that is the renderer's to see); posed: see above.
        if (b.empty() || (!posed.empty() && posed[i])) {
            newIndex[i] = uint32_t(drawn.items.size());
            drawn.items.push_back(it);
            continue;
        }
        const glm::dmat3 m(glm::dmat4(it.matrix()));
        const dvec3 c = m * b.center() + dvec3(it.model[3]);
        const glm::dmat3 a(glm::abs(m[0]), glm::abs(m[1]), glm::abs(m[2]));
        dvec3 e = a * b.halfExtent();
        e += kGrow * std::max({e.x, e.y, e.z}) + 1e-6;
        const dvec3 closest = glm::clamp(dvec3(0.0), c - e, c + e);
        const bool nearEye = glm::length(closest) <= nearReach;
        const Key key = keyOf(it, camera.eye());
        const auto found = seen_.find(key);
        if (!nearEye && found != seen_.end() && !found->second) {
            ++stats_.hidden;
            if (partOf.empty() || partOf[i] < 0) {
                stats_.hiddenTriangles += it.mesh->triangleCount();
            } else {
                const DrawList::Part& p = list.parts[size_t(partOf[i])];
                for (uint32_t r = 0; r < p.count && p.first + r < list.ranges.size(); ++r)
                    stats_.hiddenTriangles += list.ranges[p.first + r].count / 3;
            }
        } else {
            newIndex[i] = uint32_t(drawn.items.size());
            drawn.items.push_back(it);
        }
        if (nearEye) {
            ++stats_.nearEye;
            continue;
        }
        keys_.push_back(key);
        for (int k = 0; k < 8; ++k)
            corners_.push_back(vec3(c + e * dvec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1)));
    }
    stats_.queries = uint32_t(keys_.size());
    renumberRest(list, newIndex, drawn);
}

void OcclusionQueries::issue(const mat4& viewProj, bool reverseDepth) {
    const size_t n = keys_.size();
    if (n > queries_.size()) {
        const size_t old = queries_.size();
        queries_.resize(n);
        glGenQueries(GLsizei(n - old), queries_.data() + old);
    }
    if (n > 0) {
        glBindVertexArray(vao_);
        // Box k's indices point at its own 8 corners: one buffer of 36 per box, grown when the boxes outgrow it, so
        // that a query is one plain glDrawElements with no state change between them.
        if (n > indexCapacity_) {
            indexCapacity_ = std::max(n, indexCapacity_ * 2);
            std::vector<uint32_t> idx(indexCapacity_ * 36);
            for (size_t k = 0; k < indexCapacity_; ++k)
                for (int j = 0; j < 36; ++j) idx[k * 36 + size_t(j)] = uint32_t(k * 8 + kCube[j]);
            glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(idx.size() * 4), idx.data(), GL_STATIC_DRAW);
        }
        glBindBuffer(GL_ARRAY_BUFFER, vertices_);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(corners_.size() * sizeof(vec3)), corners_.data(), GL_STREAM_DRAW);
        glUseProgram(program_);
        glUniformMatrix4fv(uViewProj_, 1, GL_FALSE, &viewProj[0][0]);
        // Tested against the frame's depth, changing nothing. A box face on its mesh's own face (a box mesh) must
        // pass, though the two are triangulated differently and their depths round apart by a step of the depth
        // buffer: LEQUAL (GEQUAL with reversed depth) and the box pulled toward the eye by one step and its slope
        // (polygon offset; without it a static view of the city lost a few pixels a frame), besides kGrow.
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthMask(GL_FALSE);
        glDepthFunc(reverseDepth ? GL_GEQUAL : GL_LEQUAL);
        glDisable(GL_CULL_FACE);
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(reverseDepth ? 1.0f : -1.0f, reverseDepth ? 1.0f : -1.0f);
        // Any sample: the visibility threshold is 0 pixels, and the answer may come before the box is done.
        for (size_t k = 0; k < n; ++k) {
            glBeginQuery(GL_ANY_SAMPLES_PASSED, queries_[k]);
            glDrawElements(GL_TRIANGLES, 36, GL_UNSIGNED_INT, reinterpret_cast<const void*>(k * 36 * 4));
            glEndQuery(GL_ANY_SAMPLES_PASSED);
        }
        glDisable(GL_POLYGON_OFFSET_FILL);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthMask(GL_TRUE);
        glDepthFunc(reverseDepth ? GL_GREATER : GL_LESS);
        glUseProgram(0);
        glBindVertexArray(0);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
    }
    pendingKeys_.swap(keys_);
    keys_.clear();
}

}  // namespace sg
