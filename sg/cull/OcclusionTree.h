// OcclusionTree: the occluded space of one frame, grown from major occluders and queried with boxes.
//
// Every node holds a plane and an inside and an outside child; a child is a node or a leaf (visible,
// occluded). An occluder polygon adds a chain: one plane through the eye and each edge, then its cap
// (behind the occluder), ending in an occluded leaf. Inserting walks the tree, splits the polygon by
// the planes it straddles and drops the parts already occluded, so occluded regions never overlap. A box
// is tested the same way, split where a plane crosses it: it is occluded when every part ends in an
// occluded leaf, so one hidden behind two neighbouring occluders together is culled.
//
// Conservative by construction: a leaf is marked occluded only for the shadow of a real piece of an
// occluder, each chain's planes are moved inward by the margins below (rounding, the rasterizer's
// sub-pixel snapping, the depth buffer's resolution), and every doubtful classification goes the way
// that culls less. All geometry is eye-relative double precision.
#pragma once
#include "sg/core/Math.h"
#include "sg/cull/CullSettings.h"

#include <cstdint>
#include <vector>

namespace sg {

class Camera;

class OcclusionTree {
public:
    static constexpr int32_t kVisible = -1;   // leaf: nothing occluded here
    static constexpr int32_t kOccluded = -2;  // leaf: occluded space
    enum class Result : uint8_t {
        Visible,   // entirely outside the occluded space: nothing below needs testing
        Partial,   // partly occluded or undecided: children resume at `resume`
        Occluded,  // entirely inside
    };

    struct Options {
        OccluderCap cap = OccluderCap::FrontFaces;
        // Occluder parts nearer than this plane (eye-relative: n.p + d < 0) are clipped away when drawn,
        // so they do not occlude. hasNear false: no near plane.
        bool hasNear = false;
        Plane nearPlane{};
        double edgeMargin = 1e-9;  // radians: every shadow cone is narrowed by this angle
        double depthMargin = 0.0;  // K: every cap is moved away from the eye by K * distance^2
        // Two-level tree: 2^screenSplits screen regions (planes through the eye) above the occluders.
        int screenSplits = 0;
        glm::dmat3 viewToWorld{1.0};    // the camera's axes (looking down -Z)
        double tanX = 1.0, tanY = 1.0;  // half the field of view, as tangents
    };
    // Margins for a perspective camera: a 64th of a pixel, and 8 steps of a 24-bit depth buffer.
    static Options optionsFor(const Camera& cam, const OcclusionSettings& s);

    // Empties the tree for a new eye (world coordinates).
    void reset(const dvec3& eye, const Options& o);
    // Adds a box occluder (a box in local coordinates and an affine local-to-world matrix, or a world box
    // when toWorld is null). Returns false when nothing of it was added: hidden already, the eye inside
    // it, degenerate.
    bool insertBox(const Box& box, const dmat4* toWorld = nullptr);
    // Adds a convex planar polygon (world coordinates), seen from either side.
    bool insertPolygon(const dvec3* vertices, size_t count);

    // Tests the world box [eye + lo, eye + hi] (eye-relative corners) starting at node `resume` (root()
    // for a top-level bound). On Partial, `resume` becomes the node where tests of boxes inside this one
    // start; on Visible it becomes kVisible.
    Result testRelative(const dvec3& lo, const dvec3& hi, int32_t& resume);
    Result test(const Box& world, int32_t& resume);
    bool isOccluded(const Box& world);

    int32_t root() const { return root_; }
    bool empty() const { return root_ == kVisible; }  // nothing occluded
    size_t nodeCount() const { return nodes_.size(); }
    const dvec3& eye() const { return eye_; }
    uint64_t polygonSplits() const { return polySplits_; }
    uint64_t boxSplits() const { return boxSplits_; }

    // The outline of an axis-aligned box seen from the eye's region (per axis 0: below the box, 1: within
    // its extent, 2: above; not all 1): corner indices (bit 0: x max, bit 1: y max, bit 2: z max) in
    // order around the outline. Returns the count (4 or 6).
    static int silhouette(int rx, int ry, int rz, uint8_t out[6]);

private:
    enum class Kind : uint8_t { Edge, Cap, Split };  // Edge and Split planes pass through the eye
    struct Node {
        dvec3 n;
        double d;
        int32_t in, out;
        Kind kind;
    };
    struct Poly {  // a range of pool_: an outline, eye-relative
        uint32_t first, count;
    };
    struct Vertex {
        Vertex() {}  // left uninitialized: split() makes room first, then writes
        Vertex(const dvec3& q, bool c) : p(q), cut(c) {}
        dvec3 p;
        bool cut;  // the edge to the next vertex was made by a split (it lies on a plane above in the tree)
    };
    // What a chain needs of the occluder being inserted.
    struct Occ {
        Plane caps[3];
        int capCount = 0;
        const dvec3* extent = nullptr;  // points bounding the occluder, for cap classification
        int extentCount = 0;
    };

    int32_t newNode(const dvec3& n, double d, Kind k, int32_t in, int32_t out);
    void splitScreen(int32_t* slot, int level, double x0, double x1, double y0, double y1);
    bool insert(int32_t parent, bool inSide, Poly p, const Occ& o);
    bool chain(int32_t parent, bool inSide, Poly p, const Occ& o);
    void setSlot(int32_t parent, bool inSide, int32_t v);
    // Splits p by the plane (n, d) into the parts with s <= 0 and s >= 0 (appended to the pool).
    void split(Poly p, const dvec3& n, double d, Poly& in, Poly& out);
    // mag: a bound on |p|_1 over the polygon (scales the rounding allowance).
    bool occluded(int32_t node, Poly p, double mag);
    bool insertFaces(const dvec3 corners[8], const int region[3]);
    bool insertPlanar(const dvec3* v, size_t count);

    Options opt_;
    dvec3 eye_{0.0};
    double worldErr_ = 0.0;  // rounding of world coordinates near the eye, in metres
    int32_t root_ = kVisible;
    std::vector<Node> nodes_;
    std::vector<Vertex> pool_;
    uint64_t polySplits_ = 0, boxSplits_ = 0;
};

}  // namespace sg
