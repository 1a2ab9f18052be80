#include "sg/scene/ImageFrame.h"

namespace sg {

ImageFrame ImageFrame::make(const FlatImage& image, const dmat4& t) {
    ImageFrame f;
    f.img = &image;
    f.imgToEye = t;
    f.eyeImg = dvec3(glm::inverse(t) * dvec4(0, 0, 0, 1));
    f.scale = maxScale(t);
    f.rigid = isRigid(t);
    return f;
}

bool isRigid(const dmat4& t) {
    const glm::dmat3 a(t);
    const glm::dmat3 ata = glm::transpose(a) * a;
    return glm::length(ata[0] - dvec3(1, 0, 0)) + glm::length(ata[1] - dvec3(0, 1, 0)) +
               glm::length(ata[2] - dvec3(0, 0, 1)) <
           eps::kRigid;
}

}  // namespace sg
