#include "sg/gl/internal/GpuCache.h"

#include "sg/gl/internal/Shaders.h"
#include "sg/io/ImageOps.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <utility>

namespace sg {

GpuMesh describeMesh(const Mesh& m) {
    GpuMesh g;
    const size_t n = m.positions().size();
    const Primitive p = m.primitive();
    g.mode = p == Primitive::Points ? GL_POINTS : p == Primitive::Lines ? GL_LINES : GL_TRIANGLES;
    g.outlineCount = p == Primitive::Points ? 0 : int(m.outline().size());
    g.normals = m.normals().size() == n;
    g.uvs = m.uvs().size() == n;
    g.colors = m.colors().size() == n;
    g.tangents = m.tangents().size() == n && n > 0;
    g.uvs1 = m.uvs1().size() == n && n > 0;
    const MeshFeatures* f = m.features();
    g.featureIds =
        f && !f->sets.empty() &&
        (f->sets[0].source == FeatureIdSet::Source::Attribute || f->sets[0].source == FeatureIdSet::Source::Implicit);
    g.influences =
        m.joints().size() == n * size_t(m.influences()) && m.weights().size() == m.joints().size() ? m.influences() : 0;
    return g;
}

GpuCache::GpuCache(unsigned instanceBuffer, float maxAnisotropy)
    : instanceBuffer_(instanceBuffer), maxAnisotropy_(maxAnisotropy) {}

GpuCache::~GpuCache() { clear(); }

void GpuCache::destroy(GpuMesh& g) {
    glDeleteVertexArrays(1, &g.vao);
    glDeleteBuffers(1, &g.vbo);
    glDeleteBuffers(1, &g.ibo);
}

const GpuMesh& GpuCache::mesh(const Mesh* m) {
    auto it = meshes_.find(m);
    if (it != meshes_.end()) {
        it->second.lastFrame = frame_;
        return it->second;
    }
    GpuMesh g = describeMesh(*m);
    g.mesh = m;
    g.lastFrame = frame_;
    const size_t n = m->positions().size();
    // One buffer, one block per attribute: the arrays are uploaded as the Mesh keeps them.
    const size_t posBytes = n * sizeof(vec3), nrmBytes = g.normals ? n * sizeof(vec3) : 0,
                 uvBytes = g.uvs ? n * sizeof(vec2) : 0, colBytes = g.colors ? n * sizeof(vec4) : 0,
                 tanBytes = g.tangents ? n * sizeof(vec4) : 0, uv1Bytes = g.uvs1 ? n * sizeof(vec2) : 0;
    const size_t fidBytes = g.featureIds ? n * sizeof(float) : 0;
    const size_t skinBytes = n * size_t(g.influences) * (sizeof(float) + sizeof(uint16_t));
    const size_t nrmOff = posBytes, uvOff = nrmOff + nrmBytes, colOff = uvOff + uvBytes, tanOff = colOff + colBytes,
                 uv1Off = tanOff + tanBytes, fidOff = uv1Off + uv1Bytes, skinOff = fidOff + fidBytes;
    glGenVertexArrays(1, &g.vao);
    glBindVertexArray(g.vao);
    glGenBuffers(1, &g.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(skinOff + skinBytes), nullptr, GL_STATIC_DRAW);
    glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(posBytes), m->positions().data());
    glEnableVertexAttribArray(kPositionLocation);
    glVertexAttribPointer(kPositionLocation, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    if (g.normals) {
        glBufferSubData(GL_ARRAY_BUFFER, GLintptr(nrmOff), GLsizeiptr(nrmBytes), m->normals().data());
        glEnableVertexAttribArray(kNormalLocation);
        glVertexAttribPointer(kNormalLocation, 3, GL_FLOAT, GL_FALSE, 0, reinterpret_cast<const void*>(nrmOff));
    }
    if (g.uvs) {
        glBufferSubData(GL_ARRAY_BUFFER, GLintptr(uvOff), GLsizeiptr(uvBytes), m->uvs().data());
        glEnableVertexAttribArray(kUvLocation);
        glVertexAttribPointer(kUvLocation, 2, GL_FLOAT, GL_FALSE, 0, reinterpret_cast<const void*>(uvOff));
    }
    if (g.colors) {
        glBufferSubData(GL_ARRAY_BUFFER, GLintptr(colOff), GLsizeiptr(colBytes), m->colors().data());
        glEnableVertexAttribArray(kColorLocation);
        glVertexAttribPointer(kColorLocation, 4, GL_FLOAT, GL_FALSE, 0, reinterpret_cast<const void*>(colOff));
    }
    if (g.tangents) {
        glBufferSubData(GL_ARRAY_BUFFER, GLintptr(tanOff), GLsizeiptr(tanBytes), m->tangents().data());
        glEnableVertexAttribArray(kTangentLocation);
        glVertexAttribPointer(kTangentLocation, 4, GL_FLOAT, GL_FALSE, 0, reinterpret_cast<const void*>(tanOff));
    }
    if (g.uvs1) {
        glBufferSubData(GL_ARRAY_BUFFER, GLintptr(uv1Off), GLsizeiptr(uv1Bytes), m->uvs1().data());
        glEnableVertexAttribArray(kUv1Location);
        glVertexAttribPointer(kUv1Location, 2, GL_FLOAT, GL_FALSE, 0, reinterpret_cast<const void*>(uv1Off));
    }
    if (g.featureIds) {
        std::vector<float> ids(n);
        const MeshFeatures* f = m->features();
        for (size_t i = 0; i < n; ++i) ids[i] = float(f->idAt(0, i));  // -1 for the null feature
        glBufferSubData(GL_ARRAY_BUFFER, GLintptr(fidOff), GLsizeiptr(fidBytes), ids.data());
        glEnableVertexAttribArray(kFeatureIdLocation);
        glVertexAttribPointer(kFeatureIdLocation, 1, GL_FLOAT, GL_FALSE, 0, reinterpret_cast<const void*>(fidOff));
    }
    if (g.influences > 0) uploadSkin(*m, skinOff);
    uploadIndices(*m, g);
    // The item attributes: the renderer points them at each run's place in the instance buffer.
    glBindBuffer(GL_ARRAY_BUFFER, instanceBuffer_);
    enableItemAttributes();
    pointItemAttributes(0);
    glBindVertexArray(0);
    return meshes_.emplace(m, std::move(g)).first->second;
}

// The weights (floats) then the joint indices (16-bit, read as unsigned integers: glVertexAttribIPointer), each
// vertex's first four then, with eight influences, its next four.
void GpuCache::uploadSkin(const Mesh& m, size_t offset) {
    const size_t k = size_t(m.influences()), n = m.positions().size();
    const size_t weightBytes = n * k * sizeof(float), jointOff = offset + weightBytes;
    glBufferSubData(GL_ARRAY_BUFFER, GLintptr(offset), GLsizeiptr(weightBytes), m.weights().data());
    glBufferSubData(GL_ARRAY_BUFFER, GLintptr(jointOff), GLsizeiptr(n * k * sizeof(uint16_t)), m.joints().data());
    const auto weightStride = GLsizei(k * sizeof(float)), jointStride = GLsizei(k * sizeof(uint16_t));
    for (size_t half = 0; half < k / 4; ++half) {
        const GLuint weights = half ? kWeights1Location : kWeightsLocation;
        const GLuint joints = half ? kJoints1Location : kJointsLocation;
        glEnableVertexAttribArray(weights);
        glVertexAttribPointer(weights, 4, GL_FLOAT, GL_FALSE, weightStride,
                              reinterpret_cast<const void*>(offset + half * 4 * sizeof(float)));
        glEnableVertexAttribArray(joints);
        glVertexAttribIPointer(joints, 4, GL_UNSIGNED_SHORT, jointStride,
                               reinterpret_cast<const void*>(jointOff + half * 4 * sizeof(uint16_t)));
    }
}

// Points have no indices (drawn in order: the intensities stay on the CPU, for picking and styling). An outline's
// edges follow the faces' indices in the same buffer, as 32-bit indices at a 4-byte boundary: the draw call names
// each range's type and offset.
void GpuCache::uploadIndices(const Mesh& m, GpuMesh& g) {
    const Primitive p = m.primitive();  // g.mode and g.outlineCount: describeMesh()
    if (p == Primitive::Points) {
        g.indexCount = GLsizei(m.positions().size());
        return;
    }
    const bool small = !m.indices16().empty();
    g.indexType = small ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    g.indexCount = GLsizei(m.indexCount());
    const size_t faceBytes = small ? m.indices16().size() * 2 : m.indices32().size() * 4;
    const std::vector<uint32_t>& outline = m.outline();  // a triangle mesh's only (Mesh::setOutline)
    g.outlineOffset = (faceBytes + 3) / 4 * 4;
    glGenBuffers(1, &g.ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);  // recorded in the VAO
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(g.outlineOffset + outline.size() * 4), nullptr, GL_STATIC_DRAW);
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, GLsizeiptr(faceBytes),
                    small ? static_cast<const void*>(m.indices16().data()) : m.indices32().data());
    if (!outline.empty())
        glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, GLintptr(g.outlineOffset), GLsizeiptr(outline.size() * 4),
                        outline.data());
}

TextureBinding GpuCache::texture(const Texture* t, bool cut, bool srgb) {
    auto& cache = textures_[kind(cut, srgb)];
    auto it = cache.find(t);
    if (it != cache.end()) {
        it->second.lastFrame = frame_;
        return {it->second.id, sampler(*t)};
    }
    GpuTexture g;
    g.texture = t;
    g.lastFrame = frame_;
    glGenTextures(1, &g.id);
    glBindTexture(GL_TEXTURE_2D, g.id);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // The first row of the RGBA array is v = 0.
    Image bled;
    if (cut) {
        bled = Image{t->width(), t->height(), t->rgba()};
        bleedIntoTransparent(bled);
    }
    glTexImage2D(GL_TEXTURE_2D, 0, srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, t->width(), t->height(), 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, cut ? bled.rgba.data() : t->rgba().data());
    // Mipmaps for every texture, whatever its min filter (one upload path). The texture's own parameters (the
    // default Sampler's) hold only where no sampler object is bound.
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    const unsigned id = cache.emplace(t, std::move(g)).first->second.id;
    return {id, sampler(*t)};
}

namespace {

GLint glWrap(Sampler::Wrap w) {
    switch (w) {
        case Sampler::Wrap::MirroredRepeat: return GL_MIRRORED_REPEAT;
        case Sampler::Wrap::ClampToEdge: return GL_CLAMP_TO_EDGE;
        default: return GL_REPEAT;
    }
}

GLint glMinFilter(Sampler::Filter f) {
    switch (f) {
        case Sampler::Filter::Nearest: return GL_NEAREST;
        case Sampler::Filter::Linear: return GL_LINEAR;
        case Sampler::Filter::NearestMipmapNearest: return GL_NEAREST_MIPMAP_NEAREST;
        case Sampler::Filter::LinearMipmapNearest: return GL_LINEAR_MIPMAP_NEAREST;
        case Sampler::Filter::NearestMipmapLinear: return GL_NEAREST_MIPMAP_LINEAR;
        default: return GL_LINEAR_MIPMAP_LINEAR;
    }
}

// Magnification has no mipmaps: a mipmap filter given for it reads as its filter within a level.
GLint glMagFilter(Sampler::Filter f) {
    const bool nearest = f == Sampler::Filter::Nearest || f == Sampler::Filter::NearestMipmapNearest ||
                         f == Sampler::Filter::NearestMipmapLinear;
    return nearest ? GL_NEAREST : GL_LINEAR;
}

}  // namespace

unsigned GpuCache::sampler(const Texture& t) {
    // Anisotropic filtering samples the mipmaps along a footprint: only min filters that read mipmaps take it.
    const Sampler& s = t.sampler;
    const bool mipmapped = s.minFilter != Sampler::Filter::Nearest && s.minFilter != Sampler::Filter::Linear;
    const float anisotropy =
        mipmapped && maxAnisotropy_ > 1.0f && t.maxAnisotropy > 1.0f ? std::min(t.maxAnisotropy, maxAnisotropy_) : 1.0f;
    for (const SamplerObject& o : samplers_)
        if (o.sampler == s && o.anisotropy == anisotropy) return o.id;
    SamplerObject o{s, anisotropy, 0};
    glGenSamplers(1, &o.id);
    glSamplerParameteri(o.id, GL_TEXTURE_WRAP_S, glWrap(s.wrapS));
    glSamplerParameteri(o.id, GL_TEXTURE_WRAP_T, glWrap(s.wrapT));
    glSamplerParameteri(o.id, GL_TEXTURE_MIN_FILTER, glMinFilter(s.minFilter));
    glSamplerParameteri(o.id, GL_TEXTURE_MAG_FILTER, glMagFilter(s.magFilter));
    if (anisotropy > 1.0f) glSamplerParameterf(o.id, GL_TEXTURE_MAX_ANISOTROPY_EXT, anisotropy);
    samplers_.push_back(o);
    return o.id;
}

bool GpuCache::prepareMesh(const Mesh* m) {
    auto it = meshes_.find(m);
    const bool upload = it == meshes_.end();
    GpuMesh& g = upload ? const_cast<GpuMesh&>(mesh(m)) : it->second;
    g.keepUntil = frame_ + kPrepareGrace;
    return upload;
}

bool GpuCache::prepareTexture(const Texture* t, bool cut, bool srgb) {
    auto& cache = textures_[kind(cut, srgb)];
    auto it = cache.find(t);
    const bool upload = it == cache.end();
    if (upload) {
        texture(t, cut, srgb);
        it = cache.find(t);
    }
    it->second.keepUntil = frame_ + kPrepareGrace;
    return upload;
}

namespace {

// Erases the entries `drop` picks from `map`, `free` releasing each one's GL objects first.
template <class Map, class Drop, class Free>
void eraseWhere(Map& map, Drop drop, Free free) {
    for (auto it = map.begin(); it != map.end();) {
        if (!drop(it->second)) {
            ++it;
            continue;
        }
        free(it->second);
        it = map.erase(it);
    }
}

template <class T>
void deleteTexture(T& t) {
    glDeleteTextures(1, &t.id);
}

}  // namespace

void GpuCache::releaseUnused() {
    const auto unused = [this](const auto& e) { return e.lastFrame != frame_ && e.keepUntil <= frame_; };
    eraseWhere(meshes_, unused, destroy);
    for (auto& cache : textures_) eraseWhere(cache, unused, deleteTexture<GpuTexture>);
    eraseWhere(
        featureTables_, [this](const FeatureTable& t) { return t.lastFrame != frame_; }, deleteTexture<FeatureTable>);
}

void GpuCache::releaseOrphans() {
    eraseWhere(
        meshes_, [](const GpuMesh& g) { return g.mesh->refCount() <= 1; }, destroy);
    for (auto& cache : textures_)
        eraseWhere(
            cache, [](const GpuTexture& t) { return t.texture->refCount() <= 1; }, deleteTexture<GpuTexture>);
}

unsigned GpuCache::featureColors(const std::pair<uint64_t, int>& key, uint64_t version,
                                 const std::vector<uint8_t>& rgba) {
    FeatureTable& t = featureTables_[key];
    t.lastFrame = frame_;
    if (t.id && t.version == version) return t.id;
    // Rows of at most 4096 texels: GL 3.3 guarantees textures of 4096 x 4096 (16 million features).
    const size_t n = std::max<size_t>(1, rgba.size() / 4);
    const int w = int(std::min<size_t>(n, 4096)), h = int((n + 4095) / 4096);
    std::vector<uint8_t> px(size_t(w) * size_t(h) * 4, 255);
    std::copy(rgba.begin(), rgba.end(), px.begin());
    if (!t.id) glGenTextures(1, &t.id);
    glBindTexture(GL_TEXTURE_2D, t.id);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    t.version = version;
    return t.id;
}

void GpuCache::clear() {
    for (auto& [k, t] : featureTables_) glDeleteTextures(1, &t.id);
    featureTables_.clear();
    for (auto& [m, g] : meshes_) destroy(g);
    meshes_.clear();
    for (auto& cache : textures_) {
        for (auto& [t, g] : cache) glDeleteTextures(1, &g.id);
        cache.clear();
    }
    for (SamplerObject& o : samplers_) glDeleteSamplers(1, &o.id);
    samplers_.clear();
}

}  // namespace sg
