// The Geometries a weights channel drives: the node itself when it is a Geometry, else the Geometries below it up to
// the next Transform (a glTF node's primitives, not its child nodes'). Read by Animation::validate() and by the
// AnimationPlayer, so that both mean the same Geometries.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "nodes/Geometry.h"
#include "sg/core/Node.h"

namespace sg {

// Calls f(Geometry&) for each, in traversal order.
template <class F>
void forEachMorphGeometry(Node& n, F&& f) {
    if (n.kind() == NodeKind::Geometry) return f(static_cast<Geometry&>(n));
    for (size_t k = 0, c = n.numChildren(); k < c; ++k) {
        Node* child = n.child(k);
        if (child && child->kind() != NodeKind::Transform) forEachMorphGeometry(*child, f);
    }
}

}  // namespace sg
