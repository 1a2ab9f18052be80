#include "sg/paging/Pager.h"

#include "nodes/Geometry.h"
#include "sg/scene/internal/DistinctGeometries.h"

#include <algorithm>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <unordered_set>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace sg {

namespace {

// Pager::load()'s requests: ahead of every request of the cull.
constexpr float kCommandPriority = std::numeric_limits<float>::infinity();

// The message as it should reach the node: it names the file.
std::string withFile(const std::string& file, const std::string& message) {
    return message.find(file) == std::string::npos ? file + ": " + message : message;
}

void trimFreed() {
#ifdef __GLIBC__
    // The first call initializes glibc's malloc when nothing has yet (a sanitizer's allocator replaces malloc, so
    // only malloc_trim reaches glibc's): two loader threads doing that at once each took the main arena without
    // counting themselves attached, and the second to exit failed glibc's arena assertion. Once, then freely.
    static std::once_flag initialized;
    bool trimmed = false;
    std::call_once(initialized, [&] { malloc_trim(0), trimmed = true; });
    if (!trimmed) malloc_trim(0);
#endif
}

}  // namespace

size_t pageBytes(const Node* root) {
    std::unordered_set<const void*> seen;  // meshes and textures shared by several geometries count once
    size_t bytes = 0;
    // The nodes count too: a tile of instanced boxes is a few kilobytes of meshes and megabytes of nodes.
    forEachDistinctNode(*root, [&](const Node& n) {
        bytes += nodeBytes(n.kind()) + n.numChildren() * sizeof(void*);
        if (n.kind() != NodeKind::Geometry) return;
        const auto& g = static_cast<const Geometry&>(n);
        if (const Mesh* m = g.mesh(); m && seen.insert(m).second) bytes += m->bytes();
        if (const Material* mat = g.material(); mat && mat->texture && seen.insert(mat->texture.get()).second)
            bytes += mat->texture->rgba().size();
    });
    return bytes;
}

Pager::Pager(Scene& scene, PageLoadFunction load, PagerSettings settings)
    : scene_(scene), load_(std::move(load)), settings_(settings) {
    if (!load_) throw std::invalid_argument("Pager::Pager(): no load function (sg::loadGltfPage reads glTF files)");
    settings_.loaderThreads = std::max(1u, settings_.loaderThreads);
    try {
        for (unsigned k = 0; k < settings_.loaderThreads; ++k) threads_.emplace_back([this] { run(); });
    } catch (...) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : threads_) t.join();
        throw;
    }
}

Pager::~Pager() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        jobs_.clear();
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
    // Requests that will not be answered: the cull may ask again (another pager).
    for (auto& [node, a] : active_)
        if (a.node->state() == PagedLOD::State::Requested) a.node->setUnloaded();
}

void Pager::run() {
#ifdef __linux__
    // Below the frame thread, as Performer's DBASE process: on a busy machine the loads wait, not the frames.
    if (settings_.loaderNice > 0) setpriority(PRIO_PROCESS, pid_t(syscall(SYS_gettid)), settings_.loaderNice);
#endif
    std::vector<ref_ptr<Node>> trash;
    for (;;) {
        Job job;
        bool have = false, stopping;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || canStart() || !trash_.empty(); });
            trash.swap(trash_);
            stopping = stop_;
            if (!stopping && canStart()) {
                // The most needed that may start: over the byte budget, the most needed essential one.
                auto it = std::prev(jobs_.end());
                if (overBudget_)
                    while (!it->essential) --it;
                job = std::move(*it);
                jobs_.erase(it);
                have = true;
                loading_++;
            }
            if (!trash.empty()) freeing_++;
        }
        if (!trash.empty()) {
            trash.clear();  // detached details die here, off the frame thread
            if (settings_.trimFreedMemory) trimFreed();
            {
                std::lock_guard<std::mutex> lock(mutex_);
                freeing_--;
            }
            idle_.notify_all();
        }
        if (stopping) return;
        if (!have) continue;
        Result r{job.id, job.node, {}, 0, {}, 0.0, {}, dmat4(1.0)};
        const auto t0 = std::chrono::steady_clock::now();
        try {
            r.detail = load_(job.source);
            if (r.detail) {
                r.bytes = pageBytes(r.detail.get());
                if (job.frame) {  // the image the update would build, built here
                    r.image = Scene::buildDetailImage(*r.detail, *job.frame);
                    r.frame = *job.frame;
                }
            } else {
                r.error = job.source.name() + ": the load function returned no node";
            }
        } catch (const std::exception& e) {
            r.detail = {};
            r.error = withFile(job.source.name(), e.what());
        } catch (...) {
            r.detail = {};
            r.error = job.source.name() + ": the load failed with an unknown exception";
        }
        if (settings_.trimFreedMemory) trimFreed();
        r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        {
            std::lock_guard<std::mutex> lock(mutex_);
            done_.push_back(std::move(r));
            loading_--;
        }
        idle_.notify_all();
    }
}

bool Pager::canStart() const {
    if (jobs_.empty()) return false;
    if (!overBudget_) return true;
    return std::any_of(jobs_.begin(), jobs_.end(), [](const Job& j) { return j.essential; });
}

void Pager::waitIdle() {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [&] { return !canStart() && trash_.empty() && loading_ == 0 && freeing_ == 0; });
}

void Pager::queue(PagedLOD& node, const FrameInfo& frame, float priority, std::optional<dmat4> detailFrame) {
    if (node.file().empty()) {
        node.setFailed(node.describe() + ": no file to load the detail from");
        stats_.failures++;
        stats_.frame.failed++;
        stats_.lastError = node.error();
        return;
    }
    // The tracked node whose detail holds this one, if any: the first PagedLOD up the (first) parents whose
    // detail the path comes through.
    const PagedLOD* owner = nullptr;
    uint32_t depth = 0;
    for (const Node* prev = &node; prev->numParents() > 0;) {
        const Node* cur = prev->parent(0);
        if (cur->kind() == NodeKind::PagedLOD && static_cast<const PagedLOD*>(cur)->detail() == prev) {
            if (auto it = active_.find(static_cast<const PagedLOD*>(cur)); it != active_.end()) {
                owner = it->first;
                depth = it->second.depth + 1;
                it->second.inner.push_back(&node);
                break;
            }
        }
        prev = cur;
    }
    const uint64_t id = nextId_++;
    const uint64_t now = scene_.updateCount();
    active_[&node] = Active{
        &node, id, std::max(node.lastNeeded(), now), frame.time, 0, priority, owner, {}, depth, false, {}, 0, false};
    node.setRequested();
    stats_.requests++;
    const bool essential = priority == kCommandPriority || node.numChildren() == 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        Job job{id,       &node,     PageSource{node.file(), node.part()},
                priority, essential, settings_.buildImages ? detailFrame : std::nullopt};
        jobs_.insert(std::upper_bound(jobs_.begin(), jobs_.end(), job, lessNeeded), std::move(job));
    }
    wake_.notify_one();
}

bool Pager::dropJob(uint64_t id) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = std::find_if(jobs_.begin(), jobs_.end(), [&](const Job& j) { return j.id == id; });
    if (it == jobs_.end()) return false;  // being loaded: its result will be discarded
    jobs_.erase(it);
    return true;
}

void Pager::unload(Active& a) {
    ref_ptr<Node> d = a.node->state() == PagedLOD::State::Loaded ? a.node->detachDetail() : nullptr;
    if (d) dying_.push_back(std::move(d));
    if (a.attached) {
        stats_.unloads++;
        stats_.frame.unloaded++;
        stats_.resident--;
        stats_.bytesResident -= a.bytes;
        a.attached = false;
    }
}

void Pager::forget(const PagedLOD* key) {
    auto it = active_.find(key);
    if (it == active_.end()) return;
    if (it->second.owner)
        if (auto o = active_.find(it->second.owner); o != active_.end()) {
            auto& v = o->second.inner;
            v.erase(std::remove(v.begin(), v.end(), key), v.end());
        }
    active_.erase(it);
}

void Pager::releaseTree(const PagedLOD* key) {
    auto it = active_.find(key);
    if (it == active_.end()) return;
    // Inside first: nothing tracked may dangle in a detail freed, and its bytes leave the total.
    while (!it->second.inner.empty()) {
        const PagedLOD* in = it->second.inner.back();
        releaseTree(in);  // erases `in` from the list (forget)
        it = active_.find(key);
        if (!it->second.inner.empty() && it->second.inner.back() == in) it->second.inner.pop_back();
    }
    Active& a = it->second;
    if (a.attached) {
        unload(a);
    } else if (a.node->state() == PagedLOD::State::Requested) {
        if (a.pending) {
            if (a.prepared && drop_) drop_(*a.pending);
            (a.prepared ? dying_ : stale_).push_back(std::move(a.pending));
            a.pendingImage.reset();
            stats_.cancelled++;
            stats_.frame.cancelled++;
        } else if (dropJob(a.id)) {
            stats_.cancelled++;
            stats_.frame.cancelled++;
        }
        a.node->setUnloaded();
    }
    forget(key);
}

void Pager::attach(Active& a, ref_ptr<Node> detail, size_t bytes, uint64_t now, const FrameInfo& frame,
                   std::shared_ptr<FlatImage> image, const dmat4& imageFrame) {
    if (image) scene_.offerDetailImage(a.node.get(), detail.get(), imageFrame, std::move(image));
    a.node->attachDetail(std::move(detail), bytes);
    a.bytes = bytes;
    a.attached = true;
    a.seenUpdate = std::max(a.seenUpdate, now);
    a.seenTime = frame.time;
    stats_.loads++;
    stats_.frame.attached++;
    stats_.resident++;
    stats_.bytesResident += bytes;
}

void Pager::fail(Active& a, const std::string& error, const FrameInfo& frame) {
    // A Range node is asked for again after the back-off: retrySeconds, doubled per failure in a row.
    double retry = std::numeric_limits<double>::infinity();
    if (a.node->trigger() == PagedLOD::Trigger::Range) {
        const double wait = settings_.retrySeconds * std::ldexp(1.0, int(std::min(a.node->failures(), 30u)));
        retry = frame.time + std::min(wait, std::max(settings_.maxRetrySeconds, settings_.retrySeconds));
    }
    a.node->setFailed(error, retry);
    stats_.failures++;
    stats_.frame.failed++;
    stats_.lastError = error;
}

void Pager::update(const FrameInfo& frame) {
    const uint64_t now = scene_.updateCount();  // the update whose cull marked and posted
    frame_ = frame;
    stats_.frame = {};
    {
        std::lock_guard<std::mutex> lock(mutex_);
        results_.swap(done_);
    }
    takeResults(now, frame);
    queuePosted(frame);
    // Requests not renewed are dropped before their load; details not needed for a while are unloaded; nodes
    // whose detail was removed by other means are forgotten.
    std::vector<const PagedLOD*> gone;
    findUnneeded(now, frame, gone);
    dropUnneeded();
    releaseGone(gone);
    if (prepare_) runPrepare(now, frame);
    evict(now);
    handOver();
}

// Loaded details are attached (or wait for the prepare function); failures are kept on their node.
void Pager::takeResults(uint64_t now, const FrameInfo& frame) {
    for (Result& r : results_) {
        stats_.lastLoadMs = r.ms;
        stats_.maxLoadMs = std::max(stats_.maxLoadMs, r.ms);
        stats_.totalLoadMs += r.ms;
        auto it = active_.find(r.node);
        if (it == active_.end() || it->second.id != r.id || it->second.node->state() != PagedLOD::State::Requested) {
            stats_.discarded++;  // released or dropped while loading: never seen by another thread, freed there
            if (r.detail) stale_.push_back(std::move(r.detail));
            continue;
        }
        Active& a = it->second;
        if (!r.detail) {
            fail(a, r.error, frame);
            forget(r.node);
        } else if (prepare_) {
            a.pending = std::move(r.detail);
            a.pendingBytes = r.bytes;
            a.pendingImage = std::move(r.image);
            a.pendingFrame = r.frame;
        } else {
            attach(a, std::move(r.detail), r.bytes, now, frame, std::move(r.image), r.frame);
        }
    }
    results_.clear();
}

// New requests from the cull, with their priorities (a failed node posted once its back-off has passed).
void Pager::queuePosted(const FrameInfo& frame) {
    scene_.pageRequests().take(posted_, postedPriorities_, postedFrames_);
    for (size_t k = 0; k < posted_.size(); ++k) {
        auto* p = static_cast<PagedLOD*>(posted_[k].get());
        const bool retry = p->state() == PagedLOD::State::Failed && frame.time >= p->retryTime();
        if ((p->state() == PagedLOD::State::Unloaded || retry) && !active_.count(p))
            queue(*p, frame, postedPriorities_[k], postedFrames_[k]);
    }
    posted_.clear();
}

void Pager::findUnneeded(uint64_t now, const FrameInfo& frame, std::vector<const PagedLOD*>& gone) {
    scratch_.clear();
    for (auto& [key, a] : active_) {
        PagedLOD& p = *a.node;
        if (p.lastNeeded() > a.seenUpdate) {  // renewed by the cull: its priority too
            a.seenUpdate = p.lastNeeded();
            a.seenTime = frame.time;
            if (a.priority != kCommandPriority) a.priority = p.needPriority();
        }
        const bool byRange = p.trigger() == PagedLOD::Trigger::Range;
        if (p.state() == PagedLOD::State::Requested) {
            if (byRange && settings_.cancelUnneeded && a.seenUpdate < now) scratch_.push_back(key);
        } else if (p.state() == PagedLOD::State::Loaded && a.attached) {
            if (byRange && now - a.seenUpdate > settings_.expiryFrames &&
                frame.time - a.seenTime > settings_.expirySeconds)
                scratch_.push_back(key);
        } else {
            gone.push_back(key);
        }
    }
}

void Pager::dropUnneeded() {
    for (const PagedLOD* key : scratch_) {
        auto it = active_.find(key);
        if (it == active_.end()) continue;  // released with its owner
        Active& a = it->second;
        if (a.node->state() != PagedLOD::State::Requested || a.pending) {
            releaseTree(key);  // expired, or loaded and waiting for the prepare function
        } else if (dropJob(a.id)) {
            a.node->setUnloaded();
            stats_.cancelled++;
            stats_.frame.cancelled++;
            forget(key);
        }  // else loading: its result comes (and is attached if still needed by then)
    }
}

void Pager::releaseGone(const std::vector<const PagedLOD*>& gone) {
    for (const PagedLOD* key : gone) {
        auto it = active_.find(key);
        if (it == active_.end()) continue;
        Active& a = it->second;
        if (a.attached) {  // the detail was removed from the graph by other means
            stats_.resident--;
            stats_.bytesResident -= a.bytes;
            a.attached = false;
        }
        releaseTree(key);
    }
}

// The pending details, the most needed first, while the budget lasts.
void Pager::runPrepare(uint64_t now, const FrameInfo& frame) {
    order_.clear();
    for (auto& [key, a] : active_)
        if (a.pending) order_.push_back(&a);
    std::sort(order_.begin(), order_.end(), [](const Active* x, const Active* y) {
        return x->priority > y->priority || (x->priority == y->priority && x->id < y->id);
    });
    PrepareBudget budget(settings_.prepareMsPerFrame, settings_.prepareObjectsPerFrame);
    scratch_.clear();
    for (Active* a : order_) {
        if (budget.exhausted()) break;
        a->prepared = true;
        bool done = false;
        std::string error;
        try {
            done = prepare_(*a->pending, budget);
        } catch (const std::exception& e) {
            error = withFile(a->node->file(), e.what());
        } catch (...) {
            error = a->node->file() + ": the prepare function failed with an unknown exception";
        }
        if (!error.empty()) {
            dying_.push_back(std::move(a->pending));
            a->pendingImage.reset();
            fail(*a, error, frame);
            scratch_.push_back(a->node.get());
        } else if (done) {
            stats_.frame.prepared++;
            attach(*a, std::move(a->pending), a->pendingBytes, now, frame, std::move(a->pendingImage), a->pendingFrame);
            a->prepared = false;
        }
    }
    for (const PagedLOD* key : scratch_) forget(key);
    stats_.frame.uploadedBytes = budget.bytesUsed;
    stats_.frame.uploadedObjects = budget.objectsUsed;
    stats_.frame.prepareMs = budget.elapsedMs();
}

// Over the byte budget: the details not needed at the last update detached, the least recently needed first
// (ties: the deepest first), until the budget is met.
void Pager::evict(uint64_t now) {
    if (stats_.bytesResident > settings_.maxResidentBytes) {
        order_.clear();
        for (auto& [key, a] : active_)
            if (a.attached && a.node->trigger() == PagedLOD::Trigger::Range && a.node->lastNeeded() < now)
                order_.push_back(&a);
        std::sort(order_.begin(), order_.end(), [](const Active* x, const Active* y) {
            const uint64_t lx = x->node->lastNeeded(), ly = y->node->lastNeeded();
            return lx < ly || (lx == ly && x->depth > y->depth);
        });
        scratch_.clear();
        for (const Active* a : order_) scratch_.push_back(a->node.get());
        for (const PagedLOD* key : scratch_) {
            if (stats_.bytesResident <= settings_.maxResidentBytes) break;
            if (!active_.count(key)) continue;  // went with its owner
            stats_.evicted++;
            stats_.frame.evicted++;
            releaseTree(key);
        }
    }
    stats_.overBudget = stats_.bytesResident > settings_.maxResidentBytes;
}

void Pager::handOver() {
    size_t pending = 0;
    for (const auto& [key, a] : active_) pending += a.pending ? 1 : 0;
    stats_.pending = pending;
    bool wakeAll;
    {
        // The queue in the order of its requests' priorities, as renewed by this update.
        std::lock_guard<std::mutex> lock(mutex_);
        for (Job& j : jobs_)
            if (auto it = active_.find(j.node); it != active_.end() && it->second.id == j.id)
                j.priority = it->second.priority;
        std::sort(jobs_.begin(), jobs_.end(), lessNeeded);
        wakeAll = overBudget_ && !stats_.overBudget;
        overBudget_ = stats_.overBudget;
    }
    // Detached details may hold nodes the graph that stays holds too (a load function's cache): a dying parent
    // changes its children's parent lists, so they are freed here unless the settings say none is shared.
    if (!settings_.freeOnLoaderThread) dying_.clear();
    const bool wake = !dying_.empty() || !stale_.empty();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (ref_ptr<Node>& d : dying_) trash_.push_back(std::move(d));
        for (ref_ptr<Node>& d : stale_) trash_.push_back(std::move(d));
        stats_.queued = jobs_.size();
        stats_.maxQueued = std::max(stats_.maxQueued, stats_.queued);
        stats_.loading = loading_;
        stats_.freeing = freeing_ > 0;
    }
    if (wakeAll)
        wake_.notify_all();
    else if (wake)
        wake_.notify_one();
    dying_.clear();
    stale_.clear();
}

void Pager::load(PagedLOD& node) {
    if (active_.count(&node)) return;
    if (node.detail()) return;  // attached by other means
    queue(node, frame_, kCommandPriority);
    handOver();
}

void Pager::release(PagedLOD& node) {
    if (!active_.count(&node)) {
        if (ref_ptr<Node> d = node.detachDetail()) {
            // Attached by other means: the tracked nodes inside it go first.
            scratch_.clear();
            for (const auto& [key, a] : active_)
                if (key != &node && a.node->hasAncestorOrSelf(d.get()) && !(a.owner && active_.count(a.owner)))
                    scratch_.push_back(key);
            for (const PagedLOD* key : scratch_) releaseTree(key);
            dying_.push_back(std::move(d));
        }
        handOver();
        return;
    }
    releaseTree(&node);
    handOver();
}

}  // namespace sg
