// Base of every scene-graph node: reference count, parents, node mask, name, update callback, dirty bits.
#pragma once
#include "sg/core/Ref.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sg {

class MeshFeatures;  // sg/core/Features.h

class NodeVisitor;

enum class NodeKind : uint8_t {
    Group,
    Transform,
    Geometry,
    LOD,
    Switch,
    Billboard,
    Instance,
    BspGroup,
    Occluder,
    PagedLOD
};
const char* kindName(NodeKind k);
// The size of a node object of this kind (its children, parents and name held apart are not counted).
size_t nodeBytes(NodeKind k);

struct FrameInfo {
    uint64_t frame = 0;
    double time = 0.0;
};

class Node;
using UpdateCallback = std::function<void(Node&, const FrameInfo&)>;

class Node : public Referenced {
public:
    // State bits in one byte: four dirty bits (the update pass follows only marked paths) and two flags.
    enum : uint8_t {
        kDirtyBound = 1,      // this node's own bound-affecting data changed (matrix, mesh, shape)
        kDirtyBelow = 2,      // something below changed
        kDirtyStructure = 4,  // children were added or removed here or below
        kHasMask = 8,         // node mask is not all ones (the cull then reads it)
        kHasExtras = 16,      // name, callback or more parents are kept in the node's Extras block
        kDirtyChoice = 32,    // a choice the image copies without a refit (Switch bits) changed here or below
    };

    NodeKind kind() const noexcept { return kind_; }
    const char* kindName() const { return sg::kindName(kind_); }

    // Node masks select what cull, pick and collision see (node seen when mask & traversal mask != 0).
    uint32_t nodeMask() const noexcept { return mask_; }
    void setNodeMask(uint32_t m);

    const std::string& name() const;
    void setName(std::string name);
    // Which feature this node is, for the nodes a file or program makes one per feature (an instance of
    // EXT_instance_features or of an i3dm, a building, a machine, a map's region): sets of
    // FeatureIdSet::Source::Instance shared by such nodes, and this node's index in their ids. A pick reads them
    // on the hit's path (sg/intersect/HitFeatures.h). Kept with the name: plain nodes pay nothing.
    void setFeatures(ref_ptr<const MeshFeatures> features, uint32_t index);
    const MeshFeatures* features() const;
    uint32_t featureIndex() const;
    // "Transform 'crane'" or "Transform" when unnamed: for error messages.
    std::string describe() const;

    void setUpdateCallback(UpdateCallback cb);
    const UpdateCallback* updateCallback() const;

    size_t numParents() const noexcept;
    Node* parent(size_t i) const noexcept;

    // Generic child access; leaves have none.
    virtual size_t numChildren() const noexcept { return 0; }
    virtual Node* child(size_t) const noexcept { return nullptr; }

    virtual void accept(NodeVisitor& v);

    // The marks that make the flat image's structure or bounds stale (kDirtyChoice is not one: the update copies
    // the new switch bits into the image without a refit).
    uint8_t dirtyBits() const noexcept { return state_ & (kDirtyBound | kDirtyBelow | kDirtyStructure); }
    bool choiceChanged() const noexcept { return state_ & kDirtyChoice; }
    void clearDirty() noexcept { state_ &= kHasMask | kHasExtras; }
    // Marks this node and propagates "below" marks to every ancestor (kDirtyChoice alone propagates as
    // itself: Scene::update() then moves version() without a refit).
    void markDirty(uint8_t bits);

    // True when `n` is this node or one of its ancestors (through any parent).
    bool hasAncestorOrSelf(const Node* n) const;

    Node(const Node&) = delete;  // a node owns its Extras block and is shared through ref_ptr, never copied
    Node& operator=(const Node&) = delete;

protected:
    explicit Node(NodeKind k) : kind_(k) {}
    ~Node() override;
    void addParent(Node* p);
    void removeParent(Node* p);
    friend class Group;
    friend class Instance;

private:
    // Rare data (a name, an update callback, parents after the first) lives in a block the node owns.
    // Until a node needs one, the same pointer slot holds its only parent (kHasExtras tells which):
    // millions of plain nodes pay nothing for it, and nodes share no state, so that graphs built on
    // different threads do not race.
    struct Extras;  // defined in Node.cpp
    Extras& extras();
    const Extras* findExtras() const noexcept { return state_ & kHasExtras ? extras_ : nullptr; }
    Node* firstParent() const noexcept;
    void setFirstParent(Node* p) noexcept;

    // Order matters for size: the mask fills the tail of Referenced, and derived nodes fill this
    // class's tail (a Group is 40 bytes, a Transform 72).
    uint32_t mask_ = 0xffffffffu;
    union {
        Node* firstParent_ = nullptr;  // without kHasExtras
        Extras* extras_;               // with kHasExtras (it keeps the first parent)
    };
    NodeKind kind_;
    uint8_t state_ = kDirtyBound | kDirtyStructure;  // the dirty bits and the kHas* flags above
};

}  // namespace sg
