// The map program's command line.
#pragma once
#include "sg/viewer/Viewer.h"

#include <string>

namespace sgmap {

struct AtlasSettings;

struct Options {
    bool headless = false;
    std::string script;   // headless: the script file ("-" for standard input); empty: the built-in demo
    std::string dataDir;  // the converted levels; empty: the build tree's (the real map, else the generated one)
    int width = 1280, height = 720;
    bool overlay = false;  // headless: the overlay in screenshots (the window always has it)
    int frames = 0;        // window: quit after this many frames (0: when closed)
    std::string commands;  // window: commands run after the first frame, separated by ';' (tests)
    int loaderNice = 0;    // the loader thread's nice value (sg::PagerSettings::loaderNice)
    sg::ThreadingModel threading = sg::ThreadingModel::SingleThreaded;  // the viewer's threads (--threading)
};

// Parses argv; returns -1 to go on, or the exit code (after --help, or a message on stderr for a bad option).
int readCommandLine(int argc, char** argv, Options& o);
// The data directory to use: o.dataDir, else the build tree's real levels when converted, else the generated map.
std::string dataDirectory(const Options& o);
// The atlas's settings from the options.
AtlasSettings atlasSettings(const Options& o);
// The built-in demo: from the world into the United States, into Texas (or the generated map's first state), a
// pick at each level, and back up.
std::string demoScript(bool generated);

}  // namespace sgmap
