// Pager: loads the details of a Scene's PagedLOD nodes from files on loader threads, the most needed first,
// attaches them at the next update and unloads those not needed for a while (Performer's DBASE process,
// OpenSceneGraph's DatabasePager). The threads, queue and policy live here, below the viewer; file formats reach it as
// a load function (sg::loadGltfPage in loaders/gltf/Gltf.h reads glTF), so that the kernel does not depend on a parser.
#pragma once
#include "nodes/PagedLOD.h"
#include "sg/core/PrepareBudget.h"
#include "sg/scene/Scene.h"

#include <algorithm>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

namespace sg {

// What a load function is given: a PagedLOD's file and part (PagedLOD::setFile). A function of whole files may
// take it as the file's name (const std::string&); one that wraps another load function passes it on whole.
struct PageSource {
    std::string file;
    uint32_t part = PagedLOD::kWholeFile;
    operator const std::string&() const { return file; }
    // The file, and the part when there is one ("city/tileset.json#12"): how messages name it.
    std::string name() const { return part == PagedLOD::kWholeFile ? file : file + "#" + std::to_string(part); }
};

// Reads a detail: returns its root, or throws with the reason (the pager adds the source's name when the message
// lacks it). Runs on a loader thread, on several at once with PagerSettings::loaderThreads above 1: it must not
// touch the scene, and must be safe to call concurrently.
using PageLoadFunction = std::function<ref_ptr<Node>(const PageSource& source)>;

// Mesh, texture and node bytes below `root`, each shared mesh, texture or node counted once: what a detail takes
// (its flat image, about a third of its nodes' bytes, aside).
size_t pageBytes(const Node* root);

struct PagerSettings {
    // A detail is unloaded once it was not needed for more than this many updates AND this many seconds
    // (FrameInfo::time), as OpenSceneGraph's expiry; Command-triggered nodes never expire.
    uint64_t expiryFrames = 60;
    double expirySeconds = 1.0;
    // A request the cull did not renew at the last update is dropped if its load has not started.
    bool cancelUnneeded = true;
    // The loader threads' nice value (Linux; 0 leaves it as the process's): they yield to the frame thread.
    int loaderNice = 10;
    // Threads running the load function, each taking the most needed request queued (0 counts as 1).
    unsigned loaderThreads = std::max(1u, std::thread::hardware_concurrency());
    // The attached details' mesh and texture bytes the pager keeps to. Above it, the details not needed at the
    // last update are detached, the least recently needed first (ties: the deepest first); Command-triggered
    // nodes are not detached for it. While still above it (everything attached is needed), no new load starts
    // but commanded ones (Pager::load()) and those of nodes without coarse children (nothing of theirs would be
    // drawn otherwise); PagerStats::overBudget says so.
    size_t maxResidentBytes = size_t(512) << 20;
    // A failed Range node is asked for again by the cull after retrySeconds (FrameInfo::time), doubled per
    // failure in a row up to maxRetrySeconds.
    double retrySeconds = 2.0;
    double maxRetrySeconds = 64.0;
    // With a prepare function (Pager::setPrepare): what each update may spend on it, in ms and objects.
    double prepareMsPerFrame = 1.0;
    uint32_t prepareObjectsPerFrame = 20;
    // Build a loaded detail's flat image on the loader thread, after its load (Scene::buildDetailImage), in the
    // frame the cull posted with the request; the update then takes it instead of building it on the frame
    // thread (a large detail's image takes tens of milliseconds and more to build).
    bool buildImages = true;
    // Free detached details on the loader thread instead of in update()/release(). Only when none of their nodes
    // is also in the graph that stays (a node's parent list changes when a parent of it dies); their meshes,
    // materials and textures may be shared, with a renderer's cache too (reference counts are atomic).
    bool freeOnLoaderThread = false;
    // After each load, and after freeing details, a loader thread hands the memory freed back to the system
    // (glibc's malloc_trim; nothing elsewhere). Loader threads allocate from malloc arenas of their own, which
    // otherwise keep what every tile read and freed: the 10-million-cell flight's process grew to 870 MB with
    // 55-140 MB of tiles resident, and to 599 MB with this (docs/benchmarks.md). It gives back the main arena's
    // free memory too, which keepFreedMemory() keeps for a software rasterizer: a program that wants both fast
    // frames on such a rasterizer and little memory chooses.
    bool trimFreedMemory = true;
};

struct PagerStats {
    // The figures of the last update (and of the commands given since).
    struct Frame {
        uint64_t cancelled = 0;        // requests dropped
        uint64_t failed = 0;           // loads that failed
        uint64_t attached = 0;         // details attached
        uint64_t evicted = 0;          // details detached for the byte budget
        uint64_t unloaded = 0;         // details detached (expired, evicted, released, or inside one of those)
        uint64_t prepared = 0;         // details the prepare function finished
        size_t uploadedBytes = 0;      // by the prepare function (PrepareBudget::bytesUsed)
        uint32_t uploadedObjects = 0;  // (PrepareBudget::objectsUsed)
        double prepareMs = 0.0;        // time in the prepare function
    };
    Frame frame;
    uint64_t evicted = 0;      // details detached for the byte budget
    uint64_t requests = 0;     // loads queued
    uint64_t loads = 0;        // details attached
    uint64_t unloads = 0;      // details detached (expired or released)
    uint64_t failures = 0;     // loads that failed
    uint64_t cancelled = 0;    // requests dropped before their load
    uint64_t discarded = 0;    // loads finished after their request was dropped or released (freed, not attached)
    size_t resident = 0;       // details attached now
    size_t bytesResident = 0;  // their mesh and texture bytes
    size_t queued = 0;         // requests waiting for a loader thread (at the last update)
    size_t loading = 0;        // requests in the loader threads' hands (at the last update)
    bool freeing = false;      // a loader thread was freeing details (at the last update)
    size_t maxQueued = 0;      // the most requests queued at an update
    size_t pending = 0;        // details loaded and waiting for the prepare function (at the last update)
    bool overBudget = false;   // bytesResident above maxResidentBytes after the last update's evictions
    double lastLoadMs = 0.0, maxLoadMs = 0.0, totalLoadMs = 0.0;  // time in the load function
    std::string lastError;                                        // the last failure's message
};

class Pager {
public:
    // Starts the loader threads. Throws std::invalid_argument when `load` is empty.
    explicit Pager(Scene& scene, PageLoadFunction load = {}, PagerSettings settings = {});
    // Stops the loader threads: the loads running finish first (a load cannot be interrupted), the queue is
    // dropped and its nodes are Unloaded again. Attached details stay in the graph.
    ~Pager();
    Pager(const Pager&) = delete;
    Pager& operator=(const Pager&) = delete;

    // On the application thread, before Scene::update(frame): takes the cull's requests and queues them, renews
    // the priorities of the requests the last cull needed (the queue is kept most needed first: see
    // PagedLOD::needPriority()), drops requests no longer needed, attaches the details loaded since (and records
    // failures on their nodes), unloads the expired ones. Never waits for a load.
    void update(const FrameInfo& frame);

    // On command (a map's enter and back), on the application thread. load(): queued now, ahead of every request
    // of the cull, whatever the range (a failed node is tried again); nothing when requested or attached already.
    // release(): a queued request is dropped, an attached detail detached now and its memory freed
    // (PagerSettings::freeOnLoaderThread).
    void load(PagedLOD& node);
    void release(PagedLOD& node);

    // Blocks until no request is queued (that a loader may start) or loading and the details released are freed
    // (tests, scripted demos); update() then attaches what was loaded.
    void waitIdle();

    // Prepares a loaded detail for drawing before it is attached (Renderer::prepare() uploads its meshes and
    // textures; sg::Viewer sets that one when it has a renderer): called in update(), on the application thread,
    // for the details loaded and not attached yet, the most needed first, while the budget lasts
    // (PagerSettings::prepareMsPerFrame, prepareObjectsPerFrame); returns true when done (the detail is attached
    // in that update), false to be called again at the next update. It may throw: the load fails with the
    // message. Empty (the default): details are attached as soon as loaded.
    // `drop`, if given, is called for a detail handed to `prepare` and dropped before it was done (no longer
    // needed): a prepare function that keeps state for a detail (a renderer's upload list holds it) lets it go
    // there, so that the detail is freed where the pager frees details, not later on the frame thread.
    using PrepareFunction = std::function<bool(Node& detail, PrepareBudget& budget)>;
    using DropFunction = std::function<void(const Node& detail)>;
    void setPrepare(PrepareFunction prepare, DropFunction drop = {}) {
        prepare_ = std::move(prepare);
        drop_ = std::move(drop);
    }
    const PrepareFunction& prepare() const { return prepare_; }

    const PagerStats& stats() const { return stats_; }
    const PagerSettings& settings() const { return settings_; }
    // Nodes queued or attached by this pager.
    size_t tracked() const { return active_.size(); }

private:
    // The loader thread sees a node's address as a key only: it never reads or references the node.
    struct Job {
        uint64_t id;
        const PagedLOD* node;
        PageSource source;
        float priority;              // bigger first; Pager::load()'s: infinity
        bool essential;              // may start while over the byte budget (commanded, or no coarse children)
        std::optional<dmat4> frame;  // the detail image's frame, when the cull posted it (buildImages)
    };
    // The queue's order: the most needed last (taken from the back), ties by age (the oldest last).
    static bool lessNeeded(const Job& a, const Job& b) {
        return a.priority < b.priority || (a.priority == b.priority && a.id > b.id);
    }
    struct Result {
        uint64_t id;
        const PagedLOD* node;
        ref_ptr<Node> detail;
        size_t bytes;
        std::string error;
        double ms;
        std::shared_ptr<FlatImage> image;  // the detail's image, built ahead in `frame` (buildImages)
        dmat4 frame;
    };
    struct Active {  // a node the pager has queued or attached (held, so that it outlives its request)
        ref_ptr<PagedLOD> node;
        uint64_t id;          // its current request (results of older ones are discarded)
        uint64_t seenUpdate;  // the last PagedLOD::lastNeeded() seen, and when it was seen
        double seenTime;
        size_t bytes;                        // of the attached detail
        float priority;                      // of its request
        const PagedLOD* owner;               // the tracked node whose detail holds it, or null
        std::vector<const PagedLOD*> inner;  // the tracked nodes its detail holds
        uint32_t depth;                      // tracked owners above it
        bool attached;                       // its detail is counted in the stats
        ref_ptr<Node> pending;               // loaded, waiting for the prepare function
        size_t pendingBytes;
        bool prepared;  // the prepare function saw `pending`: freed on the application thread
        std::shared_ptr<FlatImage> pendingImage = {};  // and its image built ahead, in pendingFrame
        dmat4 pendingFrame = dmat4(1.0);
    };
    void queue(PagedLOD& node, const FrameInfo& frame, float priority, std::optional<dmat4> detailFrame = {});
    void unload(Active& a);
    // Lets go of a tracked node: the tracked nodes inside its detail first, then its request dropped or its
    // detail detached; its entry erased.
    void releaseTree(const PagedLOD* key);
    void forget(const PagedLOD* key);  // erases the entry (and its place in its owner's list)
    void attach(Active& a, ref_ptr<Node> detail, size_t bytes, uint64_t now, const FrameInfo& frame,
                std::shared_ptr<FlatImage> image = {}, const dmat4& imageFrame = dmat4(1.0));
    void fail(Active& a, const std::string& error, const FrameInfo& frame);
    // The steps of update(), in its order, after the loaders' results are taken from done_ into results_.
    void takeResults(uint64_t now, const FrameInfo& frame);  // results_: attached, kept pending, or failed
    void queuePosted(const FrameInfo& frame);                // the cull's new requests
    // Renews what the cull still needs; the requests and details no longer needed into scratch_, the entries whose
    // node lost its detail by other means into `gone`.
    void findUnneeded(uint64_t now, const FrameInfo& frame, std::vector<const PagedLOD*>& gone);
    void dropUnneeded();  // scratch_: requests dropped before their load, details released
    void releaseGone(const std::vector<const PagedLOD*>& gone);
    void runPrepare(uint64_t now, const FrameInfo& frame);
    void evict(uint64_t now);
    bool dropJob(uint64_t id);  // true when the job was still queued
    bool canStart() const;      // a queued job may start (under mutex_)
    void handOver();            // dying_ to the loader thread; the queue figures into stats_
    void run();                 // a loader thread

    Scene& scene_;
    PageLoadFunction load_;
    PagerSettings settings_;
    PagerStats stats_;
    FrameInfo frame_;
    std::unordered_map<const PagedLOD*, Active> active_;
    std::vector<ref_ptr<Node>> posted_;  // taken from the scene's PageRequests
    std::vector<float> postedPriorities_;
    std::vector<std::optional<dmat4>> postedFrames_;
    std::vector<Result> results_;       // taken from done_
    std::vector<ref_ptr<Node>> dying_;  // detached details to free
    std::vector<ref_ptr<Node>> stale_;  // loads discarded, freed on the loader thread
    std::vector<const PagedLOD*> scratch_;
    std::vector<Active*> order_;
    PrepareFunction prepare_;
    DropFunction drop_;
    uint64_t nextId_ = 1;

    // Shared with the loader threads, under mutex_.
    std::mutex mutex_;
    std::condition_variable wake_, idle_;
    std::vector<Job> jobs_;  // ordered by lessNeeded(): the most needed at the back
    std::vector<Result> done_;
    std::vector<ref_ptr<Node>> trash_;  // details to free on a loader thread
    size_t loading_ = 0;                // jobs in the loaders' hands
    size_t freeing_ = 0;                // loaders freeing details
    bool overBudget_ = false;           // only essential jobs may start
    bool stop_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace sg
