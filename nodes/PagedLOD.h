// PagedLOD: a node whose detailed child lives in a file, loaded by a pager when needed and unloaded when left;
// its own children are the coarse level, drawn until the detail is attached (OpenSceneGraph's PagedLOD).
#pragma once
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "sg/core/Math.h"

#include <atomic>
#include <limits>
#include <string>

namespace sg {

class PagedLOD : public Group {
public:
    enum class State : uint8_t {
        Unloaded,   // no detail; the cull asks for it when needed
        Requested,  // queued or being loaded
        Loaded,     // the detail is attached (the last child)
        Failed,     // the load failed: error() says why; the cull asks again from retryTime() on (a Range node),
                    // Pager::load() at once
    };
    // What makes the detail wanted.
    enum class Trigger : uint8_t {
        Range,    // the LOD value (distance, or pixel size) in range(): loaded when seen there, unloaded when left
        Command,  // Pager::load() and Pager::release() only (a map's enter and back); shown whenever attached
    };
    using Mode = LOD::Mode;

    PagedLOD() : Group(NodeKind::PagedLOD) {}

    // The file the detail is loaded from and, for a file that holds many details (a tileset's tiles), which of
    // them: `part` is the loader's own index, handed to the load function as it is (sg::PageSource), so that
    // nothing is encoded into the name and parsed back. Throws std::invalid_argument for an empty name and
    // std::logic_error while the detail is requested or attached (release it first); a failed node becomes Unloaded.
    static constexpr uint32_t kWholeFile = 0xffffffffu;
    void setFile(std::string file, uint32_t part = kWholeFile);
    const std::string& file() const { return file_; }
    uint32_t part() const { return part_; }

    // The detail is wanted while min <= value < max (value: the eye's distance to center(), or the bound's
    // size in pixels, as LOD::Mode); outside it the coarse children are drawn. Throws std::invalid_argument
    // when min > max, either is NaN or min is negative.
    void setRange(float min, float max);
    float rangeMin() const { return min_; }
    float rangeMax() const { return max_; }
    void setMode(Mode m) {
        mode_ = m;
        screenError_ = false;
        markDirty(kDirtyBound);  // the image keeps a copy of the mode and range
    }
    Mode mode() const { return mode_; }
    // 3D Tiles' refinement instead of a range: the detail is wanted while `geometricError` (world units, at the
    // node's scale), seen at the eye's distance to the sphere (center(), radius()), projects to more than
    // `maxPixels` pixels of the view (the screen-space error; 0 inside the sphere, so always wanted there). The
    // distance to the sphere, not to the tile's box, refines a little earlier than a box would: never later.
    // Throws std::invalid_argument unless both are finite and geometricError >= 0, maxPixels > 0.
    void setScreenSpaceError(double geometricError, double maxPixels);
    bool screenSpaceError() const { return screenError_; }
    double geometricError() const { return geometricError_; }
    double maxScreenPixels() const { return maxPixels_; }
    void setTrigger(Trigger t) { trigger_.store(t, std::memory_order_relaxed); }
    Trigger trigger() const { return trigger_.load(std::memory_order_relaxed); }

    // Centre in the node's frame; by default the centre of its bound.
    void setCenter(const dvec3& c);
    const dvec3& center() const { return center_; }
    bool userCenter() const { return userCenter_; }
    // The space the detail takes, known before it is loaded: a sphere of this radius at center() is part of the
    // bound, so that a node whose coarse level is small or empty is still seen where its detail will be.
    // 0 (the default): the children's bound only. Throws std::invalid_argument for a negative or non-finite radius.
    void setRadius(double r);
    double radius() const { return radius_; }

    // The attached detail (the last child), or null.
    Node* detail() const noexcept { return detail_; }
    // Index of the detail among the children, or numChildren() when none is attached.
    size_t detailIndex() const noexcept { return detail_ ? indexOf(detail_) : numChildren(); }
    State state() const noexcept { return state_.load(std::memory_order_relaxed); }
    // Why the last load failed (names the file and the reason); empty unless Failed.
    const std::string& error() const { return error_; }
    // Loads failed in a row (0 once a detail is attached or the file changes), and the FrameInfo::time from which
    // the cull asks for a failed Range node again (infinity: never; the pager's back-off sets it).
    uint32_t failures() const noexcept { return failures_; }
    double retryTime() const noexcept { return retryTime_.load(std::memory_order_relaxed); }
    // Mesh and texture bytes of the attached detail, as the pager measured them.
    size_t detailBytes() const noexcept { return detailBytes_; }

    // The count of the Scene::update() whose cull last found the detail needed (0: never). Views culled on
    // several threads mark it together: true for the first mark of an update.
    uint64_t lastNeeded() const noexcept { return lastNeeded_.load(std::memory_order_relaxed); }
    bool markNeeded(uint64_t update) noexcept {
        return lastNeeded_.exchange(update, std::memory_order_relaxed) != update;
    }
    // How much the detail was needed when last marked (CullTraversal::pagedLod(): bigger first), set by the cull
    // that marked it first in an update; the pager orders its queue by it.
    float needPriority() const noexcept { return needPriority_.load(std::memory_order_relaxed); }
    void setNeedPriority(float p) noexcept { needPriority_.store(p, std::memory_order_relaxed); }

    // The pager's side (on the application thread, outside update and cull): the state, attaching the
    // loaded detail as the last child (Loaded), detaching it (Unloaded, the detail handed back).
    void setRequested();
    // setFailed counts a failure; without retryTime the cull does not ask again.
    void setFailed(std::string error);
    void setFailed(std::string error, double retryTime);
    // Throws std::logic_error when a detail is attached already; std::invalid_argument for a null detail.
    void attachDetail(ref_ptr<Node> detail, size_t bytes);
    ref_ptr<Node> detachDetail();
    // Back to Unloaded from Requested (a request dropped before its load).
    void setUnloaded();

    void accept(NodeVisitor& v) override;

protected:
    void childRemoved(size_t i) override;
    // Attaching or detaching the detail rewrites this node's entry only (the detail has an image of its own).
    uint8_t childChangeMarks(const Node* child) const override {
        return child == detail_ ? uint8_t(kDirtyBound) : Group::childChangeMarks(child);
    }

private:
    std::string file_, error_;
    uint32_t part_ = kWholeFile;
    dvec3 center_{0.0};
    double radius_ = 0.0;
    Node* detail_ = nullptr;  // one of the children (which hold the reference)
    size_t detailBytes_ = 0;
    // The cull reads the trigger, the state and the retry time (to post a request) while the application thread
    // may set them (the pager's update, beside a cull of the last update's image): atomic. Relaxed, as the cull's
    // reading is only a hint: the pager checks the state again on its own thread before acting on a request, so a
    // stale value at worst posts a request it drops or posts one an update later.
    std::atomic<double> retryTime_{std::numeric_limits<double>::infinity()};
    uint32_t failures_ = 0;
    std::atomic<uint64_t> lastNeeded_{0};
    double geometricError_ = 0.0, maxPixels_ = 0.0;
    std::atomic<float> needPriority_{0.0f};
    float min_ = 0.0f, max_ = std::numeric_limits<float>::infinity();
    Mode mode_ = Mode::Distance;
    std::atomic<Trigger> trigger_{Trigger::Range};
    std::atomic<State> state_{State::Unloaded};
    bool userCenter_ = false;
    bool screenError_ = false;
};

}  // namespace sg
