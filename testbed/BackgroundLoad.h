// BackgroundLoad: work that competes with a benchmark for the machine while it runs (a thread spinning on
// another core), so that the LOD methods can be measured on a machine that is busy with something else.
#pragma once
#include <atomic>
#include <string>
#include <thread>

namespace scenes {

class BackgroundLoad {
public:
    enum class Kind { None, Spin };
    // Throws std::invalid_argument listing the valid names ("none", "spin").
    static Kind parse(const std::string& name);
    static const char* name(Kind k);

    // Starts the load: Spin busy-loops one thread, bound to the last CPU this process may use when it may
    // use more than one (the benchmark keeps the others), until the destructor stops it.
    explicit BackgroundLoad(Kind k);
    ~BackgroundLoad();
    BackgroundLoad(const BackgroundLoad&) = delete;
    BackgroundLoad& operator=(const BackgroundLoad&) = delete;
    Kind kind() const { return kind_; }

private:
    Kind kind_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace scenes
