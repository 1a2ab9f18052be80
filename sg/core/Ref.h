// Intrusive reference counting for nodes and shared resources: a node may have many parents (a DAG).
#pragma once
#include <atomic>
#include <cstdint>
#include <utility>

namespace sg {

class Referenced {
public:
    Referenced() = default;
    Referenced(const Referenced&) : refs_(0) {}
    Referenced& operator=(const Referenced&) { return *this; }
    void ref() const noexcept { refs_.fetch_add(1, std::memory_order_relaxed); }
    void unref() const noexcept {
        if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
    }
    uint32_t refCount() const noexcept { return refs_.load(std::memory_order_acquire); }

protected:
    virtual ~Referenced() = default;

private:
    // Atomic because a mesh or material may be shared by details that different threads build, attach and free
    // (a tileset's loads share equal meshes: loaders/SharedMeshes.h); the graph's edits stay single-threaded.
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
