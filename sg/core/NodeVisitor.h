// Visitor over the node graph (pointer walk): for tools, loaders and tests; the cull walks the flat image.
#pragma once
#include "sg/core/Node.h"

namespace sg {

class Group;
class Transform;
class Geometry;
class LOD;
class Switch;
class Billboard;
class Instance;
class BspGroup;
class Occluder;
class PagedLOD;

class NodeVisitor {
public:
    virtual ~NodeVisitor() = default;
    virtual void apply(Node& n) { traverse(n); }
    virtual void apply(Group& n);
    virtual void apply(Transform& n);
    virtual void apply(Geometry& n);
    virtual void apply(LOD& n);
    virtual void apply(Switch& n);
    virtual void apply(Billboard& n);
    virtual void apply(Instance& n);
    virtual void apply(BspGroup& n);
    virtual void apply(Occluder& n);
    virtual void apply(PagedLOD& n);
    // Visits every child (an Instance's prototype counts as its child).
    void traverse(Node& n);
};

}  // namespace sg
