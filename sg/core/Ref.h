// Intrusive reference counting for nodes and shared resources: a node may have many parents (a DAG).
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace sg {

class Referenced;

// Holds back the deletion of objects whose last reference goes away on this thread while it is active: such an
// object is queued instead of deleted, to be freed later, possibly on another thread, by releaseNow(). A viewer
// whose cull of frame N reads the image of the graph while the application changes the graph for frame N+1 runs
// the application's callbacks inside one, so that a node or mesh removed by them outlives the cull that may still
// point at it; it frees the queue once that cull is done.
//
// Scopes nest on a thread; the innermost one queues. A scope destroyed with objects still queued hands them to
// the enclosing scope, or, when it is the outermost, deletes them at once (take() them first to free them
// later). Only the thread's own final unrefs are held back; an object queued must not be referenced again.
class DeferredRelease {
public:
    DeferredRelease() noexcept;
    ~DeferredRelease();
    DeferredRelease(const DeferredRelease&) = delete;
    DeferredRelease& operator=(const DeferredRelease&) = delete;

    // The objects queued so far, in the order their counts reached 0; the queue is left empty.
    std::vector<const Referenced*> take() noexcept { return std::exchange(queue_, {}); }
    std::size_t size() const noexcept { return queue_.size(); }

private:
    friend class Referenced;
    static thread_local DeferredRelease* current_;
    DeferredRelease* outer_;
    std::vector<const Referenced*> queue_;
};

// Deletes the objects (as their last unref would have) and empties the vector. References they held are dropped
// as usual: what reaches 0 then is deleted at once, or queued when a DeferredRelease is active on this thread.
void releaseNow(std::vector<const Referenced*>& objects);

class Referenced {
public:
    Referenced() = default;
    Referenced(const Referenced&) : refs_(0) {}
    Referenced& operator=(const Referenced&) { return *this; }
    void ref() const noexcept { refs_.fetch_add(1, std::memory_order_relaxed); }
    void unref() const noexcept {
        if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) release();
    }
    uint32_t refCount() const noexcept { return refs_.load(std::memory_order_acquire); }

protected:
    virtual ~Referenced() = default;

private:
    friend void releaseNow(std::vector<const Referenced*>&);
    // The count reached 0: deleted, or queued by the thread's DeferredRelease (only then is the scope looked up).
    void release() const;

    // Atomic because a mesh or material may be shared by details that different threads build, attach and free
    // (a tileset's loads share equal meshes: loaders/tiles/internal/SharedMeshes.h); the graph's edits stay
    // single-threaded.
    mutable std::atomic<uint32_t> refs_{0};
};

template <class T>
class ref_ptr {
public:
    ref_ptr() noexcept = default;
    ref_ptr(T* p) noexcept : p_(p) {  // NOLINT: implicit from raw pointer, like osg::ref_ptr
        if (p_) p_->ref();
    }
    ref_ptr(const ref_ptr& o) noexcept : ref_ptr(o.p_) {}
    template <class U>
    ref_ptr(const ref_ptr<U>& o) noexcept : ref_ptr(o.get()) {}
    ref_ptr(ref_ptr&& o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
    ~ref_ptr() {
        if (p_) p_->unref();
    }
    ref_ptr& operator=(ref_ptr o) noexcept {
        std::swap(p_, o.p_);
        return *this;
    }
    T* get() const noexcept { return p_; }
    T* operator->() const noexcept { return p_; }
    T& operator*() const noexcept { return *p_; }
    explicit operator bool() const noexcept { return p_ != nullptr; }
    bool operator==(const ref_ptr& o) const noexcept { return p_ == o.p_; }
    bool operator!=(const ref_ptr& o) const noexcept { return p_ != o.p_; }

private:
    T* p_ = nullptr;
};

template <class T, class... Args>
ref_ptr<T> make(Args&&... args) {
    return ref_ptr<T>(new T(std::forward<Args>(args)...));
}

}  // namespace sg
