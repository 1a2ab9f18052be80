// The GPU copies of the meshes and textures a renderer draws: each uploaded on its first use and kept, with a
// reference (so that its pointer stays valid), until the frames stop using it.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "sg/core/Material.h"
#include "sg/core/Mesh.h"
#include "sg/core/Ref.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

namespace sg {

// A mesh in GL: a vertex array over one vertex buffer (an attribute block each) and an index buffer (none for points,
// which are drawn in order).
struct GpuMesh {
    ref_ptr<const Mesh> mesh;
    unsigned vao = 0, vbo = 0, ibo = 0;
    unsigned mode = 0;       // GL_TRIANGLES, GL_LINES or GL_POINTS
    unsigned indexType = 0;  // GL_UNSIGNED_SHORT or GL_UNSIGNED_INT; 0 for points
    int indexCount = 0;      // points: the vertex count
    // A triangle mesh's outline (Mesh::outline()): 32-bit line indices in the same index buffer, from this byte on.
    size_t outlineOffset = 0;
    int outlineCount = 0;
    bool normals = false, uvs = false, colors = false, tangents = false, uvs1 = false;
    bool featureIds = false;  // its first feature ID set's ids, per vertex (kFeatureIdLocation)
    int influences = 0;       // skin joints and weights a vertex (Mesh::influences(): 0, 4 or 8; kJointsLocation)
    uint64_t lastFrame = 0;
    uint64_t keepUntil = 0;  // uploaded ahead of its first draw (prepare): kept until this frame, used or not
};

// What a mesh's copy will hold, without uploading it: its mode, outline count, attribute flags and influences (no GL
// names). What the renderer picks a shader variant by, before the first draw too (Renderer::prepareVariants).
GpuMesh describeMesh(const Mesh& m);

// A texture as bound for a draw: its GL name and the GL sampler object its Texture::sampler asks for, bound to the
// same unit (a sampler object overrides the texture's own parameters).
struct TextureBinding {
    unsigned texture = 0, sampler = 0;
};

// Needs the current GL context of its renderer, alive until the cache is destroyed.
class GpuCache {
public:
    // instanceBuffer: the buffer the item attributes are read from (Shaders.h), recorded in every vertex array.
    // maxAnisotropy: the context's limit, 1 for none.
    GpuCache(unsigned instanceBuffer, float maxAnisotropy);
    ~GpuCache();
    GpuCache(const GpuCache&) = delete;
    GpuCache& operator=(const GpuCache&) = delete;

    // Starts a frame: what mesh() and texture() return from now on is what releaseUnused() keeps.
    void nextFrame() { ++frame_; }
    // Uploads on first use. A Mesh changed after its first upload keeps its old copy until released.
    const GpuMesh& mesh(const Mesh* m);
    // The texture's GL name and sampler object. A texture drawn with an alpha cutoff (cut) has its own copy, with
    // colour bled under its transparent texels (bleedIntoTransparent); one read as sRGB colour (a physical material's
    // base colour or emissive texture: linear values when sampled) has its own copy too.
    TextureBinding texture(const Texture* t, bool cut, bool srgb = false);
    // The GL sampler object of t's Sampler and anisotropy: one per distinct pair, made on first use and kept until
    // clear() (a handful at most: the textures of one look share one).
    unsigned sampler(const Texture& t);
    size_t samplerCount() const { return samplers_.size(); }

    // Uploads ahead of a draw (Renderer::prepare): as mesh() and texture(), but kept by releaseUnused() for the
    // next kPrepareGrace frames whether drawn or not, so that what was uploaded for a detail not attached or not
    // drawn yet is still there when it is; a cached copy gets the grace again. Return whether they uploaded.
    static constexpr uint64_t kPrepareGrace = 8;
    bool hasMesh(const Mesh* m) const { return meshes_.count(m) != 0; }
    bool hasTexture(const Texture* t, bool cut, bool srgb = false) const {
        return textures_[kind(cut, srgb)].count(t) != 0;
    }
    bool prepareMesh(const Mesh* m);
    bool prepareTexture(const Texture* t, bool cut, bool srgb = false);

    // A feature colour table (Renderer::setFeatureStyle) as an RGBA8 texture, feature i at texel (i % width,
    // i / width), uploaded again when `version` changes; `key` names the table (a store's serial and a table).
    unsigned featureColors(const std::pair<uint64_t, int>& key, uint64_t version, const std::vector<uint8_t>& rgba);
    size_t featureTableCount() const { return featureTables_.size(); }

    // Frees the copies the frame since the last nextFrame() did not use; clear() frees all of them.
    void releaseUnused();
    // Frees the copies whose mesh or texture only the cache still references (Renderer::releaseOrphans).
    void releaseOrphans();
    void clear();
    size_t meshCount() const { return meshes_.size(); }
    size_t textureCount() const {
        size_t n = 0;
        for (const auto& c : textures_) n += c.size();
        return n;
    }

private:
    struct GpuTexture {
        ref_ptr<const Texture> texture;
        unsigned id = 0;
        uint64_t lastFrame = 0;
        uint64_t keepUntil = 0;
    };
    static void destroy(GpuMesh& g);
    static void uploadIndices(const Mesh& m, GpuMesh& g);
    // A skinned mesh's joints and weights into the bound array buffer from byte `offset` on, and their attributes.
    static void uploadSkin(const Mesh& m, size_t offset);
    static int kind(bool cut, bool srgb) { return (cut ? 1 : 0) | (srgb ? 2 : 0); }

    unsigned instanceBuffer_;
    float maxAnisotropy_;
    uint64_t frame_ = 0;
    std::unordered_map<const Mesh*, GpuMesh> meshes_;
    std::unordered_map<const Texture*, GpuTexture> textures_[4];  // by kind(cut, srgb)
    struct FeatureTable {
        unsigned id = 0;
        uint64_t version = 0, lastFrame = 0;
    };
    std::map<std::pair<uint64_t, int>, FeatureTable> featureTables_;
    struct SamplerObject {
        Sampler sampler;
        float anisotropy = 1.0f;
        unsigned id = 0;
    };
    std::vector<SamplerObject> samplers_;  // looked up by value: few enough that a scan beats a hash
};

}  // namespace sg
