// Renderer: the frame's runs get their GPU copies and their programs (ShaderMode: the one program, or a variant
// per combination of features, compiled on first use).
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/GlProgram.h"
#include "sg/gl/internal/GpuCache.h"
#include "sg/gl/internal/Shaders.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <string>
#include <utility>

namespace sg {

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

Renderer::Program& Renderer::programFor(const Shading& s) {
    if (shaderMode_ == ShaderMode::OneProgram && !s.point && !s.wideLine && !s.outline && s.skin == 0) return one_;
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
    f = canonicalFeatures(f);
    const auto it = variants_.find(f);
    if (it != variants_.end()) return it->second;
    const std::string vs = variantSource(true, f), fs = variantSource(false, f), gs = variantGeometrySource(f);
    return variants_.emplace(f, link(vs.c_str(), fs.c_str(), "Renderer::draw()", gs.empty() ? nullptr : gs.c_str()))
        .first->second;
}

Renderer::Shading Renderer::shading(const GpuMesh& g, const Material* mat, float fade, unsigned texture) {
    Shading s;
    s.texture = texture != 0;
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
    }
    return s;
}

// Each texture of a physical material that the mesh can read (its UV set present; a normal map also needs normals
// and tangents): its copy (colour ones as sRGB) and the features and UV sets that it brings.
void Renderer::physicalTextures(Run& r) {
    const Material& m = *r.material;
    const GpuMesh& g = *r.gpu;
    const bool cut = m.alphaCutoff > 0.0f;
    auto readable = [&](const TextureSlot& t) {
        return t.texture && ((t.texCoord == 0 && g.uvs) || (t.texCoord == 1 && g.uvs1));
    };
    auto set = [&](const TextureSlot& t) { r.shading.pbr |= t.texCoord == 1 ? kShadeUv1 : kShadeUv0; };
    r.texture = 0;
    r.shading.texture = false;
    const TextureSlot base{m.texture, m.texCoord, m.textureTransform};
    if (readable(base)) {
        const TextureBinding b = cache_->texture(base.texture.get(), cut, true);
        r.texture = b.texture;
        r.sampler = b.sampler;
        r.shading.texture = true;
        set(base);
    }
    if (!r.shading.lit) return;  // unlit: the base colour alone
    const PhysicalMaterial& p = m.pbr;
    const std::pair<const TextureSlot*, uint32_t> slots[4] = {{&p.metallicRoughness, kShadePbrMr},
                                                              {&p.normal, kShadePbrNormal},
                                                              {&p.occlusion, kShadePbrOcclusion},
                                                              {&p.emissive, kShadePbrEmissive}};
    for (int k = 0; k < 4; ++k) {
        const TextureSlot& t = *slots[k].first;
        if (!readable(t) || (slots[k].second == kShadePbrNormal && (!g.tangents || !g.normals))) continue;
        const TextureBinding b = cache_->texture(t.texture.get(), false, slots[k].second == kShadePbrEmissive);
        r.pbrTextures[k] = b.texture;
        r.pbrSamplers[k] = b.sampler;
        r.shading.pbr |= slots[k].second;
        set(t);
    }
    const TextureSlot &mr = p.metallicRoughness, &ao = p.occlusion;
    if ((r.shading.pbr & kShadePbrMr) && (r.shading.pbr & kShadePbrOcclusion) && mr.texture == ao.texture &&
        mr.texCoord == ao.texCoord && mr.transform == ao.transform)
        r.shading.pbr |= kShadePbrOrm;
}

void Renderer::featureColors(Run& r) {
    r.featureColors = 0;
    const MeshFeatures* f = r.gpu->featureIds ? r.mesh->features() : nullptr;
    if (!featureStyle_ || shaderMode_ == ShaderMode::OneProgram || !f || !f->store || f->sets[0].propertyTable < 0)
        return;
    const int table = f->sets[0].propertyTable;
    const std::shared_ptr<const FeatureStyle::Colors> c = featureStyle_->colors(*f->store, table);
    r.featureColors = cache_->featureColors({f->store->serial(), table}, c->version, c->rgba);
    r.shading.features = true;
}

// Every mesh, texture and joint matrix of the frame is uploaded before the first draw: on llvmpipe an upload between
// draws makes every draw after it store the whole rasterizer state again (docs/benchmarks.md).
void Renderer::upload() {
    for (Run& r : runs_) {
        r.gpu = &cache_->mesh(r.mesh);
        const Texture* tex = r.material && !r.material->physical && r.gpu->uvs ? r.material->texture.get() : nullptr;
        const TextureBinding b = tex ? cache_->texture(tex, r.material->alphaCutoff > 0.0f) : TextureBinding{};
        r.texture = b.texture;
        r.sampler = b.sampler;
        r.shading = shading(*r.gpu, r.material, r.fade, r.texture);
        if (r.gpu->influences == 0) r.skin = nullptr;  // its copy has no skin weights to skin by
        r.shading.skin = r.skin ? r.gpu->influences : 0;
        if (r.material && r.material->physical) physicalTextures(r);
        featureColors(r);
        // Lines wider than glLineWidth draws are quads from a geometry stage; outlines are lines too.
        const bool wide = pointShading_.lineWidth > lineWidthLimit();
        r.shading.round = r.shading.point && pointShading_.round;
        r.shading.wideLine = r.gpu->mode == GL_LINES && wide;
        r.program = &programFor(r.shading);
        r.outline = nullptr;
        if (r.gpu->outlineCount > 0) {
            Shading o = r.shading;
            o.outline = true;
            o.wideLine = wide;
            r.outline = &programFor(o);
        }
    }
    uploadJoints();
}

}  // namespace sg
