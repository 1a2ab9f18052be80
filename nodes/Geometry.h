// Geometry: a leaf that draws a shared Mesh with a shared Material.
#pragma once
#include "sg/core/Material.h"
#include "sg/core/Mesh.h"
#include "sg/core/Node.h"

namespace sg {

class Geometry : public Node {
public:
    Geometry() : Node(NodeKind::Geometry) {}
    Geometry(ref_ptr<Mesh> mesh, ref_ptr<Material> material) : Geometry() {
        setMesh(std::move(mesh));
        setMaterial(std::move(material));
    }
    void setMesh(ref_ptr<Mesh> m) {
        mesh_ = std::move(m);
        markDirty(kDirtyBound);
    }
    void setMaterial(ref_ptr<Material> m) {
        material_ = std::move(m);
        markDirty(kDirtyBound);  // the image keeps a copy of the pointer
    }
    Mesh* mesh() const noexcept { return mesh_.get(); }
    Material* material() const noexcept { return material_.get(); }

    void accept(NodeVisitor& v) override;

private:
    ref_ptr<Mesh> mesh_;
    ref_ptr<Material> material_;
};

}  // namespace sg
