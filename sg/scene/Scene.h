// Scene: a root node with its flat image, kept current by the update pass (app callbacks, then an
// incremental refit of only the paths marked dirty).
#pragma once
#include "sg/core/Node.h"
#include "sg/scene/FlatImage.h"
#include "sg/scene/PageRequests.h"

#include <map>
#include <memory>
#include <unordered_map>

namespace sg {

class Geometry;
class Sequence;

struct UpdateStats {
    uint64_t callbacksRun = 0;
    uint64_t fullRebuilds = 0;
    uint64_t entriesWritten = 0;  // entries whose bound was recomputed this update
    double ms = 0.0;
};

class Scene {
public:
    // Throws std::invalid_argument for a null root.
    explicit Scene(ref_ptr<Node> root);
    ~Scene();
    Node* root() const { return root_.get(); }

    // Turns the Sequences to the frame's time, runs update callbacks, then brings the image up to date. An
    // unchanged scene costs one flag check (plus the callbacks and Sequences it has).
    void update(const FrameInfo& frame = {});

    const FlatImage& image() const { return main_; }
    // The image of an Instance's prototype placed outside paged details (built once however often it is placed);
    // null if unknown.
    const FlatImage* prototypeImage(const Node* prototype) const;
    // The image of the prototype of an Instance entry of `placedIn` (any image a walk meets: the scene's, a paged
    // detail's, a prototype's): that image's own (a paged detail's image owns its prototypes' images,
    // FlatImage::prototypes), else the scene's; null if unknown.
    const FlatImage* prototypeImage(const FlatImage& placedIn, const Node* prototype) const;
    const UpdateStats& lastUpdate() const { return stats_; }
    // Counts full rebuilds of the image: state kept per image entry (LOD hysteresis) is stale when it moves.
    uint64_t structureVersion() const { return structureVersion_; }
    // Counts updates that changed the image at all (bounds, frames, meshes, structure) or turned a Switch:
    // what is derived from the scene stays valid while this stays the same.
    uint64_t version() const { return version_; }
    size_t bytes() const;

    // Counts update() calls: the cull marks paged nodes needed with it (PagedLOD::lastNeeded()).
    uint64_t updateCount() const { return updates_; }
    // The frame given to the last update().
    const FrameInfo& frame() const { return frame_; }
    // Where the cull posts the paged nodes it needs loaded (PagedLOD), for a pager to take; safe to post to
    // from several cull threads at once.
    PageRequests& pageRequests() const { return requests_; }

    // A paged detail's image built ahead, off the frame thread (a pager's loader thread, after the load), in
    // `frame` (the frame posted with the node's request): what the update would build when the detail is
    // attached, with the images of the Instances' prototypes inside it (FlatImage::prototypes). Touches no scene;
    // any thread may call it on a graph no other thread sees.
    static std::shared_ptr<FlatImage> buildDetailImage(Node& detail, const dmat4& frame);
    // Hands such an image over with the detail just attached to `paged` (the application thread, before the
    // next update): the update takes it instead of building one, if the detail and frame are still those;
    // else it is dropped at that update.
    void offerDetailImage(const Node* paged, const Node* detail, const dmat4& frame, std::shared_ptr<FlatImage> image);

private:
    struct Builder;
    void refresh();         // brings the image up to date with the dirty marks
    void markMovedSkins();  // marks the skinned Geometries whose joints moved (ImagePoses.cpp)
    ref_ptr<Node> root_;
    FlatImage main_;
    // The prototypes' images of the Instances outside paged details (details' images own theirs); emptied by a
    // full rebuild. Shared pointers as FlatImage::prototypes, so that the update fills either through one path.
    std::unordered_map<const Node*, std::shared_ptr<FlatImage>> protos_;
    std::vector<Node*> callbacks_;
    // The skinned Geometries of the scene's image and its prototypes' (found by the full build, as callbacks are):
    // each update re-poses those whose joints moved.
    std::vector<Geometry*> skinned_;
    std::vector<Sequence*> sequences_;  // advanced to the frame's time before the callbacks
    std::map<std::pair<const Mesh*, const Material*>, uint32_t> states_;  // draw state indices
    UpdateStats stats_;
    uint64_t structureVersion_ = 0;
    uint64_t version_ = 0;
    uint64_t updates_ = 0;
    FrameInfo frame_;
    mutable PageRequests requests_;
    struct Offer {
        const Node* detail;
        dmat4 frame;
        std::shared_ptr<FlatImage> image;
    };
    std::unordered_map<const Node*, Offer> offers_;  // by PagedLOD (offerDetailImage)
};

}  // namespace sg
