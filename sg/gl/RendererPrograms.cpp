// Renderer: the frame's runs get their GPU copies and their programs (ShaderMode: the one program, or a variant
// per combination of features, compiled on first use unless prepared: RendererVariants.cpp).
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/GlProgram.h"
#include "sg/gl/internal/GpuCache.h"
#include "sg/gl/internal/Shaders.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <string>
#include <utility>

namespace sg {

namespace {
// The features of a physical material's textures but the base colour's, in Renderer::physicalSlots()' order.
constexpr uint32_t kPbrSlotFeatures[4] = {kShadePbrMr, kShadePbrNormal, kShadePbrOcclusion, kShadePbrEmissive};
}  // namespace

Renderer::Program Renderer::link(const char* vertexSource, const char* fragmentSource, const char* who,
                                 const char* geometrySource) {
    Program p;
    p.id = buildGlProgram(vertexSource, fragmentSource, who, geometrySource);
    const auto at = [&](const char* name) { return glGetUniformLocation(p.id, name); };
    p.uViewProj = at("uViewProj");
    p.uLightDir = at("uLightDir");
    p.uHeadlight = at("uHeadlight");
    p.uAmbient = at("uAmbient");
    p.uLightColor = at("uLightColor");
    p.uUseTexture = at("uUseTexture");
    p.uUseColor = at("uUseColor");
    p.uLit = at("uLit");
    p.uBakedLight = at("uBakedLight");
    p.uSpecular = at("uSpecular");
    p.uShininess = at("uShininess");
    p.uFade = at("uFade");
    p.uAlphaCutoff = at("uAlphaCutoff");
    p.uLightE = at("uLightE");
    p.uSky = at("uSky");
    p.uGround = at("uGround");
    p.uUp = at("uUp");
    p.uMetallic = at("uMetallic");
    p.uRoughness = at("uRoughness");
    p.uEmissive = at("uEmissive");
    p.uNormalScale = at("uNormalScale");
    p.uOcclusionStrength = at("uOcclusionStrength");
    p.uLightCount = at("uLightCount");
    p.uPunctualPos = at("uPunctualPos");
    p.uPunctualDir = at("uPunctualDir");
    p.uPunctualE = at("uPunctualE");
    p.uPunctualCone = at("uPunctualCone");
    p.uPointSize = at("uPointSize");
    p.uMaxPointSize = at("uMaxPointSize");
    p.uPointScale = at("uPointScale");
    p.uViewportSize = at("uViewportSize");
    p.uLineWidth = at("uLineWidth");
    const char* names[5] = {"uBase", "uMr", "uNormal", "uOcclusion", "uEmissive"};
    const char* samplers[5] = {"uTexture", "uMrTex", "uNormalTex", "uOcclusionTex", "uEmissiveTex"};
    glUseProgram(p.id);
    for (int u = 0; u < 5; ++u) {
        p.uXf[u] = at((std::string(names[u]) + "Xf").c_str());
        p.uSet[u] = at((std::string(names[u]) + "Set").c_str());
        glUniform1i(at(samplers[u]), u);  // units: Shaders.h
    }
    glUniform1i(at("uFeatureColors"), kFeatureUnit);
    const GLuint joints = glGetUniformBlockIndex(p.id, "Joints");  // a skinned variant's (kShadeSkin4, kShadeSkin8)
    if (joints != GL_INVALID_INDEX) glUniformBlockBinding(p.id, joints, kJointBinding);
    glUseProgram(0);
    return p;
}

uint32_t Renderer::variantKey(const Shading& s) const {
    if (shaderMode_ == ShaderMode::OneProgram && !s.point && !s.wideLine && !s.outline && s.skin == 0)
        return kOneProgram;
    uint32_t f = 0;
    if (s.texture) f |= kShadeTexture;
    if (s.colors) f |= kShadeColor;
    if (s.bakedLight) f |= kShadeBaked;
    if (s.lit) f |= kShadeLit;
    if (!light_.headlight) f |= kShadeSun;
    if (s.specular > 0.0f) f |= kShadeSpecular;
    if (s.alphaCutoff > 0.0f) f |= kShadeAlphaCut;
    if (s.fade < 1.0f) f |= kShadeFade;
    if (s.material && s.material->physical) f |= kShadePbr | s.pbr | (punctual_.empty() ? 0u : kShadePunctual);
    if (s.features) f |= kShadeFeature;
    if (s.point) f |= kShadePoint;
    if (s.round) f |= kShadeRound;
    if (s.wideLine) f |= kShadeWideLine;
    if (s.outline) f |= kShadeOutline;
    if (s.skin == 4) f |= kShadeSkin4;
    if (s.skin == 8) f |= kShadeSkin8;
    return canonicalFeatures(f);
}

Renderer::Program& Renderer::programFor(const Shading& s, bool blend) {
    const uint32_t key = variantKey(s);
    if (key == kOneProgram) return one_;
    const auto it = variants_.find(key);
    if (it != variants_.end()) return it->second;
    // A first use: compiled here, in the frame, unless prepareVariants() drew it ahead (warming_).
    ++stats_.programsCompiled;
    if (!warming_) ++compiledInDraw_;
    warmed_.insert(warmKey(key, blend));
    const std::string vs = variantSource(true, key), fs = variantSource(false, key), gs = variantGeometrySource(key);
    return variants_.emplace(key, link(vs.c_str(), fs.c_str(), "Renderer::draw()", gs.empty() ? nullptr : gs.c_str()))
        .first->second;
}

// Whatever the textures' GL names: a texture is drawn where the material has one the mesh can read, and the cache
// gives every texture a name.
Renderer::Shading Renderer::runShading(const GpuMesh& g, const Mesh& mesh, const Material* mat, float fade,
                                       bool skinned) const {
    Shading s;
    s.colors = g.colors;
    s.lit = (!mat || !mat->unlit) && g.normals;
    s.bakedLight = mat && mat->bakedLight;
    s.specular = mat ? mat->specular : 0.0f;
    s.shininess = mat ? mat->shininess : 1.0f;
    s.fade = fade;
    s.alphaCutoff = mat ? mat->alphaCutoff : 0.0f;
    s.point = g.mode == GL_POINTS;
    if (mat && mat->physical) {
        s.material = mat;
        // Points are lit by their normals alone, lines never (they have none): neither has a face to take one from.
        s.lit = !mat->unlit && (g.mode == GL_TRIANGLES || g.normals);
        if (s.lit && !g.normals) s.pbr |= kShadeFlat;
        if (mat->blend) s.pbr |= kShadeBlend;
        physicalSlots(*mat, g, s);
    } else {
        s.texture = mat && mat->texture && g.uvs;
    }
    s.skin = skinned ? g.influences : 0;
    s.features = styled(g, mesh);
    // Lines wider than glLineWidth draws are quads from a geometry stage.
    s.round = s.point && pointShading_.round;
    s.wideLine = g.mode == GL_LINES && wideLines();
    return s;
}

Renderer::Shading Renderer::outlineShading(const Shading& s) const {
    Shading o = s;
    o.outline = true;
    o.wideLine = wideLines();  // outlines are lines too
    return o;
}

bool Renderer::styled(const GpuMesh& g, const Mesh& mesh) const {
    const MeshFeatures* f = g.featureIds ? mesh.features() : nullptr;
    return featureStyle_ && shaderMode_ != ShaderMode::OneProgram && f && f->store && f->sets[0].propertyTable >= 0;
}

// Each texture of a physical material that the mesh can read (its UV set present; a normal map also needs normals
// and tangents), and the features and UV sets that it brings. Unlit: the base colour's alone.
unsigned Renderer::physicalSlots(const Material& m, const GpuMesh& g, Shading& s) {
    auto readable = [&](const TextureSlot& t) {
        return t.texture && ((t.texCoord == 0 && g.uvs) || (t.texCoord == 1 && g.uvs1));
    };
    auto set = [&](const TextureSlot& t) { s.pbr |= t.texCoord == 1 ? kShadeUv1 : kShadeUv0; };
    unsigned slots = 0;
    const TextureSlot base{m.texture, m.texCoord, m.textureTransform};
    if (readable(base)) {
        slots |= 1u;
        s.texture = true;
        set(base);
    }
    if (!s.lit) return slots;
    const PhysicalMaterial& p = m.pbr;
    const TextureSlot* pbr[4] = {&p.metallicRoughness, &p.normal, &p.occlusion, &p.emissive};
    for (int k = 0; k < 4; ++k) {
        const TextureSlot& t = *pbr[k];
        if (!readable(t) || (kPbrSlotFeatures[k] == kShadePbrNormal && (!g.tangents || !g.normals))) continue;
        slots |= 2u << k;
        s.pbr |= kPbrSlotFeatures[k];
        set(t);
    }
    const TextureSlot &mr = p.metallicRoughness, &ao = p.occlusion;
    if ((s.pbr & kShadePbrMr) && (s.pbr & kShadePbrOcclusion) && mr.texture == ao.texture &&
        mr.texCoord == ao.texCoord && mr.transform == ao.transform)
        s.pbr |= kShadePbrOrm;
    return slots;
}

// The physical material's textures that the shading reads, bound (colour ones as sRGB).
void Renderer::physicalTextures(Run& r) {
    const Material& m = *r.material;
    Shading probe = r.shading;
    probe.pbr = 0;
    const unsigned slots = physicalSlots(m, *r.gpu, probe);
    const bool cut = m.alphaCutoff > 0.0f;
    r.texture = 0;
    if (slots & 1u) {
        const TextureBinding b = cache_->texture(m.texture.get(), cut, true);
        r.texture = b.texture;
        r.sampler = b.sampler;
    }
    const PhysicalMaterial& p = m.pbr;
    const TextureSlot* pbr[4] = {&p.metallicRoughness, &p.normal, &p.occlusion, &p.emissive};
    for (int k = 0; k < 4; ++k) {
        if (!(slots & (2u << k))) continue;
        const TextureBinding b =
            cache_->texture(pbr[k]->texture.get(), false, kPbrSlotFeatures[k] == kShadePbrEmissive);
        r.pbrTextures[k] = b.texture;
        r.pbrSamplers[k] = b.sampler;
    }
}

void Renderer::featureColors(Run& r) {
    r.featureColors = 0;
    if (!r.shading.features) return;
    const MeshFeatures* f = r.mesh->features();
    const int table = f->sets[0].propertyTable;
    const std::shared_ptr<const FeatureStyle::Colors> c = featureStyle_->colors(*f->store, table);
    r.featureColors = cache_->featureColors({f->store->serial(), table}, c->version, c->rgba);
}

// Every mesh, texture and joint matrix of the frame is uploaded before the first draw: on llvmpipe an upload between
// draws makes every draw after it store the whole rasterizer state again (docs/benchmarks.md).
void Renderer::upload() {
    for (Run& r : runs_) {
        r.gpu = &cache_->mesh(r.mesh);
        if (r.gpu->influences == 0) r.skin = nullptr;  // its copy has no skin weights to skin by
        r.shading = runShading(*r.gpu, *r.mesh, r.material, r.fade, r.skin != nullptr);
        if (r.material && r.material->physical) {
            physicalTextures(r);
        } else if (r.shading.texture) {
            const TextureBinding b = cache_->texture(r.material->texture.get(), r.material->alphaCutoff > 0.0f);
            r.texture = b.texture;
            r.sampler = b.sampler;
        } else {
            r.texture = r.sampler = 0;
        }
        featureColors(r);
        r.program = &programFor(r.shading, r.blend);
        r.outline = r.gpu->outlineCount > 0 ? &programFor(outlineShading(r.shading), r.blend) : nullptr;
    }
    uploadJoints();
}

}  // namespace sg
