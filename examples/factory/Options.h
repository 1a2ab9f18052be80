// The factory walkthrough's command line: window size, path length, budget, outputs; the window's start view
// and replayed keys.
#pragma once
#include "sg/core/Math.h"
#include "sg/viewer/Viewer.h"
#include "testbed/BackgroundLoad.h"

#include <stdexcept>
#include <string>

namespace factory {

struct Options {
    int width = 1070, height = 865;  // the paper's window
    int frames = 480;
    double budgetMs = 33.0;
    std::string outDir = ".";
    bool json = false;
    bool headless = false;  // false: the window (the factory-window program), true: the scripted walkthrough
    int jitterDraws = 60;   // the fixed view drawn this many times for the same-view jitter
    bool lighting = true;   // the baked sun and ambient occlusion (scenes::bakeFactoryLighting)
    std::string cacheDir;   // where the bake is cached; empty: sg::VertexLightBaker::defaultCacheDir()
    // A thread spinning on another core for the whole run (jitter and every method): the busy machine.
    scenes::BackgroundLoad::Kind backgroundLoad = scenes::BackgroundLoad::Kind::None;
    // Budget and stress hold the frame rate at 1000 / budgetMs (frames that finish early wait, as at a
    // fixed frame rate); freeRun lets them run as fast as they finish.
    bool freeRun = false;
    // Which threads run the viewer's stages (sg::ThreadingModel; --threading single|draw|cull-per-view|app-cull-draw).
    sg::ThreadingModel threading = sg::ThreadingModel::SingleThreaded;
    bool help = false;
    // The window: quit after `frames` when framesGiven (writing the last one to outDir/factory-window.png),
    // the keys of `keys` replayed one frame after another (parseKeyScript), the start view from --camera.
    bool framesGiven = false;
    std::string keys;
    bool camera = false;
    sg::dvec3 eye{0.0}, center{0.0};
};

// A bad command line: what() names the option; the program exits with code 2.
struct OptionError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Throws OptionError for an unknown option, a missing or malformed value, or a value out of range.
Options parseOptions(int argc, char** argv);
const char* usage();
// A main()'s command line: parseOptions() into `o`, then the usage on stdout for --help (exit code 0), or for a
// bad command line or an --out-dir that cannot be created a message on stderr (code 2). Returns the exit code,
// or -1 to go on.
int readCommandLine(int argc, char** argv, Options& o);

}  // namespace factory
