// Skin: the joints that pose a skinned mesh (glTF's skins, OpenSceneGraph's osgAnimation::RigGeometry bones): a
// vertex goes to sum_k weight_k * world(joint_k) * inverseBind_k * vertex, whatever node holds the Geometry.
#pragma once
#include "sg/core/Math.h"
#include "sg/core/Node.h"
#include "sg/core/Ref.h"

#include <string>
#include <vector>

namespace sg {

class Skin : public Referenced {
public:
    // Joints are nodes of the graph (Transforms, as a glTF file's are); their world matrices are their paths'
    // products through their first parents. A joint must not hold the Geometry it skins below it (a cycle of
    // references: put skinned Geometries beside their skeleton, as the glTF loader does; Scene::update() throws
    // naming the node). Throws std::invalid_argument for a null joint, a count of inverse bind matrices other than
    // the joints' (empty: identities), a matrix that is not finite or not affine, or no joints.
    Skin(std::vector<ref_ptr<Node>> joints, std::vector<dmat4> inverseBind = {});
    const std::vector<ref_ptr<Node>>& joints() const { return joints_; }
    const std::vector<dmat4>& inverseBind() const { return inverseBind_; }
    size_t size() const { return joints_.size(); }
    std::string name;

private:
    std::vector<ref_ptr<Node>> joints_;
    std::vector<dmat4> inverseBind_;
};

}  // namespace sg
