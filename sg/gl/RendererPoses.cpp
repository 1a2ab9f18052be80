// Renderer: posed items (DrawList::poses): which mesh each draws, that mesh skinned on the CPU where its skin has more
// joints than the vertex stage's block holds, and the frame's joint matrices in one uniform buffer.
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/Shaders.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace sg {

namespace {

// The CPU-skinned meshes of poses not drawn for this many frames with posed items are let go (a pose is made new
// whenever its joints move, so an old one is not drawn again; a few frames spare views that draw it in turn).
constexpr uint64_t kCpuSkinGrace = 4;

vec3 normalizedOr(const vec3& v) {
    const float len = glm::length(v);
    return len > 0.0f ? v / len : v;
}

// A vertex's skin matrix: the weighted sum of its joints' (Pose::joints, less the anchor), as the vertex stage sums
// them. The joints were checked against the pose's (indexPoses).
glm::mat4x3 skinMatrix(const Mesh& m, const Pose& pose, size_t v) {
    const size_t k = size_t(m.influences());
    glm::mat4x3 s(0.0f);
    for (size_t i = v * k; i < v * k + k; ++i)
        if (m.weights()[i] > 0.0f) s += m.weights()[i] * pose.joints[m.joints()[i]];
    return s;
}

// The mesh as the vertex stage would skin it, relative to the pose's anchor: positions by the skin matrix, normals by
// its cofactor (the inverse transpose up to scale), tangents by its 3x3 part; every other array copied.
ref_ptr<Mesh> skinOnCpu(const Mesh& m, const Pose& pose) {
    const size_t n = m.positions().size();
    std::vector<vec3> positions(n), normals(m.normals().size());
    std::vector<vec4> tangents(m.tangents().size());
    for (size_t v = 0; v < n; ++v) {
        const glm::mat4x3 s = skinMatrix(m, pose, v);
        positions[v] = s * vec4(m.positions()[v], 1.0f);
        const glm::mat3 l(s);
        if (!normals.empty())
            normals[v] = normalizedOr(
                glm::mat3(glm::cross(l[1], l[2]), glm::cross(l[2], l[0]), glm::cross(l[0], l[1])) * m.normals()[v]);
        if (!tangents.empty()) tangents[v] = vec4(normalizedOr(l * vec3(m.tangents()[v])), m.tangents()[v].w);
    }
    std::vector<uint32_t> indices(m.indexCount());
    for (size_t i = 0; i < indices.size(); ++i) indices[i] = m.index(i);
    ref_ptr<Mesh> out(new Mesh);
    switch (m.primitive()) {
        case Primitive::Points: out->setPoints(std::move(positions), m.colors(), std::move(normals)); break;
        case Primitive::Lines: out->setLines(std::move(positions), std::move(indices), m.colors()); break;
        case Primitive::Triangles:
            out->set(std::move(positions), std::move(normals), std::move(indices), m.uvs(), m.colors());
            if (!tangents.empty() || !m.uvs1().empty()) out->setSurface(std::move(tangents), m.uvs1());
            if (!m.outline().empty()) out->setOutline(m.outline());
            break;
    }
    if (!m.intensities().empty()) out->setIntensities(m.intensities());
    out->setPointSpacing(m.pointSpacing());
    if (m.features()) out->setFeatures(m.features());
    out->setSource(m.source());
    return out;
}

}  // namespace

void Renderer::indexPoses(const DrawList& list) {
    poses_.clear();
    if (list.poses.empty() && cpuSkinned_.empty()) return;
    ++poseFrames_;
    for (auto it = cpuSkinned_.begin(); it != cpuSkinned_.end();)
        it = poseFrames_ - it->second.frame > kCpuSkinGrace ? cpuSkinned_.erase(it) : std::next(it);
    if (list.poses.empty()) return;
    poses_.assign(list.items.size(), nullptr);
    for (size_t k = 0; k < list.poses.size(); ++k) {
        const auto& [i, pose] = list.poses[k];
        if (i >= list.items.size())
            throw std::out_of_range("Renderer::draw(): poses[" + std::to_string(k) + "] names item " +
                                    std::to_string(i) + ", past the " + std::to_string(list.items.size()) + " items");
        if (!pose || !list.items[i].mesh) continue;
        const Mesh& drawn = pose->drawn(*list.items[i].mesh);
        // What the vertex stage (or skinOnCpu) reads: every weighted joint a matrix of the pose's.
        if (pose->skinned() && drawn.influences() > 0 && drawn.maxJoint() >= pose->joints.size())
            throw std::out_of_range("Renderer::draw(): poses[" + std::to_string(k) + "] (item " + std::to_string(i) +
                                    ") has " + std::to_string(pose->joints.size()) +
                                    " joints, its mesh weights joint " + std::to_string(drawn.maxJoint()));
        poses_[i] = pose;
    }
}

bool Renderer::gpuSkinned(const Pose* pose, const Mesh& drawn) {
    return pose && pose->skinned() && drawn.influences() > 0 && pose->joints.size() <= size_t(kMaxJoints);
}

// A skinned pose whose mesh has no skin weights has nothing to skin by: its mesh is drawn as it is.
const Mesh* Renderer::drawnMesh(const DrawItem& it, const Pose* pose) {
    if (!pose) return it.mesh;
    const Mesh& drawn = pose->drawn(*it.mesh);
    if (!pose->skinned() || drawn.influences() == 0 || pose->joints.size() <= size_t(kMaxJoints)) return &drawn;
    CpuSkinned& c = cpuSkinned_[pose];
    if (!c.mesh) {
        c.pose = pose;
        c.mesh = skinOnCpu(drawn, *pose);
    }
    c.frame = poseFrames_;
    return c.mesh.get();
}

// One upload before the first draw (on llvmpipe a draw after an upload stores its rasterizer state again): each pose's
// rows at an offset the GL's alignment allows, zeros between and after, since the block is bound whole from each
// offset and a joint index of weight 0 may read any of it.
void Renderer::uploadJoints() {
    joints_.clear();
    jointAt_.clear();
    size_t end = 0;
    for (Run& r : runs_) {
        if (!r.skin) continue;
        const auto [at, fresh] = jointAt_.emplace(r.skin, 0);
        if (fresh) {
            if (!jointBuffer_) {
                glGenBuffers(1, &jointBuffer_);
                GLint align = 0;
                glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &align);
                jointAlign_ = (std::max<size_t>(size_t(std::max(align, 0)), 16) + 15) / 16 * 16;
            }
            const size_t unit = jointAlign_ / sizeof(vec4);
            joints_.resize((joints_.size() + unit - 1) / unit * unit, vec4(0.0f));
            at->second = joints_.size() * sizeof(vec4);
            end = at->second + kJointBlockBytes;
            for (const glm::mat4x3& j : r.skin->joints) {
                const glm::mat3x4 rows = glm::transpose(j);
                joints_.insert(joints_.end(), {rows[0], rows[1], rows[2]});
            }
        }
        r.jointOffset = at->second;
    }
    if (jointAt_.empty()) return;
    joints_.resize(std::max(joints_.size(), end / sizeof(vec4)), vec4(0.0f));
    glBindBuffer(GL_UNIFORM_BUFFER, jointBuffer_);
    glBufferData(GL_UNIFORM_BUFFER, GLsizeiptr(joints_.size() * sizeof(vec4)), joints_.data(), GL_STREAM_DRAW);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
}

}  // namespace sg
