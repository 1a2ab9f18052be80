// Occluder: marks a box or a convex polygon as a major occluder (designated at modelling time).
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Node.h"

#include <vector>

namespace sg {

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

    void accept(NodeVisitor& v) override;

private:
    Box box_;
    std::vector<dvec3> polygon_;
    Shape shape_ = Shape::Box;
};

}  // namespace sg
