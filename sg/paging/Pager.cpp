#include "sg/paging/Pager.h"

#include "nodes/Geometry.h"

#include <algorithm>
#include <chrono>
#include <limits>
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

}  // namespace

size_t pageBytes(const Node* root) {
    std::unordered_set<const void*> seen;
    std::vector<const Node*> stack{root};
    size_t bytes = 0;
    while (!stack.empty()) {
        const Node* n = stack.back();
        stack.pop_back();
        if (!seen.insert(n).second) continue;
        if (n->kind() == NodeKind::Geometry) {
            const auto* g = static_cast<const Geometry*>(n);
            if (const Mesh* m = g->mesh(); m && seen.insert(m).second) bytes += m->bytes();
            if (const Material* mat = g->material(); mat && mat->texture && seen.insert(mat->texture.get()).second)
                bytes += mat->texture->rgba().size();
        }
        for (size_t i = 0; i < n->numChildren(); ++i)
            if (const Node* c = n->child(i)) stack.push_back(c);
    }
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
            wake_.wait(lock, [&] { return stop_ || !jobs_.empty() || !trash_.empty(); });
            trash.swap(trash_);
            stopping = stop_;
            if (!stopping && !jobs_.empty()) {
                job = std::move(jobs_.back());  // the most needed
                jobs_.pop_back();
                have = true;
                loading_++;
            }
            if (!trash.empty()) freeing_++;
        }
        if (!trash.empty()) {
            trash.clear();  // detached details die here, off the frame thread
            {
                std::lock_guard<std::mutex> lock(mutex_);
                freeing_--;
            }
            idle_.notify_all();
        }
        if (stopping) return;
        if (!have) continue;
        Result r{job.id, job.node, {}, 0, {}, 0.0};
        const auto t0 = std::chrono::steady_clock::now();
        try {
            r.detail = load_(job.file);
            if (r.detail)
                r.bytes = pageBytes(r.detail.get());
            else
                r.error = job.file + ": the load function returned no node";
        } catch (const std::exception& e) {
            r.detail = {};
            r.error = withFile(job.file, e.what());
        } catch (...) {
            r.detail = {};
            r.error = job.file + ": the load failed with an unknown exception";
        }
        r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        {
            std::lock_guard<std::mutex> lock(mutex_);
            done_.push_back(std::move(r));
            loading_--;
        }
        idle_.notify_all();
    }
}

void Pager::waitIdle() {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [&] { return jobs_.empty() && trash_.empty() && loading_ == 0 && freeing_ == 0; });
}

void Pager::queue(PagedLOD& node, const FrameInfo& frame, float priority) {
    if (node.file().empty()) {
        node.setFailed(node.describe() + ": no file to load the detail from");
        stats_.failures++;
        stats_.lastError = node.error();
        return;
    }
    const uint64_t id = nextId_++;
    const uint64_t now = scene_.updateCount();
    active_[&node] = Active{&node, id, std::max(node.lastNeeded(), now), frame.time, 0, priority};
    node.setRequested();
    stats_.requests++;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        Job job{id, &node, node.file(), priority};
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
    ref_ptr<Node> d = a.node->detachDetail();
    stats_.unloads++;
    stats_.resident--;
    stats_.bytesResident -= a.bytes;
    if (d) dying_.push_back(std::move(d));
}

void Pager::update(const FrameInfo& frame) {
    const uint64_t now = scene_.updateCount();  // the update whose cull marked and posted
    frame_ = frame;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        results_.swap(done_);
    }
    // Loaded details are attached; failures are kept on their node.
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
        if (r.detail) {
            a.node->attachDetail(std::move(r.detail), r.bytes);
            a.bytes = r.bytes;
            a.seenUpdate = now;
            a.seenTime = frame.time;
            stats_.loads++;
            stats_.resident++;
            stats_.bytesResident += r.bytes;
        } else {
            a.node->setFailed(r.error);
            stats_.failures++;
            stats_.lastError = r.error;
            active_.erase(it);
        }
    }
    results_.clear();

    // New requests from the cull, with their priorities.
    scene_.pageRequests().take(posted_, postedPriorities_);
    for (size_t k = 0; k < posted_.size(); ++k) {
        auto* p = static_cast<PagedLOD*>(posted_[k].get());
        if (p->state() == PagedLOD::State::Unloaded && !active_.count(p)) queue(*p, frame, postedPriorities_[k]);
    }
    posted_.clear();

    // Requests not renewed are dropped before their load; details not needed for a while are unloaded.
    for (auto it = active_.begin(); it != active_.end();) {
        Active& a = it->second;
        PagedLOD& p = *a.node;
        if (p.lastNeeded() > a.seenUpdate) {  // renewed by the cull: its priority too
            a.seenUpdate = p.lastNeeded();
            a.seenTime = frame.time;
            if (a.priority != kCommandPriority) a.priority = p.needPriority();
        }
        const bool byRange = p.trigger() == PagedLOD::Trigger::Range;
        bool drop = false;
        if (p.state() == PagedLOD::State::Requested) {
            if (byRange && settings_.cancelUnneeded && a.seenUpdate < now && dropJob(a.id)) {
                p.setUnloaded();
                stats_.cancelled++;
                drop = true;
            }
        } else if (p.state() == PagedLOD::State::Loaded) {
            if (byRange && now - a.seenUpdate > settings_.expiryFrames &&
                frame.time - a.seenTime > settings_.expirySeconds) {
                unload(a);
                drop = true;
            }
        } else {  // the detail was removed from the graph by other means
            stats_.resident--;
            stats_.bytesResident -= a.bytes;
            drop = true;
        }
        it = drop ? active_.erase(it) : std::next(it);
    }
    handOver();
}

void Pager::handOver() {
    {
        // The queue in the order of its requests' priorities, as renewed by this update.
        std::lock_guard<std::mutex> lock(mutex_);
        for (Job& j : jobs_)
            if (auto it = active_.find(j.node); it != active_.end() && it->second.id == j.id)
                j.priority = it->second.priority;
        std::sort(jobs_.begin(), jobs_.end(), lessNeeded);
    }
    // Detached details may share meshes with what the frame thread holds (a renderer's cache): reference counts
    // are not atomic, so they are freed here unless the settings say nothing else holds them.
    if (!settings_.freeOnLoaderThread) dying_.clear();
    const bool wake = !dying_.empty() || !stale_.empty();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (ref_ptr<Node>& d : dying_) trash_.push_back(std::move(d));
        for (ref_ptr<Node>& d : stale_) trash_.push_back(std::move(d));
        stats_.queued = jobs_.size();
        stats_.loading = loading_;
        stats_.freeing = freeing_ > 0;
    }
    if (wake) wake_.notify_one();
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
    auto it = active_.find(&node);
    if (it == active_.end()) {
        if (ref_ptr<Node> d = node.detachDetail()) dying_.push_back(std::move(d));
        handOver();
        return;
    }
    Active& a = it->second;
    if (a.node->state() == PagedLOD::State::Loaded) {
        unload(a);
    } else {
        if (dropJob(a.id)) stats_.cancelled++;
        a.node->setUnloaded();
    }
    active_.erase(it);
    handOver();
}

}  // namespace sg
