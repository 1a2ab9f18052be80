#include "sg/core/NodeVisitor.h"

namespace sg {

// Each kind's default apply() forwards to its base kind's; they are defined in nodes/Nodes.cpp, where the
// kinds are complete types (core includes nothing of nodes/).

void NodeVisitor::traverse(Node& n) {
    for (size_t i = 0, k = n.numChildren(); i < k; ++i)
        if (Node* c = n.child(i)) c->accept(*this);
}

}  // namespace sg
