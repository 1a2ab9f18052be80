// What every http(s) read of the process shares: libcurl's share object (DNS answers, TLS sessions), the one
// transfer thread whose multi handle holds the connections (HttpShare.cpp), and the cap on requests in flight per
// host (HostLimit.cpp).
#pragma once
#include "loaders/net/Resource.h"

#include <curl/curl.h>

#include <string>

namespace sg::net {

// The process's share object set on an easy handle (DNS answers and TLS sessions); nothing when libcurl could not
// make one. Called after every curl_easy_reset.
void shareCaches(CURL* curl);

// Runs the transfer set up on `curl` to its end and returns what curl_easy_perform would. The transfer runs on the
// process's transfer thread, among the others of every thread, so that it reuses their connections (and
// multiplexes on an HTTP/2 one); its callbacks run there while the calling thread waits. Call it after
// curl_global_init. Without that thread (it could not be started), the transfer runs here, on the handle's own
// connections.
CURLcode performShared(CURL* curl);

struct HostCount;  // HostLimit.cpp

// One of the ResourceOptions::maxRequestsPerHost slots of a URL's host ("scheme://host:port", lower-case), held
// while it lives, whichever thread or options took the others. Constructing it waits for a slot; a cancel
// (ResourceOptions::cancel) seen while waiting throws LoadError(url, "", "cancelled"). A cap of 0 holds nothing.
class HostSlot {
public:
    HostSlot(const std::string& url, const ResourceOptions& o);
    ~HostSlot();
    HostSlot(const HostSlot&) = delete;
    HostSlot& operator=(const HostSlot&) = delete;

private:
    HostCount* host_ = nullptr;
};

}  // namespace sg::net
