// Atlas: the hierarchical map as a scene: the world level read at start, each further level (the United States,
// a state) a PagedLOD's detail read from its file on the pager's thread when entered and freed when left; the
// chain of levels on the current path, the regions of the current one in a PickSet, and where a longitude and
// latitude lie on it.
#pragma once
#include "nodes/Geometry.h"
#include "nodes/PagedLOD.h"
#include "sg/core/Features.h"
#include "sg/intersect/PickSet.h"
#include "sg/paging/Pager.h"
#include "sg/scene/Scene.h"

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace sgmap {

// One region of a level, as its file describes it.
struct Region {
    std::string id, name, kind;
    std::string child;  // the file of its next level, relative to the data directory; empty when it has none
    double areaKm2 = 0.0;
    sg::Node* node = nullptr;                   // what the level holds for it: its LOD, or the PagedLOD around it
    sg::PagedLOD* paged = nullptr;              // when it has a next level
    std::vector<sg::Geometry*> geometries;      // its prism at each level of detail
    sg::Box box;                                // in the level's plane (kilometres)
    sg::Box mainBox;                            // of its largest connected piece (by top area); empty until asked
    uint32_t firstVertex = 0, vertexCount = 0;  // its part of the level's one mesh (Level::merged)
};

// One level: the regions of one file.
struct Level {
    std::string name;                // "world", "us" or "state", as the file's `level`
    std::string parent;              // the id of the region it details (empty for the world)
    std::string projection;          // as the file's `projection` (empty for the generated map)
    sg::ref_ptr<sg::Node> root;      // a paged level's is taken when attached: until then the pager holds it
    const sg::Node* read = nullptr;  // the root the loader thread made
    std::vector<Region> regions;
    std::unordered_map<const sg::Node*, size_t> byNode;  // Region::node -> its index
    sg::dmat4 toScene{1.0};                              // the level's plane -> the scene (the world level's plane)
    size_t bytes = 0;                                    // its meshes
    size_t triangles = 0;                                // at full detail
    // A level of plain regions (a state's counties) is drawn as one mesh, coloured per vertex: the regions'
    // own geometries are only picked (node mask kPickable). A software rasterizer spends about 0.16 ms on the
    // first draw of each vertex array and keeps tens of kilobytes per draw: 254 counties as 254 meshes made
    // the level's first frame 3-4 times the next and took 17 MB.
    sg::Geometry* merged = nullptr;
    std::vector<sg::vec4> mergedColors;  // its colours unhighlighted
    // The regions as features of class `region`, row i for regions[i], each Region::node bound to its row
    // (map/RegionFeatures.h): a pick's sg::featuresAt names the region, and in a level entered, its parent too.
    sg::ref_ptr<sg::MeshFeatures> features;
    int findId(const std::string& id) const;  // index of the region with that id, or -1
};

struct AtlasSettings {
    // Regions of a level with more triangles than this get coarser levels of detail (meshoptimizer), each shown
    // where its error is under lodPixelError pixels: the world's 290,000 triangles are too many for 60 frames a
    // second in software rendering, a state's counties are not. The simplifier's error counts the prisms' walls
    // (80 km tall) folding into their tops, several times the outline's own error: hence 3 pixels, whose
    // outlines cannot be told from the full ones at the world's scale.
    size_t lodAbove = 40000;
    double lodPixelError = 3.0;
    double pixelsPerRadian = 869.0;  // a 720-pixel-tall view with a 45-degree field of view
    sg::PagerSettings pager = mapPager();
    // The map's loads are what the user waits for (the frame loop draws the coarse level meanwhile): the loader
    // thread runs at the program's priority.
    static sg::PagerSettings mapPager() {
        sg::PagerSettings p;
        p.loaderNice = 0;
        return p;
    }
};

class Atlas {
public:
    // Reads dataDir/world.glb; throws sg::LoadError or std::runtime_error naming the file and the reason.
    explicit Atlas(const std::string& dataDir, AtlasSettings settings = {});
    ~Atlas();

    sg::Scene& scene() { return *scene_; }
    sg::Pager& pager() { return *pager_; }
    const std::string& dataDir() const { return dir_; }
    bool generated() const { return generated_; }

    const Level& level() const { return *chain_.back(); }
    size_t depth() const { return chain_.size(); }  // 1 at the world level
    const std::vector<std::shared_ptr<Level>>& chain() const { return chain_; }

    // Starts entering region `index` of the current level: its file is queued on the pager, and the level
    // becomes current at the update that attaches it. Returns an empty string, or why it cannot be done.
    std::string enter(size_t index);
    // The region being entered (-1 when none) and since when.
    int entering() const { return entering_; }
    std::chrono::steady_clock::time_point enterStart() const { return enterStart_; }
    // The application thread, once per frame: the pager's update, then step(), then the scene's update (a frame
    // loop that updates the pager and the scene itself, sg::Viewer, calls step() between them).
    struct Step {
        bool entered = false;
        std::string error;
    };
    Step update(const sg::FrameInfo& frame);
    // The level entered when its detail is attached, or the reason its load failed (the map stays on the level it
    // was on).
    Step step();
    // Leaves the current level for its parent and frees it. Returns an empty string, or why it cannot be done.
    std::string back();

    // The region of the current level seen along the segment, or -1. pickgeo uses a vertical one.
    int pick(const sg::Ray& ray, const sg::QueryOptions& options, sg::Hit* hit = nullptr);
    int pickPixel(const sg::Camera& camera, double x, double y);
    // pickgeo: the region of the current level at a longitude and latitude (geoToScene), by a ray straight down
    // through the intersection traversal and the pick set (full detail), as a click goes.
    int pickGeo(double lon, double lat);
    // Where a longitude and latitude lie on the current level's plane, in scene coordinates; for the generated
    // map (no projection) the two numbers are the world level's plane coordinates.
    sg::dvec3 geoToScene(double lon, double lat) const;
    // The bounds of a region of the current level, in the scene: of its largest piece when `main` (the
    // conterminous states, not the Aleutians on the far side of the world map), computed once per region.
    sg::Box sceneBox(size_t index, bool main = true);
    // Draws region `index` of the current level highlighted (-1: none).
    void highlight(int index);
    static const sg::vec4 kHighlight;
    int highlighted() const { return highlighted_; }

    // Mesh bytes of the levels loaded (the chain).
    size_t bytesLoaded() const;
    std::string lastError() const { return lastError_; }

private:
    // What the loader thread needs to place a level it reads: copies, so that it shares no node with the
    // application thread (a node's parent list and dirty marks are the application thread's).
    struct Request {
        std::string parentName, parentProjection;
        sg::Box regionBox;  // the region entered, in its level's plane
        sg::dmat4 parentToScene{1.0};
        uint64_t id = 0;
    };
    sg::ref_ptr<sg::Node> load(const std::string& file);  // the loader thread
    std::shared_ptr<Level> readLevel(const std::string& file, const Request* parent) const;
    void showSiblings(const Level& parent, size_t region, bool show);
    void restoreHighlight();

    std::string dir_;
    bool generated_ = false;
    AtlasSettings settings_;
    sg::ref_ptr<sg::Group> root_;
    std::unique_ptr<sg::Scene> scene_;
    std::vector<std::shared_ptr<Level>> chain_;
    sg::PickSet picks_;
    sg::IntersectTraversal intersect_;
    int entering_ = -1;
    std::chrono::steady_clock::time_point enterStart_;
    int highlighted_ = -1;
    uint64_t nextRequest_ = 1;
    std::vector<sg::ref_ptr<sg::Material>> saved_;  // the highlighted region's own materials
    std::string lastError_;
    // Shared with the loader thread.
    std::mutex mutex_;
    // By file. A level read is kept only while its request stands: one dropped meanwhile (back) is not.
    std::map<std::string, Request> requests_;
    std::map<std::string, std::shared_ptr<Level>> read_;
    std::unique_ptr<sg::Pager> pager_;  // last: its thread stops first
};

}  // namespace sgmap
