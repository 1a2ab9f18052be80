#include "sg/core/Mesh.h"

#include "sg/core/internal/MeshClosed.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>

namespace sg {

static std::atomic<uint32_t> g_nextMeshId{1};

Mesh::Mesh() : id_(g_nextMeshId++) {}

// The checks and the storing every set*() shares; `what` names the caller in messages.
void Mesh::store(const char* what, Primitive primitive, std::vector<vec3> positions, std::vector<vec3> normals,
                 std::vector<uint32_t> indices, std::vector<vec2> uvs, std::vector<vec4> colors) {
    const size_t n = positions.size();
    auto sizeError = [&](const char* array, size_t got) {
        throw std::invalid_argument(std::string(what) + ": " + array + " has " + std::to_string(got) +
                                    " elements, positions has " + std::to_string(n));
    };
    if (!normals.empty() && normals.size() != n) sizeError("normals", normals.size());
    if (!uvs.empty() && uvs.size() != n) sizeError("uvs", uvs.size());
    if (!colors.empty() && colors.size() != n) sizeError("colors", colors.size());
    const size_t group = primitive == Primitive::Triangles ? 3 : 2;
    if (indices.size() % group != 0)
        throw std::invalid_argument(std::string(what) + ": index count " + std::to_string(indices.size()) +
                                    " is not a multiple of " + std::to_string(group));
    uint32_t maxIndex = 0;
    for (size_t i = 0; i < indices.size(); ++i) {
        if (indices[i] >= n)
            throw std::invalid_argument(std::string(what) + ": indices[" + std::to_string(i) +
                                        "] = " + std::to_string(indices[i]) + " is out of range (" + std::to_string(n) +
                                        " positions)");
        maxIndex = std::max(maxIndex, indices[i]);
    }
    box_ = Box{};
    valid_ = true;
    for (const vec3& p : positions) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) valid_ = false;
        box_.expand(dvec3(p));
    }
    primitive_ = primitive;
    positions_ = std::move(positions);
    normals_ = std::move(normals);
    uvs_ = std::move(uvs);
    colors_ = std::move(colors);
    tangents_.clear();
    uvs1_.clear();
    intensities_.clear();
    outline_.clear();
    joints_.clear();
    weights_.clear();
    targets_.clear();
    influences_ = 0;
    maxJoint_ = 0;
    {
        std::lock_guard<std::mutex> lock(jointBoxesMutex_);
        jointBoxes_.clear();
        jointBoxesDone_.store(false, std::memory_order_release);
    }
    features_ = nullptr;
    indices16_.clear();
    indices32_.clear();
    if (maxIndex < 65536) {
        indices16_.assign(indices.begin(), indices.end());
    } else {
        indices32_ = std::move(indices);
    }
    closed_.store(-1, std::memory_order_relaxed);
    ++version_;
}

void Mesh::set(std::vector<vec3> positions, std::vector<vec3> normals, std::vector<uint32_t> indices,
               std::vector<vec2> uvs, std::vector<vec4> colors) {
    store("Mesh::set()", Primitive::Triangles, std::move(positions), std::move(normals), std::move(indices),
          std::move(uvs), std::move(colors));
}

void Mesh::setPoints(std::vector<vec3> positions, std::vector<vec4> colors, std::vector<vec3> normals) {
    store("Mesh::setPoints()", Primitive::Points, std::move(positions), std::move(normals), {}, {}, std::move(colors));
}

void Mesh::setLines(std::vector<vec3> positions, std::vector<uint32_t> indices, std::vector<vec4> colors) {
    store("Mesh::setLines()", Primitive::Lines, std::move(positions), {}, std::move(indices), {}, std::move(colors));
}

void Mesh::setIntensities(std::vector<uint16_t> intensities) {
    if (!intensities.empty() && intensities.size() != positions_.size())
        throw std::invalid_argument("Mesh::setIntensities(): " + std::to_string(intensities.size()) +
                                    " intensities, positions has " + std::to_string(positions_.size()));
    intensities_ = std::move(intensities);
    ++version_;
}

void Mesh::setOutline(std::vector<uint32_t> edges) {
    if (!edges.empty() && primitive_ != Primitive::Triangles)
        throw std::invalid_argument("Mesh::setOutline(): the mesh is not triangles");
    if (edges.size() % 2 != 0)
        throw std::invalid_argument("Mesh::setOutline(): index count " + std::to_string(edges.size()) + " is odd");
    for (size_t i = 0; i < edges.size(); ++i)
        if (edges[i] >= positions_.size())
            throw std::invalid_argument("Mesh::setOutline(): edges[" + std::to_string(i) +
                                        "] = " + std::to_string(edges[i]) + " is out of range (" +
                                        std::to_string(positions_.size()) + " positions)");
    outline_ = std::move(edges);
    ++version_;
}

void Mesh::setSurface(std::vector<vec4> tangents, std::vector<vec2> uvs1) {
    const size_t n = positions_.size();
    if (!tangents.empty() && tangents.size() != n)
        throw std::invalid_argument("Mesh::setSurface(): tangents has " + std::to_string(tangents.size()) +
                                    " elements, positions has " + std::to_string(n));
    if (!uvs1.empty() && uvs1.size() != n)
        throw std::invalid_argument("Mesh::setSurface(): uvs1 has " + std::to_string(uvs1.size()) +
                                    " elements, positions has " + std::to_string(n));
    tangents_ = std::move(tangents);
    uvs1_ = std::move(uvs1);
    ++version_;
}

void Mesh::setFeatures(ref_ptr<const MeshFeatures> features) {
    const size_t n = positions_.size();
    auto fail = [](const std::string& what) { throw std::invalid_argument("Mesh::setFeatures(): " + what); };
    if (features) {
        for (size_t s = 0; s < features->sets.size(); ++s) {
            const FeatureIdSet& f = features->sets[s];
            const std::string set = "sets[" + std::to_string(s) + "]";
            if (f.source == FeatureIdSet::Source::Attribute && f.ids.size() != n)
                fail(set + " has " + std::to_string(f.ids.size()) + " ids, positions has " + std::to_string(n));
            if (f.source == FeatureIdSet::Source::Texture && (!f.texture || f.channels.empty()))
                fail(set + " reads a texture but has no texture or no channels");
        }
        for (size_t a = 0; a < features->propertyAttributes.size(); ++a)
            for (const auto& c : features->propertyAttributes[a].columns)
                if (c.stride == 0 || c.bytes.size() != size_t(c.stride) * n)
                    fail("propertyAttributes[" + std::to_string(a) + "] has " + std::to_string(c.bytes.size()) +
                         " bytes, not " + std::to_string(n) + " vertices of " + std::to_string(c.stride));
    }
    features_ = std::move(features);
}

// Two threads asking at once may both work it out: the same answer, stored twice.
bool Mesh::closed() const {
    if (primitive_ != Primitive::Triangles) return false;
    int8_t c = closed_.load(std::memory_order_acquire);
    if (c < 0) {
        c = boundsSolids(positions_, indices16_.empty() ? nullptr : indices16_.data(),
                         indices32_.empty() ? nullptr : indices32_.data(), indexCount())
                ? 1
                : 0;
        closed_.store(c, std::memory_order_release);
    }
    return c == 1;
}

ref_ptr<Mesh> makeBoxMesh(const dvec3& mn, const dvec3& mx, int div) {
    if (div < 1) div = 1;
    std::vector<vec3> pos, nrm;
    std::vector<vec2> uv;
    std::vector<uint32_t> idx;
    // Each face: origin corner, two edge vectors (u, v) with u x v pointing outward.
    const dvec3 d = mx - mn;
    struct Face {
        dvec3 o, u, v;
    };
    const Face faces[6] = {
        {{mn.x, mn.y, mn.z}, {0, d.y, 0}, {d.x, 0, 0}},  // -z
        {{mn.x, mn.y, mx.z}, {d.x, 0, 0}, {0, d.y, 0}},  // +z
        {{mn.x, mn.y, mn.z}, {d.x, 0, 0}, {0, 0, d.z}},  // -y
        {{mn.x, mx.y, mn.z}, {0, 0, d.z}, {d.x, 0, 0}},  // +y
        {{mn.x, mn.y, mn.z}, {0, 0, d.z}, {0, d.y, 0}},  // -x
        {{mx.x, mn.y, mn.z}, {0, d.y, 0}, {0, 0, d.z}},  // +x
    };
    for (const Face& f : faces) {
        const vec3 n = vec3(glm::normalize(glm::cross(f.u, f.v)));
        const uint32_t base = uint32_t(pos.size());
        for (int j = 0; j <= div; ++j)
            for (int i = 0; i <= div; ++i) {
                const double a = double(i) / div, b = double(j) / div;
                pos.push_back(vec3(f.o + f.u * a + f.v * b));
                nrm.push_back(n);
                uv.push_back(vec2(float(a), float(b)));
            }
        for (int j = 0; j < div; ++j)
            for (int i = 0; i < div; ++i) {
                const uint32_t a = base + uint32_t(j * (div + 1) + i), b = a + 1, c = a + uint32_t(div + 1), e = c + 1;
                idx.insert(idx.end(), {a, b, e, a, e, c});
            }
    }
    auto m = make<Mesh>();
    m->set(std::move(pos), std::move(nrm), std::move(idx), std::move(uv));
    return m;
}

}  // namespace sg
