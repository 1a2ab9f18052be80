#include "map/Session.h"
#include "testbed/Stats.h"

#include <malloc.h>
#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>

namespace sgmap {

using namespace sg;
using Clock = std::chrono::steady_clock;

namespace {

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

std::vector<std::string> words(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> w;
    for (std::string s; in >> s;) w.push_back(s);
    return w;
}

bool number(const std::string& s, double& out) {
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return end && *end == '\0' && end != s.c_str() && std::isfinite(out);
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

constexpr double kEnterTimeoutMs = 60000.0;  // a load that takes longer is reported, not waited for

}  // namespace

namespace {
ViewerSettings viewerSettings(Display& display, ThreadingModel threading) {
    ViewerSettings s;
    s.threading = threading;
    s.bindContext = [&display](bool current) { display.bindContext(current); };
    return s;
}
}  // namespace

Session::Session(Atlas& atlas, Display& display, int width, int height, ThreadingModel threading)
    : atlas_(atlas), display_(display), viewer_(atlas.scene(), display.renderer(), viewerSettings(display, threading)) {
    View& v = viewer_.addView();
    v.cull.traversalMask = ~(kPickable | kCollidable);  // a level's pick-only regions are not drawn
    v.clearColor = kSeaColor;
    v.prefetchSeconds = 0.0;  // the levels are entered by command: a look-ahead would walk the map for nothing
    // The atlas's pager is updated by the viewer; between it and the scene's update, the level entered or failed.
    viewer_.usePager(&atlas_.pager());
    viewer_.onUpdate([this](const FrameInfo& fi) {
        step_ = atlas_.step();
        if (step_.entered) picked_.clear();
        if (!step_.error.empty()) note_ = "error: " + step_.error;
        if (step_.entered || release_) {
            std::lock_guard<std::mutex> lock(drawSide_);
            releaseAfter_ = int64_t(fi.frame);
            release_ = false;
        }
    });
    // A level read or left: once the frame is drawn, the GPU copies of the meshes it did not draw (the level left,
    // or the level above at the detail it had while this one loaded), then the loader's scratch memory and the
    // level's freed meshes go back to the system, so that the resident memory follows what is loaded and drawn.
    // The renderer is used only where the frame is drawn.
    viewer_.onDrawn([this](const FrameInfo& fi) {
        std::lock_guard<std::mutex> lock(drawSide_);
        if (int64_t(fi.frame) == pictureOf_) picture_ = display_.read();
        if (releaseAfter_ >= 0 && int64_t(fi.frame) >= releaseAfter_) {
            releaseAfter_ = -1;
            display_.renderer().releaseUnused();
            malloc_trim(0);
        }
    });
    viewer_.overlayText = [this] { return overlayText(); };
    view_.width = width;
    view_.height = height;
    // The whole world level in view.
    Box all;
    for (size_t i = 0; i < atlas_.level().regions.size(); ++i) all.expand(atlas_.sceneBox(i, false));
    view_.frame(all, 0.95);
}

double Session::frame() {
    const auto t0 = Clock::now();
    view_.clamp();  // the window's drag and scroll move it directly
    viewer_.view().camera = view_.camera();
    viewer_.overlay = overlay;
    viewer_.frame();
    const double ms = msSince(t0);
    frameMs_.push_back(ms);
    return ms;
}

void Session::beforeChange() {
    if (viewer_.settings().threading == ThreadingModel::AppCullDraw) viewer_.flush();
}

sg::Image Session::picture() {
    {
        std::lock_guard<std::mutex> lock(drawSide_);
        pictureOf_ = int64_t(viewer_.frameNumber());  // the next frame's number
    }
    frame();
    viewer_.flush();
    std::lock_guard<std::mutex> lock(drawSide_);
    pictureOf_ = -1;
    return std::move(picture_);
}

std::string Session::regionLine(int index) const {
    if (index < 0) return "none";
    const Region& r = atlas_.level().regions[size_t(index)];
    return r.kind + "\t" + r.id + "\t" + r.name;
}

double Session::coverage(int index) {
    if (index < 0) return 0.0;
    const Camera camera = view_.camera();
    constexpr int nx = 32, ny = 18;
    int in = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            in += atlas_.pickPixel(camera, (i + 0.5) * view_.width / nx, (j + 0.5) * view_.height / ny) == index;
    return double(in) / (nx * ny);
}

std::string Session::enterByZoom() {
    if (atlas_.entering() >= 0) return {};
    const int index = atlas_.pickPixel(view_.camera(), 0.5 * view_.width, 0.5 * view_.height);
    if (index < 0 || !atlas_.level().regions[size_t(index)].paged || coverage(index) <= 0.5) return {};
    beforeChange();
    if (!atlas_.enter(size_t(index)).empty()) return {};
    const Region& r = atlas_.level().regions[size_t(index)];
    note_ = "entering " + r.name;
    return "entering\t" + regionLine(index);
}

std::string Session::pickAt(double x, double y) { return showPick(atlas_.pickPixel(view_.camera(), x, y)); }

std::string Session::showPick(int index) {
    beforeChange();
    atlas_.highlight(index);
    release_ = atlas_.level().merged != nullptr;  // the level's mesh before the highlight
    picked_.clear();
    if (index >= 0) {
        const Region& r = atlas_.level().regions[size_t(index)];
        picked_ = r.kind + " " + r.id + " " + r.name + fmt(", %.0f km2", r.areaKm2);
    }
    return regionLine(index);
}

std::string Session::back() {
    if (const int e = atlas_.entering(); e >= 0) {
        const std::string line = "stopped\t" + regionLine(e);
        beforeChange();
        atlas_.back();
        return line;
    }
    const std::string parentId = atlas_.level().parent;
    beforeChange();
    if (const std::string err = atlas_.back(); !err.empty()) return "error\t" + err;
    picked_.clear();
    release_ = true;
    if (const int index = atlas_.level().findId(parentId); index >= 0)
        view_.frame(atlas_.sceneBox(size_t(index)), 0.35);
    const Level& l = atlas_.level();
    return l.name + (l.parent.empty() ? "" : "\t" + l.parent);
}

std::string Session::enter(const std::vector<std::string>& args) {
    const Level& l = atlas_.level();
    int index = -1;
    if (args.size() > 1) {
        index = l.findId(args[1]);
        if (index < 0) return "error\tno region with id " + args[1] + " at the " + l.name + " level";
    } else {
        index = atlas_.pickPixel(view_.camera(), 0.5 * view_.width, 0.5 * view_.height);
        if (index < 0) return "error\tno region under the window centre";
    }
    const Region region = l.regions[size_t(index)];
    beforeChange();
    if (const std::string err = atlas_.enter(size_t(index)); !err.empty()) return "error\t" + err;
    const auto t0 = Clock::now();
    view_.frame(atlas_.sceneBox(size_t(index)), 0.9);
    const size_t first = frameMs_.size();
    while (true) {
        frame();
        if (step_.entered) break;
        if (!step_.error.empty()) return "error\t" + step_.error;
        if (msSince(t0) > kEnterTimeoutMs) return "error\t" + region.name + ": still loading after 60 s";
    }
    const double ms = msSince(t0);
    // The frames drawn while it loaded (the last one shows the new level).
    std::vector<double> during(frameMs_.begin() + long(first), frameMs_.end() - 1);
    const double worst = during.empty() ? 0.0 : *std::max_element(during.begin(), during.end());
    note_ = "entered " + region.name;
    return atlas_.level().name + "\t" + region.id + "\t" + region.name + fmt("\t%.1f ms", ms) +
           fmt("\t(read %.1f ms", atlas_.pager().stats().lastLoadMs) +
           fmt("; %.0f frames while loading", double(during.size())) + fmt(", slowest %.1f ms", worst) +
           fmt("; the level's first frame %.1f ms)", frameMs_.back());
}

std::string Session::waitIdle() {
    const auto t0 = Clock::now();
    int n = 0;
    frame();  // takes the pager's state
    for (++n; atlas_.entering() >= 0 || atlas_.pager().stats().queued > 0 || atlas_.pager().stats().loading; ++n) {
        frame();
        if (msSince(t0) > kEnterTimeoutMs) return "error\tstill loading after 60 s";
    }
    std::string line = "idle" + fmt("\t%.0f frames", n) + fmt("\t%.1f ms", msSince(t0));
    if (!step_.error.empty()) line += "\t" + step_.error;
    return line;
}

size_t Session::residentKb() {
    std::ifstream in("/proc/self/statm");
    size_t pages = 0, resident = 0;
    in >> pages >> resident;
    return resident * size_t(sysconf(_SC_PAGESIZE)) / 1024;
}

size_t Session::residentFileKb() {
    std::ifstream in("/proc/self/statm");
    size_t pages = 0, resident = 0, shared = 0;
    in >> pages >> resident >> shared;
    return shared * size_t(sysconf(_SC_PAGESIZE)) / 1024;
}

std::string Session::stats() const {
    const PagerStats& p = atlas_.pager().stats();
    std::vector<double> recent(frameMs_.end() - long(std::min<size_t>(frameMs_.size(), 60)), frameMs_.end());
    const double med = stats::median(recent);
    const Level& l = atlas_.level();
    std::string s = "level " + l.name + (l.parent.empty() ? "" : " " + l.parent);
    s += fmt("\tregions %.0f", double(l.regions.size()));
    s += fmt("\tframe_ms_median %.2f", med) + fmt("\tfps %.1f", med > 0 ? 1000.0 / med : 0.0);
    s += fmt("\tloads %.0f", double(p.loads)) + fmt("\tunloads %.0f", double(p.unloads));
    s += fmt("\tfailures %.0f", double(p.failures)) + fmt("\tresident %.0f", double(p.resident));
    s += fmt("\tbytes_resident %.0f", double(p.bytesResident)) + fmt("\tqueued %.0f", double(p.queued));
    s += fmt("\tgeometry_kb %.0f", atlas_.bytesLoaded() / 1024.0) + fmt("\trss_kb %.0f", double(residentKb()));
    s += fmt("\trss_file_kb %.0f", double(residentFileKb()));
    if (emptyKb > 0) s += fmt("\tempty_kb %.0f", double(emptyKb));
    if (readyKb > 0) s += fmt("\tready_kb %.0f", double(readyKb));
    return s;
}

std::string Session::overlayText() const {
    const Level& l = atlas_.level();
    const PagerStats& p = atlas_.pager().stats();
    std::vector<double> recent(frameMs_.end() - long(std::min<size_t>(frameMs_.size(), 30)), frameMs_.end());
    const double med = stats::median(recent);
    std::string s = "level " + l.name + (l.parent.empty() ? "" : " (" + l.parent + ")") +
                    fmt(": %.0f regions", double(l.regions.size())) + fmt("   fps %.1f", med > 0 ? 1000.0 / med : 0.0) +
                    "\n";
    s += "picked: " + (picked_.empty() ? std::string("-") : picked_) + "\n";
    s += fmt("pager: loads %.0f", double(p.loads)) + fmt("  unloads %.0f", double(p.unloads)) +
         fmt("  resident %.0f", double(p.resident)) + fmt(" (%.1f MB)", p.bytesResident / 1048576.0) +
         fmt("  queued %.0f", double(p.queued)) + (atlas_.entering() >= 0 ? "  loading..." : "") + "\n";
    if (!note_.empty()) s += note_ + "\n";
    return s;
}

std::string Session::command(const std::string& line) {
    const std::vector<std::string> w = words(line);
    if (w.empty() || w[0][0] == '#') return {};
    const std::string& c = w[0];
    static const char* const known[] = {"goto",       "zoom",  "enter", "back",   "pick",   "pickgeo",
                                        "screenshot", "stats", "wait",  "frames", "overlay"};
    if (std::find(std::begin(known), std::end(known), c) == std::end(known)) return "error\tunknown command: " + c;
    std::vector<double> v(w.size(), 0.0);
    for (size_t i = 1; i < w.size(); ++i)
        if (c != "enter" && c != "screenshot" && c != "overlay" && !number(w[i], v[i]))
            return "error\t" + c + ": not a number: " + w[i];
    auto want = [&](size_t n, const char* usage) {
        return w.size() == n + 1 ? std::string() : "error\tusage: " + std::string(usage);
    };
    if (c == "goto") {
        if (auto e = want(3, "goto LON LAT HEIGHT_KM"); !e.empty()) return e;
        if (!(v[3] > 0.0)) return "error\tgoto: the height must be above 0 km";
        view_.centre = glm::dvec2(atlas_.geoToScene(v[1], v[2]));
        view_.setEyeHeight(v[3]);  // clamped, with the centre
        frame();
        const std::string entering = enterByZoom();
        return "at" + fmt("\t%g", v[1]) + fmt("\t%g", v[2]) + fmt("\t%g km", v[3]) +
               (entering.empty() ? "" : "\t" + entering);
    }
    if (c == "zoom") {
        if (auto e = want(1, "zoom FACTOR"); !e.empty()) return e;
        if (!(v[1] > 0.0)) return "error\tzoom: the factor must be above 0";
        view_.distance /= v[1];
        view_.clamp();
        frame();
        const std::string entering = enterByZoom();
        return "height" + fmt("\t%.1f km", view_.eyeHeight()) + (entering.empty() ? "" : "\t" + entering);
    }
    if (c == "enter") {
        if (w.size() > 2) return "error\tusage: enter [ID]";
        return enter(w);
    }
    if (c == "back") {
        if (auto e = want(0, "back"); !e.empty()) return e;
        const std::string r = back();
        frame();
        return r;
    }
    if (c == "pick") {
        if (auto e = want(2, "pick X Y"); !e.empty()) return e;
        return pickAt(v[1], v[2]);
    }
    if (c == "pickgeo") {
        if (auto e = want(2, "pickgeo LON LAT"); !e.empty()) return e;
        return showPick(atlas_.pickGeo(v[1], v[2]));
    }
    if (c == "screenshot") {
        if (w.size() != 2) return "error\tusage: screenshot FILE";
        try {
            savePng(w[1], picture());
        } catch (const std::exception& e) {
            return "error\t" + std::string(e.what());
        }
        return "wrote\t" + w[1];
    }
    if (c == "stats") return stats();
    if (c == "overlay") {
        if (w.size() != 2 || (w[1] != "on" && w[1] != "off")) return "error\tusage: overlay on|off";
        overlay = w[1] == "on";
        return "overlay\t" + w[1];
    }
    if (c == "wait") return waitIdle();
    if (c == "frames") {
        if (auto e = want(1, "frames N"); !e.empty()) return e;
        std::vector<double> ms;
        if (!(v[1] >= 1.0 && v[1] <= 100000.0)) return "error\tframes: the count must be 1 to 100000";
        for (int i = 0; i < int(v[1]); ++i) ms.push_back(frame());
        const double med = stats::median(ms);
        return "frames" + fmt("\t%.0f", double(ms.size())) + fmt("\tmedian %.2f ms", med) +
               fmt("\t%.1f fps", med > 0 ? 1000.0 / med : 0.0) +
               fmt("\t%.0f triangles", double(viewer_.view().cullStats().triangles));
    }
    return "error\tunknown command: " + c;
}

int Session::runScript(std::istream& in, std::ostream& out) {
    frame();
    int errors = 0;
    for (std::string line; std::getline(in, line);) {
        std::string r;
        try {
            r = command(line);
        } catch (const std::exception& e) {
            r = "error\t" + std::string(e.what());
        }
        if (!r.empty()) out << r << std::endl;
        errors += r.compare(0, 5, "error") == 0;
    }
    return errors;
}

}  // namespace sgmap
