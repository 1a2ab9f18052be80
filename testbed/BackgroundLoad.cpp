#include "testbed/BackgroundLoad.h"

#include <stdexcept>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

namespace scenes {

BackgroundLoad::Kind BackgroundLoad::parse(const std::string& name) {
    if (name == "none") return Kind::None;
    if (name == "spin") return Kind::Spin;
    throw std::invalid_argument("BackgroundLoad::parse(): '" + name + "' is not a load (none, spin)");
}

const char* BackgroundLoad::name(Kind k) { return k == Kind::Spin ? "spin" : "none"; }

BackgroundLoad::BackgroundLoad(Kind k) : kind_(k) {
    if (k != Kind::Spin) return;
    thread_ = std::thread([this] {
        volatile unsigned long sink = 0;
        while (!stop_.load(std::memory_order_relaxed)) sink = sink + 1;
    });
#if defined(__linux__)
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    if (sched_getaffinity(0, sizeof allowed, &allowed) == 0 && CPU_COUNT(&allowed) > 1) {
        int last = -1;
        for (int c = 0; c < CPU_SETSIZE; ++c)
            if (CPU_ISSET(c, &allowed)) last = c;
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(last, &one);
        pthread_setaffinity_np(thread_.native_handle(), sizeof one, &one);  // best effort: unbound, it still loads
    }
#endif
}

BackgroundLoad::~BackgroundLoad() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
}

}  // namespace scenes
