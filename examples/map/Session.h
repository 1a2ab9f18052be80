// Session: the map application without its window: the frame (through sg::Viewer: the pager, the level switch, the
// cull, the draw), the view, entering by zoom, and the commands of the headless script, which the window's keys and
// mouse also go through.
#pragma once
#include "map/Atlas.h"
#include "map/Display.h"
#include "map/MapView.h"
#include "sg/viewer/Viewer.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <mutex>
#include <string>
#include <vector>

namespace sgmap {

class Session {
public:
    // Draws with the display's renderer (its context current), its viewer's stages on the threads of `threading`
    // (the draw on a thread of its own but for SingleThreaded, the display's context moved there).
    Session(Atlas& atlas, Display& display, int width, int height,
            sg::ThreadingModel threading = sg::ThreadingModel::SingleThreaded);

    // One frame: the pager's update and a level entered or failed, the cull, the draw. Returns its milliseconds
    // (threaded: the frame's app side; its draw goes on after it returns).
    double frame();
    // One frame and its picture, read where the frame is drawn once it is (the frames before it drawn too).
    sg::Image picture();
    // Called after each frame's draw where it is drawn (the draw thread when threaded): a window's swap.
    void onPresent(std::function<void()> f) { viewer_.onPresent(std::move(f)); }
    // Runs one command line ("goto -98 39 6000"); returns its result line (empty for a blank or comment line).
    std::string command(const std::string& line);
    // Every line of `in`, each result line to `out` as soon as it is known. Returns how many printed `error`.
    int runScript(std::istream& in, std::ostream& out);

    MapView& view() { return view_; }
    Atlas& atlas() { return atlas_; }
    bool overlay = true;
    size_t emptyKb = 0;  // resident memory of the program before the map was read (0: not known)
    size_t readyKb = 0;  // the same once the renderer has drawn one box (its shaders compiled; 0: not known)
    // What the overlay says: the level, the picked region, the frame rate, the pager.
    std::string overlayText() const;
    // After the view moved (a zoom, a drag, goto): enters the region under the window's centre when it covers
    // more than half of the window. Returns the "entering ..." note, or an empty string.
    std::string enterByZoom();
    // The share of the window that region `index` of the current level covers (a grid of pick rays).
    double coverage(int index);
    // The commands behind the window's mouse: a click and going up a level.
    std::string pickAt(double x, double y);
    std::string back();

    const std::vector<double>& frameMs() const { return frameMs_; }
    // Resident memory of the process (kilobytes), from /proc; the part of it that maps files (the libraries' code).
    static size_t residentKb();
    static size_t residentFileKb();

private:
    std::string regionLine(int index) const;
    std::string showPick(int index);  // highlighted, named in the overlay; its result line
    std::string enter(const std::vector<std::string>& args);
    std::string waitIdle();
    std::string stats() const;
    // Before the atlas changes the graph between frames (a pick's highlight, entering, going back): AppCullDraw
    // culls the last frame on a thread of its own after frame() returns, so that cull is waited for (the other
    // models' cull is done by then, and their draw reads only the frame's own list).
    void beforeChange();

    Atlas& atlas_;
    Display& display_;
    MapView view_;
    sg::Viewer viewer_;  // its view 0: the map's
    std::vector<double> frameMs_;
    Atlas::Step step_;      // of the last frame
    bool release_ = false;  // a level was left: free its GPU copies after the next frame
    std::string picked_, note_;
    // Handed to the draw side (the draw thread when threaded), by frame number: the frame after whose draw the
    // renderer frees what it did not draw, and the frame whose picture picture() wants.
    std::mutex drawSide_;
    int64_t releaseAfter_ = -1, pictureOf_ = -1;
    sg::Image picture_;
};

}  // namespace sgmap
