// Switch: shows one child, several, or none (Performer's pfSwitch; interiors, states, variants).
#pragma once
#include "nodes/Group.h"

#include <vector>

namespace sg {

class Switch : public Group {
public:
    Switch() : Group(NodeKind::Switch) {}
    void addChild(ref_ptr<Node> child, bool on = true);
    bool isOn(size_t i) const noexcept { return i < on_.size() && on_[i]; }
    // A change is copied into the scene's image at its next update() (no refit) and moves its version(). Throws
    // std::out_of_range naming the index when there is no such child.
    void setOn(size_t i, bool on);
    void setAll(bool on);
    void setOnly(size_t i);  // one child on, the rest off

    void accept(NodeVisitor& v) override;

protected:
    void childInserted(size_t i) override;
    void childRemoved(size_t i) override;

private:
    std::vector<bool> on_;  // the update copies it into the image (the cull may run beside the application)
};

}  // namespace sg
