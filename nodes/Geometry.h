// Geometry: a leaf that draws a shared Mesh with a shared Material.
#pragma once
#include "sg/core/Material.h"
#include "sg/core/Mesh.h"
#include "sg/core/Node.h"
#include "sg/core/Skin.h"

#include <memory>
#include <vector>

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
    ~Geometry() override;
    void setMaterial(ref_ptr<Material> m) {
        material_ = std::move(m);
        markDirty(kDirtyBound);  // the image keeps a copy of the pointer
    }
    Mesh* mesh() const noexcept { return mesh_.get(); }

    // Skinned: its mesh's vertices follow the skin's joints (Mesh::setSkinWeights); where the Geometry sits in the
    // graph then places nothing (glTF's rule), though the Switches, LODs and masks above it still choose whether it is
    // drawn. The update works out the pose each time a joint or a node above one moved (sg/core/Pose.h). Null: not
    // skinned. Throws std::invalid_argument when the mesh has skin weights naming a joint past the skin's.
    void setSkin(ref_ptr<Skin> skin);
    const Skin* skin() const noexcept { return motion_ ? motion_->skin.get() : nullptr; }
    // Morph target weights (Mesh::morphTargets), set by the program or an animation: the update morphs the mesh
    // anew. Fewer weights than targets: the rest are 0; more: throws std::invalid_argument, as a weight that is not
    // finite does. Empty: zeros (a glTF file's mesh.weights are set here by the loader).
    void setMorphWeights(std::vector<float> weights);
    const std::vector<float>& morphWeights() const;
    // Whether the update gives it a Pose (skinned, or given morph weights).
    bool posed() const noexcept { return motion_ != nullptr; }
    Material* material() const noexcept { return material_.get(); }

    void accept(NodeVisitor& v) override;

private:
    struct Motion {
        ref_ptr<Skin> skin;
        std::vector<float> weights;
    };
    std::unique_ptr<Motion> motion_;  // rare: plain Geometries pay a pointer
    ref_ptr<Mesh> mesh_;
    ref_ptr<Material> material_;
};

}  // namespace sg
