// StageThread: a thread that runs the jobs another thread hands it, one at a time (a pipeline stage: the draw, a
// view's cull, the ISECT queries). The job catches its own exceptions; the thread only runs it.
// Internal header: not installed (an internal/ folder, cmake/LayerCheck.cmake).
#pragma once
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace sg {

class StageThread {
public:
    StageThread() : thread_([this] { loop(); }) {}
    // Finishes the job in hand, then joins.
    ~StageThread() {
        {
            std::lock_guard<std::mutex> lock(m_);
            stop_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }
    StageThread(const StageThread&) = delete;
    StageThread& operator=(const StageThread&) = delete;

    // Hands over a job, after the one in hand is done.
    void run(std::function<void()> job) {
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait(lock, [&] { return !job_; });
        job_ = std::move(job);
        lock.unlock();
        cv_.notify_all();
    }
    // Returns once no job is in hand: what the last one wrote is then visible to the caller.
    void wait() {
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait(lock, [&] { return !job_; });
    }
    bool busy() {
        std::lock_guard<std::mutex> lock(m_);
        return bool(job_);
    }

private:
    void loop() {
        std::unique_lock<std::mutex> lock(m_);
        for (;;) {
            cv_.wait(lock, [&] { return stop_ || job_; });
            if (!job_) return;  // stopped with nothing in hand
            std::function<void()> job = job_;
            lock.unlock();
            job();
            job = nullptr;  // what it captured goes before the caller may run again
            lock.lock();
            job_ = nullptr;
            cv_.notify_all();
        }
    }

    std::mutex m_;
    std::condition_variable cv_;
    std::function<void()> job_;
    bool stop_ = false;
    std::thread thread_;  // last: starts once the state above exists
};

}  // namespace sg
