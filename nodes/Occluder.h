// Occluder: marks a box or a convex polygon as a major occluder (designated at modelling time, or generated from the
// geometry: sg/build/GeneratedOccluders.h).
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Node.h"

#include <memory>
#include <vector>

namespace sg {

// The height field a terrain's occluders lie below (Occluder::setBelowSurface), in their frame: its xy rectangle,
// split into a grid of cells (the terrain's tiles), and over each cell the highest the drawn surface reaches at any
// of its levels. Plain data, shared by every occluder of one terrain.
struct OccluderSurface {
    dvec2 min{0.0}, max{0.0};  // the rectangle the surface covers with no gap (inside its drawn edges)
    int cellsX = 0, cellsY = 0;
    std::vector<double> highest;  // row-major, cellsX * cellsY: above every drawn vertex over the cell
};

class Occluder : public Node {
public:
    enum class Shape : uint8_t { Box, Polygon };
    Occluder() : Node(NodeKind::Occluder) {}
    // Throws std::invalid_argument for an empty or non-finite box.
    void setBox(const Box& b);
    // Throws std::invalid_argument for fewer than 3 vertices, non-finite ones, or a non-planar / non-convex polygon.
    void setPolygon(std::vector<dvec3> vertices);
    Shape shape() const { return shape_; }
    const Box& box() const { return box_; }  // for a polygon: its bounding box
    const std::vector<dvec3>& polygon() const { return polygon_; }

    // What a generated occluder carries (sg::generateOccluders); an authored one has none of it.
    // Made by generateOccluders (removeOccluders(root, true) takes these away, and only these).
    void setGenerated(bool g) { generated_ = g; }
    bool generated() const { return generated_; }
    // Used only while the eye is outside this box, in the occluder's frame: a box inside a closed mesh stands behind
    // its surface only for an eye outside the solid, and outside the mesh's bound is surely outside. Empty: anywhere.
    // Throws std::invalid_argument for a non-finite box.
    void setEyeOutside(const Box& b);
    const Box& eyeOutside() const { return eyeOutside_; }
    // A box inside an open mesh's solid as closed by caps over its openings (MeshOccluders::cappedBoxes): used only
    // while the eye, in the occluder's frame, is on the positive side of every plane, each of which has the box on
    // that side and its cap on the other (a sight line from there to the box meets no cap). Empty: anywhere.
    // Throws std::invalid_argument for a plane that is not finite or whose normal is not of unit length.
    void setOpenings(std::vector<Plane> planes);
    const std::vector<Plane>& openings() const { return openings_; }
    // Used only while `lod`, the sibling before it under the same parent (other occluders between them), shows one of
    // its levels with no fade to nothing (the shape lies inside every level); null: always. Not owned: the pass finds
    // the LOD by its place, and an occluder placed otherwise is not used.
    void setShownWith(const Node* lod) {
        shownWith_ = lod;
        markDirty(kDirtyBound);
    }
    const Node* shownWith() const { return shownWith_; }
    // A polygon on a single-sided surface (back faces not drawn): used only while the eye is on its front side, where
    // it turns counter-clockwise.
    void setOneSided(bool s) {
        oneSided_ = s;
        markDirty(kDirtyBound);  // the image notes which occluders carry conditions
    }
    bool oneSided() const { return oneSided_; }
    // A box below a height field's surface (sg::buildTerrain's occluders): used only while the eye, in the occluder's
    // frame, is over the surface's rectangle and higher than every point of the surface within the near plane's reach
    // by more than that reach (the argument is at conditionsHold in sg/cull/OcclusionPass.cpp). Null: anywhere.
    // Throws std::invalid_argument for a surface with no cells, a `highest` of another size, a NaN among them, or a
    // rectangle that is empty or not finite.
    void setBelowSurface(std::shared_ptr<const OccluderSurface> s);
    const OccluderSurface* belowSurface() const { return belowSurface_.get(); }

    void accept(NodeVisitor& v) override;

private:
    Box box_;
    std::vector<dvec3> polygon_;
    Shape shape_ = Shape::Box;
    Box eyeOutside_;
    std::vector<Plane> openings_;
    const Node* shownWith_ = nullptr;
    std::shared_ptr<const OccluderSurface> belowSurface_;
    bool generated_ = false, oneSided_ = false;
};

}  // namespace sg
