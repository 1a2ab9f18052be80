// ResourceOptions::maxRequestsPerHost: a counting semaphore per host, for the whole process, so that loader
// threads do not flood one server (the pager may run many; browsers keep to about six per host as well).
#include "loaders/net/internal/HttpPool.h"
#include "loaders/net/internal/Net.h"

#include <cctype>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>

namespace sg::net {

// The requests in flight to one host, and the waiters for a slot of it.
struct HostCount {
    size_t inFlight = 0;
    std::condition_variable freed;
};

namespace {

struct Hosts {
    std::mutex mutex;
    std::map<std::string, HostCount> byKey;  // entries are kept: slots hold their address
};

Hosts& hosts() {
    static Hosts* const all = new Hosts;  // never freed: a loader thread may still hold a slot at exit
    return *all;
}

// "https://example.com:443": what libcurl connects to, by its own URL parser (the default port filled in).
std::string hostKey(const std::string& url) {
    std::string key;
    if (CURLU* u = curl_url()) {
        if (curl_url_set(u, CURLUPART_URL, url.c_str(), 0) == CURLUE_OK) {
            char *scheme = nullptr, *host = nullptr, *port = nullptr;
            if (curl_url_get(u, CURLUPART_SCHEME, &scheme, 0) == CURLUE_OK &&
                curl_url_get(u, CURLUPART_HOST, &host, 0) == CURLUE_OK &&
                curl_url_get(u, CURLUPART_PORT, &port, CURLU_DEFAULT_PORT) == CURLUE_OK)
                key = std::string(scheme) + "://" + host + ":" + port;
            curl_free(scheme);
            curl_free(host);
            curl_free(port);
        }
        curl_url_cleanup(u);
    }
    if (key.empty()) key = url;  // not a URL libcurl reads: it fails the read itself, under a slot of its own
    for (char& c : key) c = char(std::tolower(static_cast<unsigned char>(c)));
    return key;
}

}  // namespace

HostSlot::HostSlot(const std::string& url, const ResourceOptions& o) {
    if (o.maxRequestsPerHost == 0) return;
    const std::string key = hostKey(url);
    Hosts& all = hosts();
    std::unique_lock<std::mutex> lock(all.mutex);
    HostCount& host = all.byKey[key];
    while (host.inFlight >= o.maxRequestsPerHost) {
        if (!o.cancel) {
            host.freed.wait(lock);
            continue;
        }
        if (cancelled(o)) fail(url, "cancelled");
        // A release wakes this at once; the timeout only serves a cancel, which nothing signals.
        host.freed.wait_for(lock, std::chrono::milliseconds(100));
    }
    ++host.inFlight;
    host_ = &host;
}

HostSlot::~HostSlot() {
    if (!host_) return;
    std::lock_guard<std::mutex> lock(hosts().mutex);
    --host_->inFlight;
    host_->freed.notify_all();  // waiters may have caps of their own: each checks its own
}

}  // namespace sg::net
