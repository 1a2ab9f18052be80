// The connections of every http(s) read in one place: a libcurl multi handle, driven by one transfer thread, holds
// them, so that a connection a read opened on one loader thread is reused (HTTP/1.1 keep-alive) or multiplexed
// (HTTP/2) by the reads of the others. libcurl does not support a connection cache shared by easy handles running
// on several threads at once (CURLSHOPT_SHARE's CURL_LOCK_DATA_CONNECT: "not supported ... between multiple
// concurrent threads", and HTTP/2 streams are added only to connections of the same multi handle); one multi handle
// on one thread is its way. DNS answers and TLS sessions are shared through a share object, which is thread-safe.
#include "loaders/net/internal/HttpPool.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace sg::net {

namespace {

// The share object, with one lock per kind of data, as libcurl asks.
struct Share {
    CURLSH* handle = nullptr;
    std::mutex locks[CURL_LOCK_DATA_LAST];
};

void lockShare(CURL*, curl_lock_data data, curl_lock_access, void* user) noexcept {
    if (data >= 0 && data < CURL_LOCK_DATA_LAST) static_cast<Share*>(user)->locks[data].lock();
}

void unlockShare(CURL*, curl_lock_data data, void* user) noexcept {
    if (data >= 0 && data < CURL_LOCK_DATA_LAST) static_cast<Share*>(user)->locks[data].unlock();
}

Share& share() {
    // Never freed: the easy handles of threads still running at exit hold it.
    static Share* const s = [] {
        auto* made = new Share;
        CURLSH* h = curl_share_init();
        if (!h) return made;
        curl_share_setopt(h, CURLSHOPT_LOCKFUNC, &lockShare);
        curl_share_setopt(h, CURLSHOPT_UNLOCKFUNC, &unlockShare);
        curl_share_setopt(h, CURLSHOPT_USERDATA, made);
        curl_share_setopt(h, CURLSHOPT_SHARE, CURL_LOCK_DATA_DNS);
        // A new connection to a server seen before resumes its TLS session: a shorter handshake.
        curl_share_setopt(h, CURLSHOPT_SHARE, CURL_LOCK_DATA_SSL_SESSION);
        made->handle = h;
        return made;
    }();
    return *s;
}

// One transfer handed to the transfer thread; its caller waits on `finished` until `done`.
struct Job {
    CURL* curl = nullptr;
    bool done = false;
    CURLcode result = CURLE_OK;
    std::condition_variable finished;
};

// The multi handle and the thread that drives it. Loader threads queue their transfers and wait; the thread adds
// them, runs them all and hands each its result.
class TransferThread {
public:
    // The process's; nullptr when libcurl or the system cannot give one.
    static TransferThread* get();
    CURLcode perform(CURL* curl);

private:
    // How long the thread waits on its sockets at most: callbacks see a cancel or a stall this often.
    static constexpr int kPollMs = 100;

    void run();
    void startQueued();
    void finishDone();

    CURLM* multi_ = nullptr;
    std::mutex mutex_;
    std::condition_variable queued_;
    std::vector<Job*> queue_;    // to start, under mutex_
    std::vector<Job*> running_;  // the thread's own
};

TransferThread* TransferThread::get() {
    static TransferThread* const instance = []() -> TransferThread* {
        CURLM* multi = curl_multi_init();
        if (!multi) return nullptr;
        // Idle connections kept for the next reads: a few per host of a few hosts (libcurl's default follows the
        // transfers running, which is none between reads).
        curl_multi_setopt(multi, CURLMOPT_MAXCONNECTS, 64L);
        curl_multi_setopt(multi, CURLMOPT_PIPELINING, long(CURLPIPE_MULTIPLEX));
        auto* t = new TransferThread;  // never freed: loader threads may still be reading at exit
        t->multi_ = multi;
        try {
            std::thread(&TransferThread::run, t).detach();
        } catch (...) {
            curl_multi_cleanup(multi);
            delete t;
            return nullptr;
        }
        return t;
    }();
    return instance;
}

CURLcode TransferThread::perform(CURL* curl) {
    Job job;
    job.curl = curl;
    std::unique_lock<std::mutex> lock(mutex_);
    queue_.push_back(&job);
    queued_.notify_one();       // the thread waits here while it has no transfer
    curl_multi_wakeup(multi_);  // or in curl_multi_poll while it has some
    job.finished.wait(lock, [&] { return job.done; });
    return job.result;
}

void TransferThread::run() {
    for (;;) {
        {
            std::unique_lock<std::mutex> lock(mutex_);
            // Nothing to run: sleep until a transfer comes, no polling.
            queued_.wait(lock, [&] { return !queue_.empty() || !running_.empty(); });
            startQueued();
        }
        int active = 0;
        curl_multi_perform(multi_, &active);
        finishDone();
        if (!running_.empty() && curl_multi_poll(multi_, nullptr, 0, kPollMs, nullptr) != CURLM_OK) {
            // Not expected; waiting a moment keeps a failing poll from spinning.
            std::unique_lock<std::mutex> lock(mutex_);
            queued_.wait_for(lock, std::chrono::milliseconds(kPollMs));
        }
    }
}

// The queued transfers added to the multi handle; called under mutex_.
void TransferThread::startQueued() {
    for (Job* job : queue_) {
        const CURLMcode rc = curl_multi_add_handle(multi_, job->curl);
        if (rc == CURLM_OK) {
            running_.push_back(job);
            continue;
        }
        job->result = rc == CURLM_OUT_OF_MEMORY ? CURLE_OUT_OF_MEMORY : CURLE_FAILED_INIT;
        job->done = true;
        job->finished.notify_one();
    }
    queue_.clear();
}

// The transfers libcurl finished taken off the multi handle (their connections stay in it) and handed back.
void TransferThread::finishDone() {
    int left = 0;
    while (CURLMsg* msg = curl_multi_info_read(multi_, &left)) {
        if (msg->msg != CURLMSG_DONE) continue;
        CURL* curl = msg->easy_handle;
        const CURLcode result = msg->data.result;  // msg is gone once the handle is removed
        curl_multi_remove_handle(multi_, curl);
        const auto it = std::find_if(running_.begin(), running_.end(), [&](Job* j) { return j->curl == curl; });
        if (it == running_.end()) continue;
        Job* job = *it;
        running_.erase(it);
        std::lock_guard<std::mutex> lock(mutex_);
        job->result = result;
        job->done = true;
        job->finished.notify_one();  // under the lock: the job lives on its caller's stack
    }
}

}  // namespace

void shareCaches(CURL* curl) {
    if (CURLSH* h = share().handle) curl_easy_setopt(curl, CURLOPT_SHARE, h);
}

CURLcode performShared(CURL* curl) {
    if (TransferThread* t = TransferThread::get()) return t->perform(curl);
    return curl_easy_perform(curl);
}

}  // namespace sg::net
