// Renderer: draws a DrawList with OpenGL 3.3 core, batching runs of equal state into instanced draws.
#pragma once
#include "sg/core/Camera.h"
#include "sg/core/DirectionalLight.h"
#include "sg/core/Material.h"
#include "sg/core/Mesh.h"
#include "sg/core/Node.h"
#include "sg/core/Pose.h"
#include "sg/core/PrepareBudget.h"
#include "sg/core/Ref.h"
#include "sg/cull/DrawList.h"
#include "sg/gl/PointShading.h"
#include "sg/io/ImageIO.h"
#include "sg/style/FeatureStyle.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace sg {

class DepthTarget;  // sg/gl/internal/DepthTarget.h, internal
class DrawUseWalk;  // sg/gl/internal/DrawUseWalk.h, internal
class EyeDome;      // sg/gl/internal/EyeDome.h, internal
class GpuCache;     // sg/gl/internal/GpuCache.h, internal
struct GpuMesh;
struct ItemAttributes;  // sg/gl/internal/Shaders.h, internal

struct RenderStats {
    // Draw calls: a glDrawElementsInstanced per run of equal mesh and material (glDrawArraysInstanced for points), a
    // glMultiDrawElements per item drawn in part (DrawList::parts), and one more per run whose mesh has an outline.
    uint64_t drawCalls = 0;
    uint64_t instances = 0;  // draw items drawn
    uint64_t triangles = 0;
    uint64_t points = 0;
    uint64_t lines = 0;             // segments: those of line meshes and of outlines (Mesh::outline())
    uint64_t backFacesSkipped = 0;  // items drawn without their back faces (Renderer::setBackFaceCulling)
    double ms = 0.0;                // CPU time of draw(), without waiting for the GPU to finish
    // Shader variants compiled in this draw: their first use (0 in every frame once the scene's are prepared:
    // Renderer::prepareVariants).
    uint64_t programsCompiled = 0;
};

class Renderer {
public:
    // How depth is stored and compared. ReverseZ keeps depth resolution relative to the distance at any
    // near/far ratio (docs/architecture.md, "Depth"); Classic is what a context without glClipControl can do.
    enum class DepthMode : uint8_t {
        Classic,   // the bound framebuffer's depth buffer (24-bit fixed point), near -> 0, far -> 1, GL_LESS
        ReverseZ,  // a 32-bit float depth buffer of the renderer's own, near -> 1, far -> 0, GL_GREATER;
                   // the colour is copied to the bound framebuffer at the end of draw()
        // Per draw: ReverseZ when the camera's far/near ratio is above kAutoReverseRatio (where 24 bits no
        // longer resolve a thousandth of the distance at the far plane), Classic below it: ordinary ranges do
        // not need to pay for the copy ReverseZ ends with (docs/benchmarks.md, "Depth").
        Auto,
    };
    static constexpr double kAutoReverseRatio = 1e4;

    // Needs a current OpenGL 3.3+ core context, which must stay alive (and be current whenever the
    // renderer is used or destroyed). Throws std::runtime_error when there is no such context or a
    // shader does not compile or link (the message carries the GLSL info log). Draws with Auto when the
    // context has glClipControl (OpenGL 4.5 or GL_ARB_clip_control), Classic otherwise.
    Renderer();
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // How draws get their shader program. Variants (the default): a program per combination of the features a
    // draw uses (texture, vertex colours, baked light, lit by the headlight or the sun, highlight, alpha cutoff,
    // fade), compiled on first use and kept, holding only what those draws read. OneProgram: one program for
    // every draw, branching on uniforms: the reference the variants are tested against pixel for pixel. Points,
    // outlines, lines wider than the context draws and skinned items take their variants in both modes (the one
    // program sizes no point and skins nothing).
    enum class ShaderMode : uint8_t { Variants, OneProgram };
    void setShaderMode(ShaderMode mode) { shaderMode_ = mode; }
    ShaderMode shaderMode() const { return shaderMode_; }
    // The variants compiled so far.
    size_t variantCount() const { return variants_.size(); }
    // Variants compiled inside draw() since the renderer was made (what prepareVariants() and prepare() did not
    // compile ahead); RenderStats::programsCompiled counts the last draw's.
    uint64_t compiledInDraw() const { return compiledInDraw_; }

    // A Geometry as its draws pick their shader variants: what prepareVariants() compiles ahead of them.
    struct DrawUse {
        ref_ptr<const Mesh> mesh;
        ref_ptr<const Material> material;
        bool fades = false;   // below an LOD with a transition: drawn dissolving at times, as well as whole
        uint32_t joints = 0;  // its skin's joints (Geometry::setSkin); 0: not skinned
    };
    // The Geometries below root with a mesh, each once for every way it can be drawn (a Geometry below LODs with and
    // without a transition, twice). Reads the graph only: on any thread that may read it, no context needed.
    static std::vector<DrawUse> drawUses(const Node& root);
    // Compiles the variants that the uses' draws take with the renderer's present state (light, punctual lights,
    // point shading, wide lines, feature style, shader mode), each both whole and dissolving where it can fade, and
    // readies each as drawn: the uses are drawn once each into a 1x1 viewport at the bound framebuffer's corner
    // (cleared there) with nothing reaching a pixel, and into the depth mode this camera takes. A compiled program is
    // not enough on a software rasterizer, which compiles its code for each program and draw state at the first draw
    // (llvmpipe: 1 ms to link, 40-80 ms at the first draw; docs/benchmarks.md, "Shader variants"). Uses whose
    // variants are ready are skipped (one draw per new variant at most). sg::Viewer calls it with the scene's root
    // before a scene's first frame; Renderer::prepare() does it for paged details. Returns the variants compiled.
    // Needs the renderer's context current; a change of the state above later compiles in the draw again.
    size_t prepareVariants(const std::vector<DrawUse>& uses, const Camera& camera);
    size_t prepareVariants(const Node& root, const Camera& camera) { return prepareVariants(drawUses(root), camera); }

    // Back faces that cannot show are not drawn (on by default): those of items whose mesh is closed (Mesh::closed()),
    // drawn opaque, with a matrix that keeps the winding, the eye outside the item's bound and the near
    // plane clear of it (sg/gl/internal/BackFaces.h). Such an item's back faces all lie behind its front faces, so the
    // pixels are those drawn with it off (tested), but where a back face meets its front face at a silhouette edge
    // at one depth, and the rounding of the rasterizer picked the back face: a few pixels a view. A software
    // rasterizer is spared half the triangles of a solid.
    void setBackFaceCulling(bool on) { backFaceCulling_ = on; }
    bool backFaceCulling() const { return backFaceCulling_; }

    // Whether the context rasterizes in software (llvmpipe, softpipe, swrast): where a frame loop wants
    // keepFreedMemory() (sg/gl/KeepFreedMemory.h), and where the renderer filters textures without anisotropy.
    bool softwareRasterizer() const { return software_; }

    // The depth strategy of the next draws, and whether the context allows ReverseZ. setDepthMode throws
    // std::invalid_argument when asked for ReverseZ or Auto on a context without glClipControl.
    DepthMode depthMode() const { return depthMode_; }
    bool reverseZSupported() const { return reverseZSupported_; }
    void setDepthMode(DepthMode mode);

    // A rectangle of the framebuffer in pixels, as glViewport takes it: (x, y) its lower left corner.
    struct Viewport {
        int x = 0, y = 0, width = 0, height = 0;
    };
    inline static const vec4 kClearColor{0.55f, 0.7f, 0.9f, 1.0f};

    // Clears the viewport (0, 0, camera.width(), camera.height()), then draws the items in list.order (all items
    // in their order when list.order is empty). Runs of consecutive items with the same mesh and
    // material pointers become one instanced draw call; an item drawn in part (DrawList::parts) draws its
    // index ranges alone, in one glMultiDrawElements (a triangle mesh's only: an item of points or lines is drawn whole
    // whatever its part says). Points and lines: see setPointShading(); they are unlit, but points with normals.
    // A triangle mesh's outline (Mesh::outline()) is drawn over its faces in black. An item listed in DrawList::poses
    // draws its pose's mesh (Pose::drawn); a skinned pose's vertices are moved by the weighted sum of their joints'
    // matrices (Pose::joints; on the GPU up to 256 joints, on the CPU beyond), then by the item's matrix, each such
    // item drawn alone. A posed item is drawn whole (a part, if any, is ignored: the cull cut the unposed mesh) and
    // with every back face that is not a single-sided material's (the proof that a closed mesh's back faces cannot
    // show is about the unposed mesh). Colour: base colour (white
    // without a material)
    // x texture (when the mesh has UVs) x vertex colour, lit by a two-sided headlight unless the
    // material is unlit or the mesh has no normals, or by the light setLight() gave (see there); fragments whose alpha
    // is below the material's alphaCutoff are discarded, all others drawn opaque. Throws std::out_of_range for an order
    // index past the items, a part whose item or ranges are out of range, or a pose whose item is past the items or
    // whose mesh weights a joint past the pose's joints; in debug builds std::runtime_error on a GL
    // error. The colour ends in the framebuffer bound for drawing at the call; with ReverseZ that framebuffer's depth
    // buffer is left as it was (readDepth reads the renderer's own), and a multisampled one is drawn into directly,
    // with Classic depth.
    void draw(const DrawList& list, const Camera& camera, const vec4& clearColor = kClearColor);
    // The same into `viewport` of the bound framebuffer: no pixel outside it is cleared or drawn (a scissor), so
    // views side by side in one framebuffer each look as if drawn alone (the camera's projection is the caller's
    // to match to the viewport's shape). Throws std::invalid_argument, before drawing anything, for a viewport
    // without area, with a negative corner or reaching past the framebuffer where its size is known (OSMesa's
    // buffer, a framebuffer object's colour renderbuffer; not a window's).
    void draw(const DrawList& list, const Camera& camera, const Viewport& viewport,
              const vec4& clearColor = kClearColor);
    const RenderStats& lastStats() const { return stats_; }
    // Drawn into every frame after its items (opaque, then blended ones, which write no depth) and before the frame
    // ends, with the frame's framebuffer, viewport, scissor and depth buffer still bound: what must test against the
    // frame's depth (OcclusionQueries' boxes). viewProj: the frame's projection times the view's rotation (the items'
    // matrices are eye-relative); reverseDepth: the frame stores reversed depth (nearer is greater, GL_GREATER). The
    // pass leaves GL as it found it: depth test on with the frame's function, depth and colour writes on, no program
    // or vertex array bound. Empty: none (the default).
    using AfterItems = std::function<void(const mat4& viewProj, bool reverseDepth)>;
    void setAfterItems(AfterItems pass) { afterItems_ = std::move(pass); }
    // The light of the next draws. A sun shades a lit fragment with albedo x (ambient + color x sun x
    // max(0, n.l)) + color x sun x specular x max(0, n.h)^shininess (Blinn-Phong, n turned toward the eye,
    // h halfway between the light and the eye), where sun is the vertex alpha for a bakedLight material
    // and 1 otherwise. The default headlight gives albedo x (0.35 + 0.65 |n.l| x sun), no highlight. Throws
    // std::invalid_argument for a sun whose direction is zero or not finite.
    void setLight(const DirectionalLight& light);
    const DirectionalLight& light() const { return light_; }
    // The scene's own lights (glTF's KHR_lights_punctual), which physical materials receive besides the light above
    // (classic materials do not): at most kMaxLights. Throws std::invalid_argument for more, or for a light whose
    // position, direction, colour, intensity, range or cone is not finite or out of its range (the message names
    // the light and the field).
    static constexpr size_t kMaxLights = 8;
    void setPunctualLights(std::vector<PunctualLight> lights);
    // Per-feature colours (a style, a highlighted feature): meshes whose first feature ID set is per vertex (an
    // attribute or implicit, with a property table) are drawn with their features' colours multiplying the base
    // colour, and without the features the style hides; null: no styling. The style is read at each draw, so a
    // restyle (FeatureStyle::setRule) shows in the next frame. ShaderMode::OneProgram draws unstyled.
    void setFeatureStyle(ref_ptr<FeatureStyle> style) { featureStyle_ = std::move(style); }
    FeatureStyle* featureStyle() const { return featureStyle_.get(); }
    // How points and lines are drawn (sg/gl/PointShading.h). Throws std::invalid_argument for a size, width, scale,
    // strength or radius that is not finite and positive (strength: not negative), naming it.
    void setPointShading(const PointShading& shading);
    const PointShading& pointShading() const { return pointShading_; }
    // How lines wider than a pixel are drawn. Auto (the default): glLineWidth where the context draws wide lines,
    // else quads from a geometry stage (a forward-compatible context, as GlfwWindow makes, takes no width above 1).
    // GeometryStage: the quads always; what a window draws, in any context (the tests compare the two).
    enum class WideLines : uint8_t { Auto, GeometryStage };
    void setWideLines(WideLines mode) { wideLines_ = mode; }
    const std::vector<PunctualLight>& punctualLights() const { return punctual_; }
    // Waits until the GPU has drawn everything (whole-frame timings).
    void finish() const;
    // The last draw()'s time as the GL measured it (a GL_TIME_ELAPSED query around the draw), in ms; waits for the
    // draw to finish. -1 where the context has no timer queries.
    double gpuMs();
    bool timerQueries() const { return timeQuery_ != 0; }

    // The current viewport's pixels (after a draw, its viewport's), rows top to bottom: readColor from the bound
    // read framebuffer, readDepth the last draw's depth buffer as stored: Classic 0 at the near plane and 1 at the
    // far plane and where nothing was drawn; ReverseZ 1 at the near plane and 0 at the far plane and where nothing
    // was drawn.
    Image readColor() const;
    // The pixels of `rect` of the bound read framebuffer (several views at once). Throws std::invalid_argument
    // for a rectangle without area or with a negative corner.
    Image readColor(const Viewport& rect) const;
    std::vector<float> readDepth() const;
    // Whether the last draw stored reversed depth (ReverseZ, or Auto that chose it): how readDepth() reads.
    bool lastDepthReversed() const { return lastReverseZ_; }

    // Meshes and textures are uploaded once and kept (with a reference, so that their pointers stay
    // valid); a Mesh changed after its first draw keeps its old GPU copy until released.
    // releaseUnused() frees those the last draw() did not use; clear() frees all of them.
    void releaseUnused();
    // Frees the copies of meshes and textures that nothing but the cache holds any more (a paged detail dropped: they
    // can never be drawn again), used or not; what the rest of the program holds stays. sg::Viewer calls it every few
    // frames, so that a flight's memory follows its pager's budget.
    void releaseOrphans();
    void clear();
    size_t cachedMeshes() const;
    // Uploads the meshes and textures below `root` (a paged detail before it is attached: Pager::setPrepare, which
    // sg::Viewer wires to this) into the cache while `budget` lasts, and readies the shader variants their draws
    // take (as prepareVariants(), with the last draw's camera): each upload counts an object and the bytes
    // (PrepareBudget::spend), a variant's compile counts its time, and none starts once the budget is exhausted
    // (its objects spent or its time, measured with steady_clock, up); a Geometry started is finished (on llvmpipe
    // a new variant takes 40-80 ms, more than a frame's budget: one a frame then). Returns true when everything
    // below root is in the cache and its variants are ready. What it uploads is kept
    // by releaseUnused() for a few frames (GpuCache::kPrepareGrace) until first drawn, so that the first draw
    // uploads nothing more. Needs the renderer's context current.
    bool prepare(const Node& root, PrepareBudget& budget);
    // Lets go of what prepare() keeps for `root` (its list holds the detail): for a detail dropped unprepared,
    // so that it is freed by whoever drops it, not by this renderer frames later.
    void forgetPrepare(const Node& root) { prepareLists_.erase(&root); }
    // A texture drawn with an alpha cutoff has its own copy, with colour bled under its transparent texels.
    size_t cachedTextures() const;
    // The GL sampler objects made so far: one per distinct Texture::sampler drawn (and per anisotropy, where the
    // context filters anisotropically), kept until clear().
    size_t samplerCount() const;

private:
    // The rest of a run's material and mesh, as uniforms: set only where they differ from the run before,
    // because on llvmpipe every draw after a uniform's change stores the whole rasterizer state again.
    struct Shading {
        bool texture = false, colors = false, lit = false, bakedLight = false;
        float specular = 0.0f, shininess = 1.0f, fade = 1.0f, alphaCutoff = 0.0f;
        // A physical material (Material::physical): its program's extra features (Shaders.h) and the material
        // whose factors and texture transforms its uniforms get.
        uint32_t pbr = 0;
        const Material* material = nullptr;
        bool features = false;  // per-feature colours (kShadeFeature)
        // Points (kShadePoint, round: kShadeRound) with their attenuation: the mesh's point spacing in pixels at
        // distance 1, 0 for a fixed size (set per frame); lines through a geometry stage (kShadeWideLine); the
        // outline's program (kShadeOutline).
        bool point = false, round = false, wideLine = false, outline = false;
        float pointScale = 0.0f;
        int skin = 0;  // skinned on the GPU: its mesh's influences, 4 or 8 (kShadeSkin4, kShadeSkin8); 0 not skinned
    };
    // A linked program, the locations of its uniforms (-1: not in this program) and the values they hold.
    struct Program {
        unsigned id = 0;
        int uViewProj = -1, uLightDir = -1, uHeadlight = -1, uAmbient = -1, uLightColor = -1, uUseTexture = -1,
            uUseColor = -1, uLit = -1, uBakedLight = -1, uSpecular = -1, uShininess = -1, uFade = -1, uAlphaCutoff = -1;
        // A physical variant's (ShadersPbr.cpp).
        int uLightE = -1, uSky = -1, uGround = -1, uUp = -1, uMetallic = -1, uRoughness = -1, uEmissive = -1,
            uNormalScale = -1, uOcclusionStrength = -1, uLightCount = -1, uPunctualPos = -1, uPunctualDir = -1,
            uPunctualE = -1, uPunctualCone = -1;
        // Points' and lines' (ShadersVertex.cpp).
        int uPointSize = -1, uMaxPointSize = -1, uPointScale = -1, uViewportSize = -1, uLineWidth = -1;
        int uXf[5] = {-1, -1, -1, -1, -1}, uSet[5] = {-1, -1, -1, -1, -1};  // by texture unit (Shaders.h)
        Shading shading;                                                    // what its per-run uniforms hold
        bool shadingSet = false;  // whether `shading` is known (from its first run in a frame on)
        uint64_t frame = 0;       // the draw() whose camera and light its uniforms hold
    };
    struct Run {
        const Mesh* mesh;
        const Material* material;
        uint32_t first, count;  // range in items_
        float fade;             // DrawList::fades
        uint32_t part;          // index into DrawList::parts for an item drawn in part (a run of one), else kWhole
        bool cullBack;  // its items' back faces are skipped (sg/gl/internal/BackFaces.h, or a single-sided material)
        bool mirrored;  // a single-sided material's items whose matrix turns the winding: clockwise is front
        bool blend;     // Material::blend: drawn blended, after the opaque runs
        const GpuMesh* gpu = nullptr;  // set before the first draw, when the frame's meshes are uploaded
        unsigned texture = 0;          // GL name, 0 without a texture
        unsigned pbrTextures[4] = {};  // a physical material's others, by unit from kMetallicRoughnessUnit
        Program* program = nullptr;    // set with gpu
        Shading shading;               // set with gpu: what picked the program and what its uniforms get
        unsigned featureColors = 0;    // the per-feature colour table's texture (kFeatureUnit), 0 without
        Program* outline = nullptr;    // its mesh's outline's program (set with gpu), null without an outline
        unsigned sampler = 0;          // texture's GL sampler object (Texture::sampler), set with it
        unsigned pbrSamplers[4] = {};  // pbrTextures' sampler objects
        // A skinned item (a run of one) drawn on the GPU: its pose, whose joints' matrices are at this byte offset in
        // the frame's joint buffer (set with gpu). Null: not skinned on the GPU.
        const Pose* skin = nullptr;
        size_t jointOffset = 0;
    };
    static constexpr uint32_t kWhole = ~0u;
    // The framebuffers bound at the call and the draw one's size (0 x 0 where GL cannot tell), the rectangle drawn,
    // and whether the frame goes to the renderer's own framebuffer (ReverseZ).
    struct Target {
        unsigned drawFbo = 0, readFbo = 0;
        int width = 0, height = 0;
        Viewport viewport;
        bool reverse = false;
    };

    // The steps of draw(), in order. inFramebuffer: the viewport must lie in the framebuffer where its size is known.
    void drawFrame(const DrawList& list, const Camera& camera, const Viewport& viewport, const vec4& clearColor,
                   bool inFramebuffer);
    static Target target(const Viewport& viewport, bool inFramebuffer);
    void buildRuns(const DrawList& list, const Camera& camera);
    void addItem(const DrawList& list, uint32_t i, double reach);
    void indexFades(const DrawList& list);
    // With a feature style: the colour of each item below a feature node (DrawList::features), alpha 0 for a
    // hidden one; filled only in frames that have such items.
    void indexFeatures(const DrawList& list);
    void indexParts(const DrawList& list);
    // DrawList::poses, checked, as a pose per item (filled only in frames with posed items); the CPU-skinned meshes
    // of the poses the frame before drew that this one does not, dropped (RendererPoses.cpp).
    void indexPoses(const DrawList& list);
    // What an item draws: its mesh, its pose's (Pose::drawn), or that skinned on the CPU (a skin past kMaxJoints).
    const Mesh* drawnMesh(const DrawItem& it, const Pose* pose);
    // Whether the pose is skinned on the GPU: joints within kMaxJoints and a mesh with skin weights.
    static bool gpuSkinned(const Pose* pose, const Mesh& drawn);
    // The skinned runs' joint matrices into the joint buffer, each pose's once, before the first draw.
    void uploadJoints();
    void upload();
    bool wantsReverseZ(const Camera& camera) const;
    void beginFrame(Target& target, const Camera& camera, const vec4& clearColor);
    // The frame's light uniforms (lightDir_, punctual*_) for this camera.
    void frameLights(const Camera& camera);
    void drawRuns(const DrawList& list, const Camera& camera, bool reverse);
    void drawRun(const DrawList& list, const Run& r);
    // PointShading::eyeDome's pass over the frame drawn (RendererEyeDome.cpp); nothing when it is off.
    void eyeDomePass(const Target& target, const Camera& camera);
    void drawOutline(const Run& r);
    void endFrame(const Target& target);

    // What picks a run's program, from its mesh's copy (or describeMesh(), before any upload), material, fade and
    // whether it is skinned on the GPU, with the renderer's state: the one function that says which variant a draw
    // takes, for draw() and prepareVariants() alike (RendererPrograms.cpp).
    Shading runShading(const GpuMesh& g, const Mesh& mesh, const Material* mat, float fade, bool skinned) const;
    Shading outlineShading(const Shading& s) const;  // its mesh's outline's
    // Whether the mesh draws with per-feature colours (setFeatureStyle, its ids per vertex, a property table).
    bool styled(const GpuMesh& g, const Mesh& mesh) const;
    // The physical material's textures the mesh reads (bit 0 the base colour, bit 1 + k the k-th of metallic-
    // roughness, normal, occlusion, emissive), their features and UV sets put into s.pbr (and s.texture).
    static unsigned physicalSlots(const Material& m, const GpuMesh& g, Shading& s);
    // A physical material's textures that the run's shading reads, bound.
    void physicalTextures(Run& r);
    // The run's per-feature colour table (setFeatureStyle), when its shading says so.
    void featureColors(Run& r);
    // The canonical features of the variant a shading draws with (Shaders.h), kOneProgram for the one program.
    static constexpr uint32_t kOneProgram = ~0u;
    uint32_t variantKey(const Shading& s) const;
    // The run's program: the one program, or the variant of the features it uses (compiled on first use, counted).
    Program& programFor(const Shading& s, bool blend);
    // A variant as ready to draw: its features, and whether it was drawn blended (a software rasterizer compiles
    // the blended draw's code apart).
    static uint64_t warmKey(uint32_t variant, bool blend) { return uint64_t(variant) | (uint64_t(blend) << 32); }
    // The keys of a use's draws (whole, dissolving, its outline) that no draw has readied yet, into `cold`.
    void coldKeys(const DrawUse& u, std::vector<uint64_t>& cold) const;
    // Draws the uses so that their variants are compiled and readied (prepareVariants()).
    void warmDraw(const std::vector<const DrawUse*>& uses, const Camera& camera);
    static Program link(const char* vertexSource, const char* fragmentSource, const char* who,
                        const char* geometrySource = nullptr);
    // Makes p current; the frame's camera and light go into it on its first use in the frame.
    void use(Program& p);
    void setShading(Program& p, const Shading& s);

    unsigned instanceVbo_ = 0;
    unsigned timeQuery_ = 0;                          // GL_TIME_ELAPSED around each draw(); 0 without timer queries
    bool timePending_ = false;                        // the last draw's query not read yet
    double gpuMs_ = -1.0;                             // its result once read
    Program one_;                                     // ShaderMode::OneProgram's
    std::unordered_map<uint32_t, Program> variants_;  // by canonical features (Shaders.h)
    std::unordered_set<uint64_t> warmed_;             // the variants drawn so far, by warmKey()
    uint64_t compiledInDraw_ = 0;
    bool warming_ = false;  // in prepareVariants()' draw: its compiles are not the frame's
    Camera lastCamera_;     // the last draw()'s: prepare() readies a detail's variants for it
    ShaderMode shaderMode_ = ShaderMode::Variants;
    bool backFaceCulling_ = true;
    Program* current_ = nullptr;  // in use in the draw
    uint64_t draws_ = 0;          // draw() calls: which frame a program's camera and light are of
    mat4 viewProj_{1.0f};         // the draw's
    vec3 lightDir_{0.0f};
    DepthMode depthMode_ = DepthMode::Classic;
    bool reverseZSupported_ = false;
    bool software_ = false;
    bool lastReverseZ_ = false;  // whether the last draw went to the renderer's framebuffer
    DirectionalLight light_;
    std::vector<PunctualLight> punctual_;
    ref_ptr<FeatureStyle> featureStyle_;
    PointShading pointShading_;
    WideLines wideLines_ = WideLines::Auto;
    // The widest line glLineWidth is asked to draw (setWideLines).
    float lineWidthLimit() const { return wideLines_ == WideLines::GeometryStage ? 1.0f : maxLineWidth_; }
    // Whether lines are drawn through the geometry stage (kShadeWideLine).
    bool wideLines() const { return pointShading_.lineWidth > lineWidthLimit(); }
    float maxLineWidth_ = 1.0f;   // the widest line glLineWidth draws: 1 in a forward-compatible context
    vec2 viewportSize_{1.0f};     // the frame's, in pixels
    float pixelsPerUnit_ = 0.0f;  // the frame's: a length 1 at distance 1, in pixels (Camera::pixelsPerUnit())
    vec4 punctualPos_[kMaxLights], punctualDir_[kMaxLights];  // the frame's uniforms for them (ShadersPbr.cpp)
    vec3 punctualE_[kMaxLights];
    vec2 punctualCone_[kMaxLights];
    std::vector<std::pair<float, uint32_t>> blended_;  // the frame's blended items: depth, item
    std::unique_ptr<GpuCache> cache_;
    // prepare()'s work per detail: its meshes and textures listed by one walk, and how far the uploads got, so
    // that a detail of many objects takes a walk once and a step per frame (not a walk per frame). Lists not
    // touched for kPrepareForget frames (their detail dropped unprepared) are forgotten. A list holds its detail:
    // its walk and materials point into it, and a detail freed early could leave its address to a new one.
    struct PrepareList {
        ref_ptr<const Node> root;
        std::shared_ptr<DrawUseWalk> walk;  // listing items; null once listed (internal type)
        std::vector<DrawUse> items;
        size_t next = 0;
        uint64_t touched = 0;
    };
    static constexpr uint64_t kPrepareForget = 600;
    std::unordered_map<const Node*, PrepareList> prepareLists_;
    uint64_t prepareCalls_ = 0;
    std::unique_ptr<DepthTarget> depthTarget_;  // ReverseZ's framebuffer
    std::unique_ptr<EyeDome> eyeDome_;          // made at the first frame with eye-dome lighting
    std::vector<ItemAttributes> items_;         // the frame's items, in draw order (Shaders.h)
    std::vector<Run> runs_;
    std::vector<float> fades_;             // per item, filled only in frames with dissolving items
    std::vector<vec4> itemFeatureColors_;  // per item, filled only in frames with feature nodes and a style
    std::vector<uint32_t> parts_;          // per item, its DrawList::parts index; filled only in frames with parts
    std::vector<const Pose*> poses_;       // per item, its pose or null; filled only in frames with posed items
    // The poses skinned on the CPU (more joints than the GPU's block holds): the mesh made for each, kept while the
    // pose is drawn (a pose never changes), with the last frame that drew it.
    struct CpuSkinned {
        ref_ptr<const Pose> pose;
        ref_ptr<const Mesh> mesh;
        uint64_t frame = 0;
    };
    std::unordered_map<const Pose*, CpuSkinned> cpuSkinned_;
    uint64_t poseFrames_ = 0;                          // frames with posed items so far: what CpuSkinned::frame counts
    unsigned jointBuffer_ = 0;                         // the frame's joint matrices (kJointBinding), made on first use
    size_t jointAlign_ = 0;                            // GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, in bytes (16 at least)
    std::vector<vec4> joints_;                         // the frame's, as uploaded: each joint's three rows
    std::unordered_map<const Pose*, size_t> jointAt_;  // the frame's poses' byte offsets in it
    std::vector<int> rangeCounts_;
    std::vector<const void*> rangeOffsets_;
    RenderStats stats_;
    AfterItems afterItems_;
};

}  // namespace sg
