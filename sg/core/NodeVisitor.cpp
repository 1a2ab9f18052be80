#include "sg/core/NodeVisitor.h"

#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"

namespace sg {

void NodeVisitor::apply(Group& n) { apply(static_cast<Node&>(n)); }
void NodeVisitor::apply(Transform& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Geometry& n) { apply(static_cast<Node&>(n)); }
void NodeVisitor::apply(LOD& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Switch& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Billboard& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Instance& n) { apply(static_cast<Node&>(n)); }
void NodeVisitor::apply(BspGroup& n) { apply(static_cast<Group&>(n)); }
void NodeVisitor::apply(Occluder& n) { apply(static_cast<Node&>(n)); }

void NodeVisitor::traverse(Node& n) {
    for (size_t i = 0, k = n.numChildren(); i < k; ++i)
        if (Node* c = n.child(i)) c->accept(*this);
}

}  // namespace sg
