#include "sg/gl/Renderer.h"

#include "nodes/Geometry.h"

#include "sg/gl/internal/BackFaces.h"
#include "sg/gl/internal/DepthTarget.h"
#include "sg/gl/internal/GlProgram.h"
#include "sg/gl/internal/GpuCache.h"
#include "sg/gl/internal/Shaders.h"
#include "sg/scene/internal/DistinctGeometries.h"

#include <GL/gl.h>
#include <GL/glext.h>
#ifdef SGKIT_GL_OSMESA
#include <GL/osmesa.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace sg {

namespace {

// OSMesa's library exports only part of GL 4.5 (not glClipControl): ask it; the system libGL exports all.
PFNGLCLIPCONTROLPROC clipControl() {
#ifdef SGKIT_GL_OSMESA
    static const auto fn = reinterpret_cast<PFNGLCLIPCONTROLPROC>(OSMesaGetProcAddress("glClipControl"));
    return fn;
#else
    return &glClipControl;
#endif
}

// The same for glGetQueryObjectui64v (GL 3.3's timer queries), which OSMesa's library does not export either.
PFNGLGETQUERYOBJECTUI64VPROC queryObjectUi64() {
#ifdef SGKIT_GL_OSMESA
    static const auto fn =
        reinterpret_cast<PFNGLGETQUERYOBJECTUI64VPROC>(OSMesaGetProcAddress("glGetQueryObjectui64v"));
    return fn;
#else
    return &glGetQueryObjectui64v;
#endif
}

#ifndef NDEBUG
const char* errorName(GLenum e) {
    switch (e) {
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        default: return "unknown GL error";
    }
}

void checkGl(const char* fn, const char* what) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) return;
    while (glGetError() != GL_NO_ERROR) {
    }
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(e));
    throw std::runtime_error(std::string(fn) + ": " + errorName(e) + " (" + code + ") " + what);
}
// Errors left by the application are not ours to report.
void drainGl() {
    while (glGetError() != GL_NO_ERROR) {
    }
}
#else
inline void checkGl(const char*, const char*) {}
inline void drainGl() {}
#endif

std::string describe(const Renderer::Viewport& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.width) + "x" +
           std::to_string(v.height) + ")";
}

// The size of the framebuffer bound for drawing, where GL tells it: OSMesa's buffer, or a framebuffer object's
// first colour renderbuffer. A window's framebuffer and texture attachments (whose target would have to be bound
// to ask) give 0 x 0.
void drawFramebufferSize(GLuint fbo, int& width, int& height) {
    width = height = 0;
    if (fbo == 0) {
#ifdef SGKIT_GL_OSMESA
        GLint w = 0, h = 0;
        OSMesaGetIntegerv(OSMESA_WIDTH, &w);
        OSMesaGetIntegerv(OSMESA_HEIGHT, &h);
        if (w > 0 && h > 0) width = w, height = h;
#endif
        return;
    }
    GLint type = GL_NONE, name = 0, bound = 0;
    glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                          GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_RENDERBUFFER) return;
    glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                          GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    glGetIntegerv(GL_RENDERBUFFER_BINDING, &bound);
    glBindRenderbuffer(GL_RENDERBUFFER, GLuint(name));
    glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_WIDTH, &width);
    glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_HEIGHT, &height);
    glBindRenderbuffer(GL_RENDERBUFFER, GLuint(bound));
}

}  // namespace

Renderer::Renderer() {
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    if (!version) throw std::runtime_error("Renderer::Renderer(): no current OpenGL context");
    int major = 0, minor = 0;
    if (std::sscanf(version, "%d.%d", &major, &minor) != 2 || major * 10 + minor < 33)
        throw std::runtime_error(std::string("Renderer::Renderer(): OpenGL 3.3 is needed, the context has ") + version);
    drainGl();

    one_ = link(kVertexShader, kFragmentShader, "Renderer::Renderer()");
    glGenBuffers(1, &instanceVbo_);
    // Anisotropic filtering: core in GL 4.6, an extension before it that nearly every driver has. Not on a
    // software rasterizer, where each extra sample is paid in full, unlike on a GPU's texture units (what it
    // costs: docs/benchmarks.md, "Factory walkthrough").
    const auto* glRenderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string rendererName = glRenderer ? glRenderer : "";
    software_ = rendererName.find("llvmpipe") != std::string::npos ||
                rendererName.find("softpipe") != std::string::npos || rendererName.find("swrast") != std::string::npos;
    float maxAnisotropy = 1.0f;  // 1 when GL has no anisotropic filtering, or rasterizes in software
    GLint extensions = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &extensions);
    for (GLint i = 0; i < extensions && !software_; ++i) {
        const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
        if (e && (std::strcmp(e, "GL_EXT_texture_filter_anisotropic") == 0 ||
                  std::strcmp(e, "GL_ARB_texture_filter_anisotropic") == 0)) {
            glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT, &maxAnisotropy);
            break;
        }
    }
    // Reverse-Z needs the [0, 1] clip depth of glClipControl: with GL's [-1, 1] the window transform's
    // 0.5 z + 0.5 rounds away the float buffer's resolution near 0, where the far depths are.
    bool clipControlExt = major * 10 + minor >= 45;
    for (GLint i = 0; i < extensions && !clipControlExt; ++i) {
        const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
        clipControlExt = e && std::strcmp(e, "GL_ARB_clip_control") == 0;
    }
    reverseZSupported_ = clipControlExt && clipControl() != nullptr;
    depthMode_ = reverseZSupported_ ? DepthMode::Auto : DepthMode::Classic;
    try {
        checkGl("Renderer::Renderer()", "after compiling the shaders");
    } catch (...) {
        glDeleteBuffers(1, &instanceVbo_);
        glDeleteProgram(one_.id);
        throw;
    }
    // Timer queries are core in GL 3.3 (ARB_timer_query); a driver may still report no counter bits.
    GLint bits = 0;
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &bits);
    if (glGetError() == GL_NO_ERROR && bits > 0 && queryObjectUi64()) glGenQueries(1, &timeQuery_);
    cache_ = std::make_unique<GpuCache>(instanceVbo_, maxAnisotropy);
    depthTarget_ = std::make_unique<DepthTarget>();
}

Renderer::~Renderer() {
    cache_.reset();
    depthTarget_.reset();
    glDeleteBuffers(1, &instanceVbo_);
    if (timeQuery_) glDeleteQueries(1, &timeQuery_);
    glDeleteProgram(one_.id);
    for (auto& [features, p] : variants_) glDeleteProgram(p.id);
}

double Renderer::gpuMs() {
    if (timePending_) {
        GLuint64 ns = 0;
        queryObjectUi64()(timeQuery_, GL_QUERY_RESULT, &ns);
        gpuMs_ = double(ns) * 1e-6;
        timePending_ = false;
    }
    return timeQuery_ ? gpuMs_ : -1.0;
}

Renderer::Program Renderer::link(const char* vertexSource, const char* fragmentSource, const char* who) {
    Program p;
    p.id = buildGlProgram(vertexSource, fragmentSource, who);
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
    const char* names[5] = {"uBase", "uMr", "uNormal", "uOcclusion", "uEmissive"};
    const char* samplers[5] = {"uTexture", "uMrTex", "uNormalTex", "uOcclusionTex", "uEmissiveTex"};
    glUseProgram(p.id);
    for (int u = 0; u < 5; ++u) {
        p.uXf[u] = at((std::string(names[u]) + "Xf").c_str());
        p.uSet[u] = at((std::string(names[u]) + "Set").c_str());
        glUniform1i(at(samplers[u]), u);  // units: Shaders.h
    }
    glUseProgram(0);
    return p;
}

Renderer::Program& Renderer::programFor(const Shading& s) {
    if (shaderMode_ == ShaderMode::OneProgram) return one_;
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
    f = canonicalFeatures(f);
    const auto it = variants_.find(f);
    if (it != variants_.end()) return it->second;
    const std::string vs = variantSource(true, f), fs = variantSource(false, f);
    return variants_.emplace(f, link(vs.c_str(), fs.c_str(), "Renderer::draw()")).first->second;
}

void Renderer::use(Program& p) {
    if (current_ == &p) return;
    glUseProgram(p.id);
    current_ = &p;
    if (p.frame == draws_) return;
    p.frame = draws_;
    p.shadingSet = false;  // set in full by its first run of the frame
    glUniformMatrix4fv(p.uViewProj, 1, GL_FALSE, &viewProj_[0][0]);
    glUniform3f(p.uLightDir, lightDir_.x, lightDir_.y, lightDir_.z);
    glUniform1i(p.uHeadlight, light_.headlight ? 1 : 0);
    glUniform3f(p.uAmbient, light_.ambient.r, light_.ambient.g, light_.ambient.b);
    glUniform3f(p.uLightColor, light_.color.r, light_.color.g, light_.color.b);
    if (p.uLightE < 0) return;  // a classic program
    // Physical: the main light as irradiance (x pi: a white matte surface facing it shows its colour), the
    // hemisphere, the punctual lights relative to the eye.
    const vec3 e = light_.color * 3.14159265f, sky = light_.ambient, ground = light_.ambient * light_.groundShare;
    const float upLen = glm::length(light_.up);
    const vec3 up = upLen > 0.0f && std::isfinite(upLen) ? light_.up / upLen : vec3(0.0f, 0.0f, 1.0f);
    glUniform3f(p.uLightE, e.r, e.g, e.b);
    glUniform3f(p.uSky, sky.r, sky.g, sky.b);
    glUniform3f(p.uGround, ground.r, ground.g, ground.b);
    glUniform3f(p.uUp, up.x, up.y, up.z);
    if (p.uLightCount < 0) return;
    const auto n = GLsizei(punctual_.size());
    glUniform1i(p.uLightCount, n);
    glUniform4fv(p.uPunctualPos, n, &punctualPos_[0][0]);
    glUniform4fv(p.uPunctualDir, n, &punctualDir_[0][0]);
    glUniform3fv(p.uPunctualE, n, &punctualE_[0][0]);
    glUniform2fv(p.uPunctualCone, n, &punctualCone_[0][0]);
}

void Renderer::setDepthMode(DepthMode mode) {
    if (mode != DepthMode::Classic && !reverseZSupported_)
        throw std::invalid_argument(
            "Renderer::setDepthMode(): reverse-Z needs glClipControl (OpenGL 4.5 or GL_ARB_clip_control), which "
            "this context lacks");
    depthMode_ = mode;
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
    if (mat && mat->physical) {
        s.material = mat;
        s.lit = !mat->unlit;
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
        r.texture = cache_->texture(base.texture.get(), cut, true);
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
        r.pbrTextures[k] = cache_->texture(t.texture.get(), false, slots[k].second == kShadePbrEmissive);
        r.shading.pbr |= slots[k].second;
        set(t);
    }
    const TextureSlot &mr = p.metallicRoughness, &ao = p.occlusion;
    if ((r.shading.pbr & kShadePbrMr) && (r.shading.pbr & kShadePbrOcclusion) && mr.texture == ao.texture &&
        mr.texCoord == ao.texCoord && mr.transform == ao.transform)
        r.shading.pbr |= kShadePbrOrm;
}

// Uniforms missing from a variant have location -1, which GL ignores; the values are kept per program, as GL keeps
// them.
void Renderer::setShading(Program& p, const Shading& s) {
    const bool all = !p.shadingSet;
    const Shading& o = p.shading;
    if (all || s.texture != o.texture) glUniform1i(p.uUseTexture, s.texture ? 1 : 0);
    if (all || s.colors != o.colors) glUniform1i(p.uUseColor, s.colors ? 1 : 0);
    if (all || s.lit != o.lit) glUniform1i(p.uLit, s.lit ? 1 : 0);
    if (all || s.bakedLight != o.bakedLight) glUniform1i(p.uBakedLight, s.bakedLight ? 1 : 0);
    if (all || s.specular != o.specular) glUniform1f(p.uSpecular, s.specular);
    if (all || s.shininess != o.shininess) glUniform1f(p.uShininess, s.shininess);
    if (all || s.fade != o.fade) glUniform1f(p.uFade, s.fade);
    if (all || s.alphaCutoff != o.alphaCutoff) glUniform1f(p.uAlphaCutoff, s.alphaCutoff);
    if (s.material && (all || s.material != o.material)) {  // a physical material's factors and UV transforms
        const Material& m = *s.material;
        const PhysicalMaterial& pm = m.pbr;
        glUniform1f(p.uMetallic, pm.metallic);
        glUniform1f(p.uRoughness, pm.roughness);
        glUniform3f(p.uEmissive, pm.emissiveFactor.r, pm.emissiveFactor.g, pm.emissiveFactor.b);
        glUniform1f(p.uNormalScale, pm.normalScale);
        glUniform1f(p.uOcclusionStrength, pm.occlusionStrength);
        const std::pair<int, const mat3*> slots[5] = {{m.texCoord, &m.textureTransform},
                                                      {pm.metallicRoughness.texCoord, &pm.metallicRoughness.transform},
                                                      {pm.normal.texCoord, &pm.normal.transform},
                                                      {pm.occlusion.texCoord, &pm.occlusion.transform},
                                                      {pm.emissive.texCoord, &pm.emissive.transform}};
        for (int u = 0; u < 5; ++u) {
            glUniform1i(p.uSet[u], slots[u].first);
            glUniformMatrix3fv(p.uXf[u], 1, GL_FALSE, &(*slots[u].second)[0][0]);
        }
    }
    p.shading = s;
    p.shadingSet = true;
}

void Renderer::draw(const DrawList& list, const Camera& camera, const vec4& clearColor) {
    // The camera's own viewport is not checked against the framebuffer: GL clips what lies outside, as it always has.
    drawFrame(list, camera, Viewport{0, 0, camera.width(), camera.height()}, clearColor, false);
}

void Renderer::draw(const DrawList& list, const Camera& camera, const Viewport& viewport, const vec4& clearColor) {
    drawFrame(list, camera, viewport, clearColor, true);
}

void Renderer::drawFrame(const DrawList& list, const Camera& camera, const Viewport& viewport, const vec4& clearColor,
                         bool inFramebuffer) {
    const auto t0 = std::chrono::steady_clock::now();
    drainGl();
    Target t = target(viewport, inFramebuffer);
    cache_->nextFrame();
    stats_ = RenderStats{};
    buildRuns(list, camera);
    upload();
    if (timeQuery_) glBeginQuery(GL_TIME_ELAPSED, timeQuery_);
    beginFrame(t, camera, clearColor);
    if (!runs_.empty()) drawRuns(list, camera, t.reverse);
    if (afterItems_)
        afterItems_(mat4((t.reverse ? camera.reverseZProjection() : camera.projection()) * camera.viewRotation()),
                    t.reverse);
    endFrame(t);
    if (timeQuery_) {
        glEndQuery(GL_TIME_ELAPSED);
        timePending_ = true;
    }
    checkGl("Renderer::draw()", "after drawing");
    stats_.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

Renderer::Target Renderer::target(const Viewport& viewport, bool inFramebuffer) {
    const Viewport& v = viewport;
    if (v.width <= 0 || v.height <= 0 || v.x < 0 || v.y < 0)
        throw std::invalid_argument("Renderer::draw(): viewport " + describe(v) +
                                    (v.width <= 0 || v.height <= 0 ? " has no area" : " has a negative corner"));
    GLint drawFbo = 0, readFbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFbo);
    Target t;
    t.drawFbo = GLuint(drawFbo);
    t.readFbo = GLuint(readFbo);
    t.viewport = v;
    drawFramebufferSize(t.drawFbo, t.width, t.height);
    const int64_t right = int64_t(v.x) + v.width, top = int64_t(v.y) + v.height;
    if (std::max(right, top) > std::numeric_limits<int>::max())
        throw std::invalid_argument("Renderer::draw(): viewport " + describe(v) + " reaches past any framebuffer");
    if (inFramebuffer && t.width > 0 && (right > t.width || top > t.height))
        throw std::invalid_argument("Renderer::draw(): viewport " + describe(v) + " reaches past the " +
                                    std::to_string(t.width) + "x" + std::to_string(t.height) + " framebuffer");
    return t;
}

// Dissolving items are few: a dense copy of DrawList::fades only in frames that have them.
void Renderer::indexFades(const DrawList& list) {
    fades_.clear();
    if (list.fades.empty()) return;
    fades_.assign(list.items.size(), 1.0f);
    for (const auto& [i, f] : list.fades)
        if (i < fades_.size() && f > -1.0f && f < 1.0f) fades_[i] = f;
}

// Like fades: a dense copy of DrawList::parts only in frames that draw items in part, each part checked.
void Renderer::indexParts(const DrawList& list) {
    parts_.clear();
    if (list.parts.empty()) return;
    parts_.assign(list.items.size(), kWhole);
    for (size_t p = 0; p < list.parts.size(); ++p) {
        const DrawList::Part& part = list.parts[p];
        const Mesh* m = part.item < list.items.size() ? list.items[part.item].mesh : nullptr;
        bool ok = m && uint64_t(part.first) + part.count <= list.ranges.size();
        for (uint32_t r = 0; ok && r < part.count; ++r) {
            const IndexRange& ir = list.ranges[size_t(part.first) + r];
            ok = uint64_t(ir.first) + ir.count <= m->indexCount();
        }
        if (!ok)
            throw std::out_of_range("Renderer::draw(): parts[" + std::to_string(p) + "] (item " +
                                    std::to_string(part.item) + ", ranges " + std::to_string(part.first) + " + " +
                                    std::to_string(part.count) + ") is past the items, the " +
                                    std::to_string(list.ranges.size()) + " ranges or its mesh's indices");
        parts_[part.item] = uint32_t(p);
    }
}

// Runs of equal (mesh, material) pointers in draw order, split where the back faces' culling changes; blended items
// (Material::blend) after all others, farthest first by the centre of their bound along the view. Every matrix of
// the frame goes in one buffer.
void Renderer::buildRuns(const DrawList& list, const Camera& camera) {
    const double reach = backFaceCulling_ ? nearPlaneReach(camera) : -1.0;
    const size_t n = list.order.empty() ? list.items.size() : list.order.size();
    items_.clear();
    runs_.clear();
    blended_.clear();
    indexFades(list);
    indexParts(list);
    const vec3 view(camera.viewDirection());
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = list.order.empty() ? uint32_t(k) : list.order[k];
        if (i >= list.items.size())
            throw std::out_of_range("Renderer::draw(): order[" + std::to_string(k) + "] = " + std::to_string(i) +
                                    " is past the " + std::to_string(list.items.size()) + " items");
        const DrawItem& it = list.items[i];
        if (!it.mesh || it.mesh->indexCount() == 0) continue;
        if (it.material && it.material->blend) {
            const float depth = glm::dot(view, it.model * vec4(vec3(it.mesh->box().center()), 1.0f));
            blended_.push_back({std::isfinite(depth) ? depth : 0.0f, i});
            continue;
        }
        addItem(list, i, reach);
    }
    std::stable_sort(blended_.begin(), blended_.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& [depth, i] : blended_) addItem(list, i, reach);
}

void Renderer::addItem(const DrawList& list, uint32_t i, double reach) {
    const DrawItem& it = list.items[i];
    const float fade = fades_.empty() ? 1.0f : fades_[i];
    const uint32_t part = parts_.empty() ? kWhole : parts_[i];
    const Material* mat = it.material;
    // A single-sided material's back faces are never drawn (glTF: "back-face culling must be enabled"); a mirroring
    // matrix turns which winding is in front.
    const bool single = mat && !mat->doubleSided;
    const bool mirrored = single && glm::determinant(glm::mat3(it.model)) < 0.0f;
    const bool cullBack = single || (fade == 1.0f && (part == kWhole || list.parts[part].coversScreen) &&
                                     backFacesHidden(it, mat, reach));
    if (runs_.empty() || runs_.back().mesh != it.mesh || runs_.back().material != mat || runs_.back().fade != fade ||
        part != kWhole || runs_.back().part != kWhole || runs_.back().cullBack != cullBack ||
        runs_.back().mirrored != mirrored) {
        runs_.push_back(Run{it.mesh,
                            mat,
                            uint32_t(items_.size()),
                            0,
                            fade,
                            part,
                            cullBack,
                            mirrored,
                            mat && mat->blend,
                            nullptr,
                            0,
                            {},
                            nullptr,
                            {}});
    }
    runs_.back().count++;
    items_.push_back(ItemAttributes{it.matrix(), mat ? mat->baseColor : vec4(1.0f)});
}

// Every mesh and texture of the frame is uploaded before the first draw: on llvmpipe an upload between
// draws makes every draw after it store the whole rasterizer state again (docs/benchmarks.md).
void Renderer::upload() {
    for (Run& r : runs_) {
        r.gpu = &cache_->mesh(r.mesh);
        const Texture* tex = r.material && !r.material->physical && r.gpu->uvs ? r.material->texture.get() : nullptr;
        r.texture = tex ? cache_->texture(tex, r.material->alphaCutoff > 0.0f) : 0;
        r.shading = shading(*r.gpu, r.material, r.fade, r.texture);
        if (r.material && r.material->physical) physicalTextures(r);
        r.program = &programFor(r.shading);
    }
}

// Auto: the far/near ratio of a perspective projection is (a - 1) / (a + 1) for a = proj[2][2]
// (-(f + n) / (f - n)); an infinite far plane (a = -1) or NaN gives ReverseZ, the safer.
bool Renderer::wantsReverseZ(const Camera& camera) const {
    const double a = camera.projection()[2][2];
    return depthMode_ == DepthMode::ReverseZ || (depthMode_ == DepthMode::Auto && camera.perspective() &&
                                                 !(std::abs((a - 1.0) / (a + 1.0)) <= kAutoReverseRatio));
}

// Binds where the frame goes (ReverseZ: the renderer's framebuffer, with float depth, in the target's pixel
// coordinates; its colour goes to the target in endFrame), sets the frame's GL state and clears the viewport.
void Renderer::beginFrame(Target& t, const Camera& camera, const vec4& clearColor) {
    const Viewport& v = t.viewport;
    if (wantsReverseZ(camera)) {
        // As large as the target where its size is known, so that views side by side share one; else as large
        // as the viewports drawn so far.
        const int w = std::max(v.x + v.width, t.width), h = std::max(v.y + v.height, t.height);
        const DepthTarget::Bind bound = depthTarget_->bind(w, h, t.width > 0);
        t.reverse = bound == DepthTarget::Bind::Bound;
        if (bound == DepthTarget::Bind::Unsupported) {  // a driver without float depth attachments
            reverseZSupported_ = false;
            depthMode_ = DepthMode::Classic;
        }
        if (!t.reverse) {  // drawn into directly: the bindings as they were (a failed setup may move them)
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.drawFbo);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, t.readFbo);
        }
    }
    lastReverseZ_ = t.reverse;
    if (t.reverse) clipControl()(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glViewport(v.x, v.y, v.width, v.height);
    glScissor(v.x, v.y, v.width, v.height);
    glEnable(GL_SCISSOR_TEST);  // the clear too: glClear ignores the viewport
    glDisable(GL_CULL_FACE);    // per run (Run::cullBack)
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(t.reverse ? GL_GREATER : GL_LESS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(clearColor.r, clearColor.g, clearColor.b, clearColor.a);
    glClearDepth(t.reverse ? 0.0 : 1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void Renderer::drawRuns(const DrawList& list, const Camera& camera, bool reverse) {
    glBindBuffer(GL_ARRAY_BUFFER, instanceVbo_);
    // Orphaning: the driver hands out fresh storage instead of waiting for last frame's draws.
    const auto bytes = GLsizeiptr(items_.size() * sizeof(ItemAttributes));
    glBufferData(GL_ARRAY_BUFFER, bytes, nullptr, GL_STREAM_DRAW);
    glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, items_.data());

    // Projection times the view's rotation only, in double: the eye's translation is already in the
    // items' matrices, so no large coordinate ever reaches float.
    viewProj_ = mat4((reverse ? camera.reverseZProjection() : camera.projection()) * camera.viewRotation());
    lightDir_ = light_.headlight ? vec3(camera.viewDirection()) : glm::normalize(light_.direction);
    // The punctual lights relative to the eye, in float (as the items' matrices).
    const dvec3 eye = camera.eye();
    for (size_t k = 0; k < punctual_.size(); ++k) {
        const PunctualLight& l = punctual_[k];
        const float type = l.type == PunctualLight::Type::Directional ? 0.0f
                           : l.type == PunctualLight::Type::Point     ? 1.0f
                                                                      : 2.0f;
        punctualPos_[k] = vec4(vec3(l.position - eye), type);
        punctualDir_[k] = vec4(glm::normalize(l.direction), l.range);
        punctualE_[k] = l.color * l.intensity;
        // KHR_lights_punctual's cone: clamp(cos * scale + offset), scale = 1 / max(0.001, cos inner - cos outer).
        const float cosOuter = std::cos(l.outerConeAngle), cosInner = std::cos(l.innerConeAngle);
        const float scale = 1.0f / std::max(0.001f, cosInner - cosOuter);
        punctualCone_[k] = vec2(scale, -cosOuter * scale);
    }
    ++draws_;
    current_ = nullptr;
    glActiveTexture(GL_TEXTURE0);
    bool culling = false, mirrored = false, blending = false;
    for (const Run& r : runs_) {
        if (r.cullBack != culling) {
            culling = r.cullBack;
            if (culling)
                glEnable(GL_CULL_FACE);
            else
                glDisable(GL_CULL_FACE);
        }
        if (r.mirrored != mirrored) {
            mirrored = r.mirrored;
            glFrontFace(mirrored ? GL_CW : GL_CCW);
        }
        if (r.blend != blending) {  // the blended runs come last: the depth test stays, the writes stop
            blending = r.blend;
            glEnable(GL_BLEND);
            glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
            glDepthMask(GL_FALSE);
        }
        drawRun(list, r);
    }
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glBindVertexArray(0);
    glUseProgram(0);
    current_ = nullptr;
}

void Renderer::drawRun(const DrawList& list, const Run& r) {
    const GpuMesh& g = *r.gpu;
    glBindVertexArray(g.vao);
    glBindBuffer(GL_ARRAY_BUFFER, instanceVbo_);
    pointItemAttributes(r.first);
    if (r.texture) glBindTexture(GL_TEXTURE_2D, r.texture);
    if (r.shading.pbr & (kShadePbrMr | kShadePbrNormal | kShadePbrOcclusion | kShadePbrEmissive)) {
        for (int k = 0; k < 4; ++k)
            if (r.pbrTextures[k]) {
                glActiveTexture(GLenum(GL_TEXTURE0 + kMetallicRoughnessUnit + k));
                glBindTexture(GL_TEXTURE_2D, r.pbrTextures[k]);
            }
        glActiveTexture(GL_TEXTURE0);
    }
    use(*r.program);
    setShading(*r.program, r.shading);
    if (r.part == kWhole) {
        glDrawElementsInstanced(GL_TRIANGLES, g.indexCount, g.indexType, nullptr, GLsizei(r.count));
        stats_.triangles += uint64_t(r.count) * uint64_t(g.indexCount / 3);
    } else {
        // One item, its ranges: a non-instanced draw reads the item attributes' first element.
        const DrawList::Part& p = list.parts[r.part];
        const size_t bytes = g.indexType == GL_UNSIGNED_SHORT ? 2 : 4;
        rangeCounts_.clear();
        rangeOffsets_.clear();
        for (uint32_t k = 0; k < p.count; ++k) {
            const IndexRange& ir = list.ranges[size_t(p.first) + k];
            rangeCounts_.push_back(GLsizei(ir.count));
            rangeOffsets_.push_back(reinterpret_cast<const void*>(size_t(ir.first) * bytes));
            stats_.triangles += ir.count / 3;
        }
        glMultiDrawElements(GL_TRIANGLES, rangeCounts_.data(), g.indexType, rangeOffsets_.data(), GLsizei(p.count));
    }
    stats_.drawCalls++;
    stats_.instances += r.count;
    if (r.cullBack) stats_.backFacesSkipped += r.count;
}

// Back to GL's defaults for whatever draws next; ReverseZ: the viewport's colour to the framebuffer bound at the
// call, at the same place.
void Renderer::endFrame(const Target& target) {
    glDisable(GL_SCISSOR_TEST);
    if (!target.reverse) return;
    clipControl()(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glClearDepth(1.0);
    const Viewport& v = target.viewport;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, depthTarget_->framebuffer());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.drawFbo);
    glBlitFramebuffer(v.x, v.y, v.x + v.width, v.y + v.height, v.x, v.y, v.x + v.width, v.y + v.height,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.readFbo);
}

void Renderer::setLight(const DirectionalLight& light) {
    const float len = glm::length(light.direction);
    if (!light.headlight && !(len > 0.0f && std::isfinite(len)))
        throw std::invalid_argument(
            "Renderer::setLight(): the direction of a light that is not the headlight must be "
            "finite and non-zero");
    light_ = light;
}

void Renderer::setPunctualLights(std::vector<PunctualLight> lights) {
    if (lights.size() > kMaxLights)
        throw std::invalid_argument("Renderer::setPunctualLights(): " + std::to_string(lights.size()) +
                                    " lights, at most " + std::to_string(kMaxLights));
    for (size_t k = 0; k < lights.size(); ++k) {
        const PunctualLight& l = lights[k];
        const auto bad = [&](const char* field, const char* why) {
            throw std::invalid_argument("Renderer::setPunctualLights(): lights[" + std::to_string(k) + "]." + field +
                                        " " + why);
        };
        const auto finite3 = [](const auto& v) {
            return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
        };
        if (!finite3(l.position)) bad("position", "is not finite");
        if (!finite3(l.direction) || !(glm::length(l.direction) > 0.0f)) bad("direction", "is zero or not finite");
        if (!finite3(l.color) || l.color.r < 0.0f || l.color.g < 0.0f || l.color.b < 0.0f)
            bad("color", "is negative or not finite");
        if (!(l.intensity >= 0.0f) || !std::isfinite(l.intensity)) bad("intensity", "is negative or not finite");
        if (!(l.range >= 0.0f) || !std::isfinite(l.range)) bad("range", "is negative or not finite");
        if (l.type == PunctualLight::Type::Spot &&
            !(l.innerConeAngle >= 0.0f && l.innerConeAngle < l.outerConeAngle && l.outerConeAngle <= 1.5707964f))
            bad("outerConeAngle", "must satisfy 0 <= innerConeAngle < outerConeAngle <= pi / 2");
    }
    punctual_ = std::move(lights);
}

void Renderer::finish() const { glFinish(); }

Image Renderer::readColor() const {
    GLint vp[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_VIEWPORT, vp);
    return readColor(Viewport{vp[0], vp[1], vp[2], vp[3]});
}

Image Renderer::readColor(const Viewport& rect) const {
    if (rect.width <= 0 || rect.height <= 0 || rect.x < 0 || rect.y < 0)
        throw std::invalid_argument("Renderer::readColor(): rectangle " + describe(rect) +
                                    (rect.width <= 0 || rect.height <= 0 ? " has no area" : " has a negative corner"));
    Image img;
    img.width = rect.width;
    img.height = rect.height;
    const size_t row = size_t(img.width) * 4u;
    std::vector<uint8_t> tmp(row * size_t(img.height));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(rect.x, rect.y, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, tmp.data());
    checkGl("Renderer::readColor()", "from glReadPixels");
    img.rgba.resize(tmp.size());
    for (int y = 0; y < img.height; ++y)  // GL's first row is the bottom one
        std::memcpy(&img.rgba[size_t(y) * row], &tmp[size_t(img.height - 1 - y) * row], row);
    return img;
}

std::vector<float> Renderer::readDepth() const {
    GLint vp[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_VIEWPORT, vp);
    const size_t w = size_t(vp[2]), h = size_t(vp[3]);
    std::vector<float> tmp(w * h), out(w * h);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    GLint readTarget = 0;
    if (lastReverseZ_) {  // the depth is in the renderer's framebuffer, not the target's
        glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readTarget);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, depthTarget_->framebuffer());
    }
    glReadPixels(vp[0], vp[1], vp[2], vp[3], GL_DEPTH_COMPONENT, GL_FLOAT, tmp.data());
    if (lastReverseZ_) glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(readTarget));
    checkGl("Renderer::readDepth()", "from glReadPixels");
    for (size_t y = 0; y < h; ++y) std::memcpy(&out[y * w], &tmp[(h - 1 - y) * w], w * sizeof(float));
    return out;
}

bool Renderer::prepare(const Node& root, PrepareBudget& budget) {
    ++prepareCalls_;
    auto found = prepareLists_.find(&root);
    if (found == prepareLists_.end()) {  // the first call for this detail: list what draw() would upload
        PrepareList list;
        list.root = &root;
        list.walk = std::make_shared<DistinctGeometryWalk>(root);
        found = prepareLists_.emplace(&root, std::move(list)).first;
    }
    PrepareList& list = found->second;
    list.touched = prepareCalls_;
    // Listing a detail of many thousand nodes takes milliseconds too: it goes on within the time budget, the
    // items listed so far upload meanwhile.
    if (list.walk) {
        const bool listed = list.walk->run(
            [&](const Geometry& g) {
                if (g.mesh()) list.items.emplace_back(g.mesh(), g.material());
            },
            [&] { return budget.elapsedMs() >= budget.ms; });
        if (listed) list.walk.reset();
    }
    // What was uploaded by earlier calls keeps its grace while this detail waits (GpuCache::prepareMesh).
    for (size_t i = 0; i < list.next; ++i) cache_->prepareMesh(list.items[i].first.get());
    for (; list.next < list.items.size(); ++list.next) {
        const Mesh* m = list.items[list.next].first.get();
        const Material* mat = list.items[list.next].second;
        // The same copies draw() would take: the mesh, and its material's texture when it has UVs.
        // (A physical material's other textures upload on first draw.)
        const bool physical = mat && mat->physical;
        const auto& uvs = physical && mat->texCoord == 1 ? m->uvs1() : m->uvs();
        const Texture* tex = mat && !uvs.empty() && uvs.size() == m->positions().size() ? mat->texture.get() : nullptr;
        const bool cut = mat && mat->alphaCutoff > 0.0f;
        const bool needs = !cache_->hasMesh(m) || (tex && !cache_->hasTexture(tex, cut, physical));
        if (needs && budget.exhausted()) break;
        if (cache_->prepareMesh(m)) budget.spend(1, m->bytes());
        if (tex && cache_->prepareTexture(tex, cut, physical)) budget.spend(1, tex->rgba().size());
    }
    const bool done = !list.walk && list.next == list.items.size();
    if (done) prepareLists_.erase(found);
    // Lists of details dropped before they were prepared.
    for (auto it = prepareLists_.begin(); it != prepareLists_.end();)
        it = prepareCalls_ - it->second.touched > kPrepareForget ? prepareLists_.erase(it) : std::next(it);
    return done;
}

void Renderer::releaseUnused() { cache_->releaseUnused(); }

void Renderer::clear() { cache_->clear(); }

size_t Renderer::cachedMeshes() const { return cache_->meshCount(); }

size_t Renderer::cachedTextures() const { return cache_->textureCount(); }

}  // namespace sg
