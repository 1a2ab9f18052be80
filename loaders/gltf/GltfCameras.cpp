// glTF cameras, as the nodes that carry them place them, into the scene's list of cameras.
#include "loaders/gltf/internal/GltfConverter.h"

#include <cmath>

namespace sg::gltf {

void Converter::camera(int c, const dmat4& world, const std::string& nodeName) {
    const tinygltf::Camera& gc = m.cameras[size_t(c)];
    GltfCamera cam;
    cam.name = gc.name.empty() ? nodeName : gc.name;
    cam.world = world;
    cam.perspective = gc.type == "perspective";
    if (cam.perspective) {
        // Exporters write 0 or degrees now and then: a usable camera, said so, rather than a refused file.
        const double y = gc.perspective.yfov;
        cam.yfovDegrees = glm::degrees(y);
        if (!(std::isfinite(y) && y > 0.0 && y < glm::pi<double>())) {
            cam.yfovDegrees = !std::isfinite(y) ? 60.0 : y <= 0.0 ? 1.0 : 179.0;
            warn(at("cameras", size_t(c)) + ".perspective.yfov", "yfov " + std::to_string(y) + " is not in (0, pi), " +
                                                                     std::to_string(cam.yfovDegrees) + " degrees used");
        }
        cam.aspect = gc.perspective.aspectRatio;
        cam.znear = gc.perspective.znear;
        cam.zfar = gc.perspective.zfar;
    } else {
        cam.xmag = gc.orthographic.xmag;
        cam.ymag = gc.orthographic.ymag;
        cam.znear = gc.orthographic.znear;
        cam.zfar = gc.orthographic.zfar;
    }
    cameraEntries[c].push_back(out.cameras.size());
    out.cameras.push_back(cam);
}

}  // namespace sg::gltf
