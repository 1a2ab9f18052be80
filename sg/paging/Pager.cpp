#include "sg/paging/Pager.h"

#include "nodes/Geometry.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <unordered_set>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace sg {

namespace {

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
    thread_ = std::thread([this] { run(); });
}

Pager::~Pager() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        jobs_.clear();
    }
    wake_.notify_all();
    thread_.join();
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
                job = std::move(jobs_.front());
                jobs_.pop_front();
                have = true;
            }
            busy_ = have || !trash.empty();
        }
        trash.clear();  // detached details die here, off the frame thread
        if (stopping) return;
        if (!have) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                busy_ = false;
            }
            idle_.notify_all();
            continue;
        }
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
            busy_ = false;
        }
        idle_.notify_all();
    }
}

void Pager::waitIdle() {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [&] { return jobs_.empty() && trash_.empty() && !busy_; });
}

void Pager::queue(PagedLOD& node, const FrameInfo& frame) {
    if (node.file().empty()) {
        node.setFailed(node.describe() + ": no file to load the detail from");
        stats_.failures++;
        stats_.lastError = node.error();
        return;
    }
    const uint64_t id = nextId_++;
    const uint64_t now = scene_.updateCount();
    active_[&node] = Active{&node, id, std::max(node.lastNeeded(), now), frame.time, 0};
    node.setRequested();
    stats_.requests++;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        jobs_.push_back(Job{id, &node, node.file()});
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

    // New requests from the cull.
    scene_.pageRequests().take(posted_);
    for (const ref_ptr<Node>& n : posted_) {
        auto* p = static_cast<PagedLOD*>(n.get());
        if (p->state() == PagedLOD::State::Unloaded && !active_.count(p)) queue(*p, frame);
    }
    posted_.clear();

    // Requests not renewed are dropped before their load; details not needed for a while are unloaded.
    for (auto it = active_.begin(); it != active_.end();) {
        Active& a = it->second;
        PagedLOD& p = *a.node;
        if (p.lastNeeded() > a.seenUpdate) {
            a.seenUpdate = p.lastNeeded();
            a.seenTime = frame.time;
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
    // Detached details may share meshes with what the frame thread holds (a renderer's cache): reference counts
    // are not atomic, so they are freed here unless the settings say nothing else holds them.
    if (!settings_.freeOnLoaderThread) dying_.clear();
    const bool wake = !dying_.empty() || !stale_.empty();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (ref_ptr<Node>& d : dying_) trash_.push_back(std::move(d));
        for (ref_ptr<Node>& d : stale_) trash_.push_back(std::move(d));
        stats_.queued = jobs_.size();
        stats_.loading = busy_;
    }
    if (wake) wake_.notify_one();
    dying_.clear();
    stale_.clear();
}

void Pager::load(PagedLOD& node) {
    if (active_.count(&node)) return;
    if (node.detail()) return;  // attached by other means
    queue(node, frame_);
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
