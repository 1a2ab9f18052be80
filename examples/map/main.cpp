// sgmap: the hierarchical map (the world's countries, the United States' states, each state's counties) after the
// Performer paper's map: a level entered by zooming in on a region or by command, read from disk on the pager's
// thread, freed on going back; a click picks the region of the current level. Without --headless it starts
// sgmap-window; with it, a script of commands (or the built-in demo) runs offscreen, one result line per command.
#include "common/WindowProgram.h"
#include "map/Atlas.h"
#include "map/Options.h"
#include "map/OsmesaDisplay.h"
#include "map/Session.h"
#include "sg/core/Material.h"
#include "sg/core/Mesh.h"
#include "sg/cull/DrawList.h"
#include "sg/gl/KeepFreedMemory.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

using namespace sgmap;

namespace {

// Two boxes, drawn as the map draws its regions (one with vertex colours, as a state's merged counties). llvmpipe
// compiles its shaders on the first draws, and that pages in some 12 MB of LLVM's code whatever is drawn: the
// program ready to draw, without a map, is measured after it.
void drawTrivialFrame(Display& display, int width, int height) {
    using namespace sg;
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1.0), dvec3(1.0));
    const ref_ptr<Mesh> coloured = make<Mesh>();
    coloured->set(box->positions(), box->normals(), {box->indices16().begin(), box->indices16().end()}, {},
                  std::vector<vec4>(box->positions().size(), vec4(0.5f, 0.8f, 0.6f, 1.0f)));
    const ref_ptr<Material> material = make<Material>();
    DrawList list;
    for (const Mesh* m : {box.get(), coloured.get()}) {
        DrawItem item;
        item.mesh = m;
        item.material = material.get();
        item.model = glm::mat4x3(glm::translate(mat4(1.0f), vec3(m == box.get() ? -2.0f : 2.0f, 0.0f, -10.0f)));
        list.add(item, 10.0f);
    }
    Camera camera;
    camera.setLookAt(dvec3(0.0), dvec3(0.0, 0.0, -1.0), dvec3(0.0, 1.0, 0.0));
    camera.setPerspective(30.0, double(width) / height, 1.0, 100.0);
    camera.setViewport(width, height);
    display.renderer().draw(list, camera, kSeaColor);
    display.renderer().finish();
}

#ifdef SGMAP_WINDOW_PROGRAM
constexpr const char* kWindowProgram = SGMAP_WINDOW_PROGRAM;
#else
constexpr const char* kWindowProgram = nullptr;
#endif

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const int code = readCommandLine(argc, argv, o); code >= 0) return code;
    if (!o.headless)
        return common::runWindowProgram(
            argv, kWindowProgram, "sgmap",
            "built without GLFW, so there is no window; --headless runs a script offscreen");
    try {
        const std::string dir = dataDirectory(o);
        // The program without a map (its GL context and renderer), and the same after drawing two boxes: what
        // `stats` compares the memory with.
        OsmesaDisplay display(o.width, o.height);
        if (display.renderer().softwareRasterizer()) sg::keepFreedMemory();  // before the memory is measured
        const size_t emptyKb = Session::residentKb();
        drawTrivialFrame(display, o.width, o.height);
        const size_t readyKb = Session::residentKb();
        Atlas atlas(dir, atlasSettings(o));
        std::fprintf(stderr, "sgmap: %s map from %s: %zu regions, %zu triangles at the world level\n",
                     atlas.generated() ? "generated" : "real", dir.c_str(), atlas.level().regions.size(),
                     atlas.level().triangles);
        Session session(atlas, display, o.width, o.height, o.threading);
        session.emptyKb = emptyKb;
        session.readyKb = readyKb;
        session.overlay = o.overlay;
        if (o.script == "-") {
            session.runScript(std::cin, std::cout);
        } else if (!o.script.empty()) {
            std::ifstream in(o.script);
            if (!in) {
                std::fprintf(stderr, "sgmap: cannot read the script %s: %s\n", o.script.c_str(), std::strerror(errno));
                return 1;
            }
            session.runScript(in, std::cout);
        } else {
            std::istringstream in(demoScript(atlas.generated()));
            if (const int errors = session.runScript(in, std::cout); errors > 0) {
                std::fprintf(stderr, "sgmap: %d command%s of the demo failed\n", errors, errors == 1 ? "" : "s");
                return 1;
            }
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgmap: %s\n", e.what());
        return 1;
    }
}
