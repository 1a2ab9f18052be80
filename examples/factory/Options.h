// The factory walkthrough's command line: window size, path length, budget, outputs.
#pragma once
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
    bool headless = true;  // the only way it runs so far; the flag is accepted for the documented command
    int jitterDraws = 60;  // the fixed view drawn this many times for the same-view jitter
    bool lighting = true;  // the baked sun and ambient occlusion (scenes::bakeFactoryLighting)
    // A thread spinning on another core for the whole run (jitter and every method): the busy machine.
    scenes::BackgroundLoad::Kind backgroundLoad = scenes::BackgroundLoad::Kind::None;
    std::string cacheDir;  // where the bake is cached; empty: sg::VertexLightBaker::defaultCacheDir()
};

// A bad command line: what() names the option; the program exits with code 2.
struct OptionError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Throws OptionError for an unknown option, a missing or malformed value, or a value out of range.
Options parseOptions(int argc, char** argv);
const char* usage();

}  // namespace factory
