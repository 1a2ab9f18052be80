// Billboard: turns its children toward the eye each frame, about an axis (trees) or fully (sprites).
#pragma once
#include "nodes/Group.h"
#include "sg/core/Math.h"

namespace sg {

class Billboard : public Group {
public:
    enum class Mode : uint8_t { Axial, PointEye };
    Billboard() : Group(NodeKind::Billboard) {}

    // Children are authored facing -Y (the local +Y axis turns away from the eye... i.e. the face is
    // seen from -Y), with the rotation axis along `axis` (default +Z, up).
    void setMode(Mode m) { mode_ = m; }
    Mode mode() const { return mode_; }
    // Throws std::invalid_argument for a zero or non-finite axis.
    void setAxis(const dvec3& a);
    const dvec3& axis() const { return axis_; }

    // Rotation (in the billboard's frame) that turns the children toward `eyeLocal`, the eye in that frame.
    dmat4 rotationToward(const dvec3& eyeLocal) const;

    void accept(NodeVisitor& v) override;

private:
    dvec3 axis_{0.0, 0.0, 1.0};
    Mode mode_ = Mode::Axial;
};

}  // namespace sg
