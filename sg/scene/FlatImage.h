// FlatImage: the pre-order, structure-of-arrays image of a graph that the cull walks instead of pointers.
#pragma once
#include "sg/core/Assert.h"
#include "sg/core/Features.h"
#include "sg/core/Material.h"
#include "sg/core/Math.h"
#include "sg/core/Mesh.h"
#include "sg/core/Node.h"
#include "sg/core/Pose.h"

#include <cstdint>
#include <map>
#include <memory>
#include <unordered_map>
#include <vector>

namespace sg {

// One entry per node per path (a shared child appears once under each parent; an Instance's prototype
// has an image of its own). Bounds are world-space boxes and spheres sharing one centre, stored in float
// relative to `origin`, each rounded outward by its own rounding error (see sg/core/Math.h, eps).
struct FlatImage {
    enum Flag : uint8_t {
        kInvalid = 1,   // non-finite bound: never culled, always drawn, counted
        kEmpty = 2,     // nothing below to draw
        kMasked = 4,    // node mask is not all ones: the cull reads it
        kNoTest = 8,    // below a Billboard: orientation changes per frame, the billboard's own test covers it
        kGeneral = 16,  // a Transform whose matrix is not a translation
        kFeature = 32,  // the node is a feature (Node::setFeatures): the cull notes it on the draw items below
        kPosed = 64,    // a skinned or morphed Geometry: its pose is in `posed` (poseOf())
        kSlowPath = kInvalid | kEmpty | kMasked | kNoTest | kFeature | kPosed,  // the cull's fast paths skip these
    };

    dvec3 origin{0.0};
    double extent = 0.0;  // max |centre| + radius: scales the float slack of the planes

    // Columns (4 bytes each per entry unless said): centre, sphere radius, box half extents.
    std::vector<float> cx, cy, cz, r, ex, ey, ez;
    std::vector<uint32_t> end;   // one past the last entry of this entry's subtree (skip index)
    std::vector<NodeKind> kind;  // 1 byte
    std::vector<uint8_t> flags;  // 1 byte (kGeneral is set once, at the transform's write; not a cull flag)
    std::vector<uint32_t> aux;   // index into the table of its kind (see below)

    // What the cull reads of the nodes, copied here at Scene::update(): it never waits on a node, and the
    // application may change the graph (turn switches, move transforms, set masks) while a cull reads the image
    // of the last update. Transform entries: aux indexes `translations`, or with kGeneral set, `matrices`.
    struct Lod {
        float cx, cy, cz;     // the centre (user's, or the bound's), in image coordinates like the bounds
        uint32_t firstRange;  // into ranges, one per child
        float fade;      // LOD::transition(): the width of the dissolve band at range ends, 0 for none; kScreenError:
                         // the node's scale (image units per unit of its geometric error)
        uint8_t mode;    // LOD::Mode, or kScreenError (a PagedLOD refined by screen-space error)
        bool hasErrors;  // LOD::hasErrors(): the levels' errors are known (Range::error, 0 included)
        float reach;     // kScreenError: the radius of the tile's sphere about the centre, in image units
    };
    // Lod::mode of a PagedLOD refined by screen-space error: its value is the view's pixels per world unit at the
    // eye's distance to the sphere (centre, reach), its range [maxPixels / geometricError, inf).
    static constexpr uint8_t kScreenError = 2;
    struct Range {
        float min, max;
        float error;  // the child's geometric error (LOD::error), 0 when not given
    };
    struct Draw {
        const Mesh* mesh;
        const Material* material;
        uint32_t state;  // dense index of the mesh/material pair in the scene: the draw list sorts by it
    };
    // Groups with many children and a large subtree (a city's root over its tiles) keep their children's
    // spheres side by side as well, so that the cull classifies them in one flat pass instead of reading
    // bounds spread over the whole image. A Group entry's aux is its index here plus one (0: none).
    struct Wide {
        uint32_t first, count;  // into wideEntry and the wide columns
    };
    std::vector<Wide> wides;
    std::vector<uint32_t> wideEntry;
    std::vector<float> wcx, wcy, wcz, wr;

    // Draws and LOD range sets are shared by every entry with the same values (a city has a few dozen
    // mesh/material pairs and one set of ranges): found through these keys while building.
    std::map<std::pair<const Mesh*, const Material*>, uint32_t> drawIndex;
    std::map<std::vector<float>, uint32_t> rangeIndex;

    std::vector<dvec3> translations;
    std::vector<dmat4> matrices;  // general Transforms' and Instances' matrices
    // Switch entries: aux indexes `switchOn`, one byte per child (Switch::isOn), rewritten by an update after
    // a switch turned (Node::choiceChanged()) without a refit.
    std::vector<uint8_t> switchOn;
    // Billboard and BspGroup entries: aux indexes their node. The cull reads the billboard's axis and the BSP
    // tree there: both are set when the graph is built (the BSP by Scene::update()), not per frame.
    std::vector<Node*> nodes;
    // Entries whose node mask is not all ones, sorted, with the mask as of the last update; maskOf(i) finds entry
    // i's mask there (all ones when it is not listed, never for a kMasked entry).
    std::vector<std::pair<uint32_t, uint32_t>> masked;
    uint32_t maskOf(uint32_t i) const;
    // Entries whose node is a feature (kFeature), sorted, with its feature as of the last update (held: the
    // application may set another while a cull reads this image); featureOf(i) finds entry i's.
    struct FeatureRef {
        ref_ptr<const MeshFeatures> features;
        uint32_t index = 0;
    };
    std::vector<std::pair<uint32_t, FeatureRef>> featured;
    const FeatureRef* featureOf(uint32_t i) const;
    // Posed Geometry entries (kPosed), sorted, with the pose the last update made (held: the draw of a frame in flight
    // keeps its own while the next update makes another); poseOf(i) finds entry i's. A skinned entry's bound is its
    // pose's world box, wherever the Geometry sits.
    std::vector<std::pair<uint32_t, ref_ptr<const Pose>>> posed;
    const Pose* poseOf(uint32_t i) const;
    std::vector<Lod> lods;
    std::vector<Range> ranges;
    // PagedLOD entries (their aux indexes `paged`): the LOD value's centre and mode as an LOD's (lod.firstRange
    // unused), the range where the detail is wanted, and the node, which the cull marks needed. The entry's
    // children here are the coarse ones; an attached detail has an image of its own, in this image's frame, so
    // that attaching or detaching it rewrites that image and this entry, never this image's structure.
    struct Paged {
        Lod lod;
        float min, max;
        Node* node;                         // a PagedLOD
        std::shared_ptr<FlatImage> detail;  // null when no detail is attached
        dmat4 frame{1.0};                   // the frame its detail's image is built in (posted with requests)
        // For the occlusion pass, which takes the occluders of the details drawn: whether the walk reaches this entry
        // whenever its path's conditions hold (no LOD, Billboard or Instance prototype above it, not masked itself),
        // and those conditions, listed in occluderSwitchBits as an occluder's are.
        bool plainPath = false;
        uint32_t condFirst = 0, condCount = 0;
        uint32_t entry = 0;  // its entry in this image
    };
    std::vector<Paged> paged;
    std::vector<Draw> draws;
    // Instance entries (their aux indexes `placements`): what the cull needs of the node, copied so that it
    // reads neither the node nor a table of images for each of a tile's thousands of placements.
    struct Placement {
        const Node* node;        // the Instance
        const FlatImage* proto;  // its prototype's image (held by this image or the Scene); null: none
        dvec3 translation;       // the placement, when `matrix` is kNone
        uint32_t matrix;         // the node's matrix in `matrices` when it is not a translation
    };
    static constexpr uint32_t kNone = ~0u;
    std::vector<Placement> placements;

    // The images of the Instance prototypes placed in this image, by prototype, when it owns them: a paged
    // detail's image (and a prototype's image inside one) is built with them, on a loader thread too, and frees
    // them with it, so that a detail evicted leaves no image keyed by its freed nodes. Empty in the scene's own
    // image and its prototypes' images: the Scene keeps those (Scene::prototypeImage()).
    std::unordered_map<const Node*, std::shared_ptr<FlatImage>> prototypes;

    // Occluder entries (their aux indexes `occluders`), for the occlusion pass. Its shape is read from the node
    // (Occluder::box(), polygon()): set when the graph is built, not per frame. Only occluders that are
    // drawn whatever the frame, or while the Switch children, masked nodes and PagedLODs on their path let them be
    // drawn, are active: not below an LOD or Billboard, not masked themselves, not inside an Instance's prototype.
    // A paged detail's image lists its own (the pass takes them while the detail is drawn).
    struct OccluderRef {
        const Node* node;  // an Occluder
        uint32_t entry;
        uint32_t matrix;  // ~0u: the frame is the translation `shift`; else its index in occluderMatrices
        dvec3 shift;
        bool active;
        // A generated occluder's conditions (Occluder::eyeOutside, openings, oneSided, shownWith, belowSurface): the
        // pass checks them per frame. `lod`: the entry of the LOD it is shown with (kNone: none; with shownWith set, it
        // is not used).
        bool conditional = false;
        uint32_t lod = ~0u;
        // What its path needs to be drawn (listed in occluderSwitchBits from switchFirst): each Switch child's byte in
        // switchOn on, each masked node's entry (kMaskCondition set) seen by the traversal mask, each PagedLOD's
        // entry (kPagedCondition set) showing its coarse children, not its detail.
        uint32_t switchFirst = 0, switchCount = 0;
        bool underPaged = false;  // a PagedLOD's coarse children hold it: drawn only until its detail is
    };
    static constexpr uint32_t kOccluderChunk = 32;
    std::vector<OccluderRef> occluders;
    std::vector<dmat4> occluderMatrices;
    std::vector<uint32_t> occluderSwitchBits;
    static constexpr uint32_t kMaskCondition = 0x80000000u, kPagedCondition = 0x40000000u;
    std::vector<Box> occluderChunks;  // world box of each run of kOccluderChunk active occluders

    size_t size() const { return end.size(); }
    void resize(size_t n);
    size_t bytes() const;

    dvec3 center(size_t i) const {
        SG_ASSERT(i < size(), "FlatImage::center(): entry past the image");
        return origin + dvec3(cx[i], cy[i], cz[i]);
    }
    Box box(size_t i) const;
    // Stores a world box and sphere radius at i, rounding outward.
    void setBound(size_t i, const Box& b, double radius);
    void setInvalid(size_t i);
};

}  // namespace sg
