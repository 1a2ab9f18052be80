// Renderer: the runs drawn, each with its program, uniforms, textures and draw call.
#include "sg/gl/Renderer.h"

#include "sg/gl/internal/GpuCache.h"
#include "sg/gl/internal/Shaders.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <cmath>

namespace sg {

void Renderer::drawRuns(const DrawList& list, const Camera& camera, bool reverse) {
    glBindBuffer(GL_ARRAY_BUFFER, instanceVbo_);
    // Orphaning: the driver hands out fresh storage instead of waiting for last frame's draws.
    const auto bytes = GLsizeiptr(items_.size() * sizeof(ItemAttributes));
    glBufferData(GL_ARRAY_BUFFER, bytes, nullptr, GL_STREAM_DRAW);
    glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, items_.data());

    // Projection times the view's rotation only, in double: the eye's translation is already in the
    // items' matrices, so no large coordinate ever reaches float.
    viewProj_ = mat4((reverse ? camera.reverseZProjection() : camera.projection()) * camera.viewRotation());
    frameLights(camera);
    GLint viewport[4] = {0, 0, 1, 1};
    glGetIntegerv(GL_VIEWPORT, viewport);
    viewportSize_ = vec2(float(viewport[2]), float(viewport[3]));
    pixelsPerUnit_ = float(camera.projection()[1][1] * 0.5 * viewport[3]);
    glLineWidth(pointShading_.lineWidth <= lineWidthLimit() ? pointShading_.lineWidth : 1.0f);
    // The faces under an outline are pushed back rather than its lines pulled forward: the factor follows each face's
    // own depth slope (a line and a triangle sample depth up to a pixel apart, and across a grazing face that is more
    // than any fixed pull would cover), and the units are steps of the depth buffer at that depth (2^-24 in Classic's
    // fixed point, the float's own spacing in ReverseZ's), so the one offset holds in both modes. Away from the eye is
    // a smaller depth in ReverseZ. A wide line's quad reaches half its width off the edge: the factor covers that.
    const float away = reverse ? -1.0f : 1.0f;
    glPolygonOffset(away * (1.5f + 0.5f * pointShading_.lineWidth), away * 2.0f);
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
    glDisable(GL_POLYGON_OFFSET_FILL);
    glLineWidth(1.0f);
    glBindVertexArray(0);
    glUseProgram(0);
    // A sampler object left bound would override the parameters of whatever binds a texture there next (the
    // eye-dome pass's unfiltered depth, which has no mipmaps).
    for (int u = kBaseColorUnit; u <= kEmissiveUnit; ++u) glBindSampler(GLuint(u), 0);
    current_ = nullptr;
}

void Renderer::drawRun(const DrawList& list, const Run& r) {
    const GpuMesh& g = *r.gpu;
    glBindVertexArray(g.vao);
    glBindBuffer(GL_ARRAY_BUFFER, instanceVbo_);
    pointItemAttributes(r.first);
    if (r.skin)  // the block whole from the pose's rows (uploadJoints leaves room for it)
        glBindBufferRange(GL_UNIFORM_BUFFER, kJointBinding, jointBuffer_, GLintptr(r.jointOffset),
                          GLsizeiptr(kJointBlockBytes));
    if (r.texture) {
        glBindTexture(GL_TEXTURE_2D, r.texture);
        glBindSampler(kBaseColorUnit, r.sampler);
    }
    if (r.shading.pbr & (kShadePbrMr | kShadePbrNormal | kShadePbrOcclusion | kShadePbrEmissive)) {
        for (int k = 0; k < 4; ++k)
            if (r.pbrTextures[k]) {
                glActiveTexture(GLenum(GL_TEXTURE0 + kMetallicRoughnessUnit + k));
                glBindTexture(GL_TEXTURE_2D, r.pbrTextures[k]);
                glBindSampler(GLuint(kMetallicRoughnessUnit + k), r.pbrSamplers[k]);
            }
        glActiveTexture(GL_TEXTURE0);
    }
    if (r.featureColors) {
        glActiveTexture(GLenum(GL_TEXTURE0 + kFeatureUnit));
        glBindTexture(GL_TEXTURE_2D, r.featureColors);
        glActiveTexture(GL_TEXTURE0);
    }
    use(*r.program);
    if (r.shading.point && pointShading_.attenuate) {  // the spacing on screen at distance 1, for this frame
        Shading s = r.shading;
        s.pointScale = r.mesh->pointSpacing() * pointShading_.spacingScale * pixelsPerUnit_;
        setShading(*r.program, s);
    } else {
        setShading(*r.program, r.shading);
    }
    if (r.outline) glEnable(GL_POLYGON_OFFSET_FILL);
    if (g.mode == GL_POINTS) {
        glDrawArraysInstanced(GL_POINTS, 0, g.indexCount, GLsizei(r.count));
        stats_.points += uint64_t(r.count) * uint64_t(g.indexCount);
    } else if (g.mode == GL_LINES) {
        glDrawElementsInstanced(GL_LINES, g.indexCount, g.indexType, nullptr, GLsizei(r.count));
        stats_.lines += uint64_t(r.count) * uint64_t(g.indexCount / 2);
    } else if (r.part == kWhole) {
        glDrawElementsInstanced(GL_TRIANGLES, g.indexCount, g.indexType, nullptr, GLsizei(r.count));
        stats_.triangles += uint64_t(r.count) * uint64_t(g.indexCount / 3);
    } else {
        // One item, its ranges (a triangle mesh's: indexParts): a non-instanced draw reads the item attributes' first
        // element.
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
    if (r.outline) drawOutline(r);
}

// The whole outline, also over an item drawn in part: its edges are few, and those off screen are clipped.
void Renderer::drawOutline(const Run& r) {
    glDisable(GL_POLYGON_OFFSET_FILL);
    const GpuMesh& g = *r.gpu;
    use(*r.outline);
    setShading(*r.outline, r.shading);
    // The faces' culling is not the edges': a wide line's quad winds either way.
    if (r.cullBack) glDisable(GL_CULL_FACE);
    glDrawElementsInstanced(GL_LINES, g.outlineCount, GL_UNSIGNED_INT, reinterpret_cast<const void*>(g.outlineOffset),
                            GLsizei(r.count));
    if (r.cullBack) glEnable(GL_CULL_FACE);
    stats_.lines += uint64_t(r.count) * uint64_t(g.outlineCount / 2);
    stats_.drawCalls++;
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
    glUniform1f(p.uPointSize, pointShading_.pointSize);
    glUniform1f(p.uMaxPointSize, pointShading_.maxPointSize);
    glUniform2f(p.uViewportSize, viewportSize_.x, viewportSize_.y);
    glUniform1f(p.uLineWidth, pointShading_.lineWidth);
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
    if (all || s.pointScale != o.pointScale) glUniform1f(p.uPointScale, s.pointScale);
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

}  // namespace sg
