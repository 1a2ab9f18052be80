// glfw_smoke: opens a window, draws one frame of a box and checks the centre pixel (run under xvfb-run).
#include "sg/gl/GlfwWindow.h"
#include "sg/gl/Renderer.h"

#include <cstdio>
#include <exception>

int main() try {
    using namespace sg;
    GlfwWindow window(320, 240, "sgkit glfw smoke");
    Renderer renderer;
    auto mesh = makeBoxMesh(dvec3(-0.5), dvec3(0.5));
    auto material = make<Material>(vec4(0.9f, 0.2f, 0.2f, 1.0f));
    Camera camera;
    camera.setLookAt(dvec3(0, 0, 3), dvec3(0.0), dvec3(0, 1, 0));
    camera.setViewport(window.width(), window.height());
    DrawItem item;
    item.mesh = mesh.get();
    item.material = material.get();
    item.model = glm::mat4x3(glm::translate(dmat4(1.0), -camera.eye()));  // the box at the origin, eye-relative
    DrawList list;
    list.items.push_back(item);
    renderer.draw(list, camera);
    const Image img = renderer.readColor();
    window.swapBuffers();
    window.pollEvents();
    const uint8_t* p = &img.rgba[size_t(img.height / 2 * img.width + img.width / 2) * 4];
    std::printf("%dx%d, centre %d %d %d, %.3f s\n", img.width, img.height, p[0], p[1], p[2], window.time());
    return p[0] > 200 && p[1] < 80 ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "glfw_smoke: %s\n", e.what());
    return 1;
}
