// sgview: the scene viewer. A window with trackball, fly and walk navigation and a stats overlay; or
// --headless, rendering offscreen to a PNG; or --info, a summary of the scene. `sgview --help` lists it all.
#include "sg/scene/Scene.h"
#include "sgview/Info.h"
#include "sgview/LoadScene.h"
#include "sgview/Modes.h"
#include "sgview/Options.h"

#include <cstdio>
#include <exception>

using namespace sgview;

int main(int argc, char** argv) {
    // Exit codes: 0 done, 1 the run failed (no GL context, a file that cannot be written), 2 bad input (the
    // command line or a file to load).
    try {
        const Options o = parseOptions(argc, argv);
        if (o.help) {
            std::fputs(usageText(), stdout);
            return 0;
        }
        const LoadedScene loaded = loadScene(o);
        sg::Scene scene(loaded.root);
        scene.update();
        if (o.info) {
            printInfo(stdout, loaded.title, computeInfo(*loaded.root, scene), loaded.warnings);
            if (loaded.tilesReport) std::printf("%s\n", loaded.tilesReport().c_str());
            std::printf("animations: %zu\n", loaded.animations.size());
            for (size_t i = 0; i < loaded.animations.size() && i < 20; ++i)
                std::printf("  %zu '%s': %.3f s, %zu channels\n", i, loaded.animations[i]->name.c_str(),
                            loaded.animations[i]->duration(), loaded.animations[i]->channels.size());
            return 0;
        }
        for (const std::string& w : loaded.warnings) std::fprintf(stderr, "sgview: warning: %s\n", w.c_str());
        if (!o.save.empty()) {
            saveSceneFile(loaded, o.save);  // with its animations (GltfSaveOptions::animations)
            std::printf("sgview: wrote %s\n", o.save.c_str());
            return 0;
        }
        return o.headless ? runHeadless(o, scene, loaded) : runWindow(o, scene, loaded);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "sgview: %s\n(sgview --help lists the options)\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgview: %s\n", e.what());
        return 1;
    }
}
