// Scene::Builder: writes a flat image from its graph, whole (a full build) or only along the paths marked dirty (a
// refit), with the images it holds (Instance prototypes', PagedLOD details').
// Its parts: ImageBuild.cpp (the passes: a full build's layout, a refit, a Switch's bits copied alone),
// ImageWrite.cpp (an entry written: the steps every kind shares, then a small handler per node kind),
// internal/ImageBounds.h (an entry's bound from its children's, and what its kind derives from them),
// NestedImages.cpp (prototypes' and paged details' images built or adopted). What runs once per entry is inline
// (here, in ImageBounds.h, or in the .cpp of the loop that calls it): the library is built with -fPIC, where a
// function that is not inline is called through the PLT and never inlined.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "sg/scene/Scene.h"

#include <algorithm>
#include <memory>
#include <unordered_set>
#include <utility>
#include <vector>

namespace sg {

struct Scene::Builder {
    Scene& scene;
    FlatImage& img;
    // Prototypes (re)built in this update in the table proto() fills: one set per table, as a prototype rebuilt in
    // one table (the scene's, a detail's) is still stale in another.
    std::unordered_set<const Node*>& builtProtos;
    uint32_t cursor = 0;
    bool collect = false;    // full builds list the nodes with update callbacks
    bool fresh = false;      // full build: tables are appended to; refit: rewritten at their index
    bool prototype = false;  // building an Instance prototype's image: its occluders are not used
    // Building a PagedLOD detail's image, or a prototype's inside one: not a rebuild of the scene's structure, and
    // the prototypes' images it places are the image's own (img.prototypes), not the scene's, so that the detail
    // can be built alone (buildDetailImage) and its prototypes' images die with it.
    bool detail = false;
    int conditional = 0;  // Switch, LOD, Billboard or masked nodes above: drawn or not per frame
    bool occludersWritten = false;
    // write(): the child written before the current one, and its entry (Occluder::shownWith).
    const Node* prevSibling = nullptr;
    uint32_t prevSiblingEntry = ~0u;
    // What an occluder (or a PagedLOD) below the path being written needs to be drawn, for the pass to check per
    // frame: the Switch children on it (their bytes in switchOn) on, the masked nodes on it (their entries,
    // kMaskCondition set) seen by the traversal mask, the PagedLODs on it (their entries, kPagedCondition set) showing
    // their coarse children. `described` counts the conditional nodes so described: an occluder below an LOD or
    // Billboard (`conditional` counts those too) is not used. Initialised here as the builders are made with
    // their first three members only (Builder{scene, img, built}).
    std::vector<uint32_t> pathConds{};
    int described = 0;

    // Pushes the conditions of going from n (entry i) to its child k; returns how many it pushed.
    int enter(uint32_t i, const Node* n, size_t k) {
        const NodeKind kind = n->kind();
        if (kind == NodeKind::LOD || kind == NodeKind::Billboard) return 0;
        int pushed = 0;
        if (kind == NodeKind::Switch) pathConds.push_back(img.aux[i] + uint32_t(k)), pushed++;
        if (kind == NodeKind::PagedLOD) pathConds.push_back(FlatImage::kPagedCondition | i), pushed++;
        if (n->nodeMask() != 0xffffffffu) pathConds.push_back(FlatImage::kMaskCondition | i), pushed++;
        described += isConditional(n);
        return pushed;
    }
    void leave(const Node* n, int pushed) {
        const NodeKind kind = n->kind();
        if (kind == NodeKind::LOD || kind == NodeKind::Billboard) return;
        pathConds.resize(pathConds.size() - size_t(pushed));
        described -= isConditional(n);
    }
    // pathConds stored for an entry that listed `count` of them from `first` before (a full build: none): kept where
    // they are when the same, else appended (a node masked since makes them differ: the old list is left until the
    // next full build).
    std::pair<uint32_t, uint32_t> storeConds(uint32_t first, uint32_t count, bool had) {
        if (had && count == pathConds.size() &&
            std::equal(pathConds.begin(), pathConds.end(), img.occluderSwitchBits.begin() + first))
            return {first, count};
        const auto at = uint32_t(img.occluderSwitchBits.size());
        img.occluderSwitchBits.insert(img.occluderSwitchBits.end(), pathConds.begin(), pathConds.end());
        return {at, uint32_t(pathConds.size())};
    }
    bool underPaged() const {
        return std::any_of(pathConds.begin(), pathConds.end(), [](uint32_t c) {
            return (c & (FlatImage::kPagedCondition | FlatImage::kMaskCondition)) == FlatImage::kPagedCondition;
        });
    }

    static bool isConditional(const Node* n) {
        const NodeKind k = n->kind();
        return k == NodeKind::Switch || k == NodeKind::LOD || k == NodeKind::PagedLOD || k == NodeKind::Billboard ||
               n->nodeMask() != 0xffffffffu;
    }
    // A PagedLOD's attached detail, which is not among its entry's children (it has an image of its own).
    static const Node* detailOf(const Node* n) {
        return n->kind() == NodeKind::PagedLOD ? static_cast<const PagedLOD*>(n)->detail() : nullptr;
    }
    // Switch n's on bits into its entry i's slot (the children are the same since its entry was written).
    void switchBits(uint32_t i, const Node* n) {
        const auto* sw = static_cast<const Switch*>(n);
        uint8_t* on = img.switchOn.data() + img.aux[i];
        for (size_t k = 0, c = n->numChildren(); k < c; ++k) on[k] = sw->isOn(k);
    }

    // Copies the parameters the cull reads into the kind's table (appended on a full build).
    // A refit rewrites the entry's slot in place, unless the slot is in another table now (a transform
    // that stopped being a translation): then it takes a new one at the end.
    template <class T>
    uint32_t slot(std::vector<T>& v, uint32_t i, const T& value, bool sameTable = true) {
        if (fresh || !sameTable) {
            v.push_back(value);
            return uint32_t(v.size() - 1);
        }
        v[img.aux[i]] = value;
        return img.aux[i];
    }
    // A matrix in img.matrices for the entry that held slot `had` (kNone: none, or a full build): rewritten in
    // place, else appended.
    uint32_t matrixSlot(uint32_t had, const dmat4& m) {
        if (!fresh && had != FlatImage::kNone) {
            img.matrices[had] = m;
            return had;
        }
        img.matrices.push_back(m);
        return uint32_t(img.matrices.size() - 1);
    }

    // The passes (ImageBuild.cpp).
    struct Counts {
        uint32_t entries = 0, xforms = 0, lods = 0;
    };
    static void count(const Node* n, Counts& c);
    static dvec3 pickOrigin(const Node* n);
    void full(Node* root, const dmat4& frame = dmat4(1.0));
    void updateExtent();
    void refit(uint32_t i, Node* n, const dmat4& m);
    void occluderChunks();
    void choices(uint32_t i, Node* n);
    static void clear(Node* n);

    // An entry written (ImageWrite.cpp).
    void write(Node* n, const dmat4& m);
    void setMasked(uint32_t i, const Node* n);
    void setFeatured(uint32_t i, const Node* n);
    void params(uint32_t i, Node* n);
    void writeTransform(uint32_t i, Node* n);
    void writeGeometry(uint32_t i, Node* n);
    void writeLod(uint32_t i, Node* n);
    void writePaged(uint32_t i, Node* n);
    void writeInstance(uint32_t i, Node* n);
    void writeSwitch(uint32_t i, Node* n);
    void occluder(uint32_t i, const Node* n, const dmat4& m);
    const FlatImage& proto(Node* p);

    // A posed Geometry's entry (ImagePoses.cpp).
    void posed(uint32_t i, Geometry* g, const dmat4& m);
    void dropPose(uint32_t i);
    void noteSkinned(Geometry* g, const Pose* had);

    // Bounds (internal/ImageBounds.h).
    static constexpr uint32_t kWideChildren = 16, kWideEntries = 1024;
    void leafBound(uint32_t i, const Box& local, bool valid, const dmat4& m);
    void boundFromChildren(uint32_t i);
    void expandBound(uint32_t i, const Box& add, double r);
    static double localRadius(const Node* n, const dmat4& m);
    void billboard(uint32_t i, Node* n, const dmat4& m);
    void bsp(uint32_t i, Node* n, const dmat4& m);
    void lodCenter(uint32_t i, const LOD* l, const dmat4& m);
    void paged(uint32_t i, const PagedLOD* p, const dmat4& m, bool rebuild);
    void wide(uint32_t i, Node* n);

    // Images inside the image (NestedImages.cpp).
    void buildProto(std::shared_ptr<FlatImage>& slot, Node* p);
    void detailImage(const PagedLOD* p, Node* d, const dmat4& m, FlatImage::Paged& pg, bool rebuild);
    bool adopt(const PagedLOD* p, const Node* d, const dmat4& m, FlatImage::Paged& pg);
    void renumber(FlatImage& image);
};

}  // namespace sg
