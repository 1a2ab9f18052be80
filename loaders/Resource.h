// Reading a resource (a tile's content, a tileset.json) from a file path or a URL.
#pragma once
#include "loaders/Gltf.h"

#include <atomic>
#include <string>
#include <vector>

namespace sg {

struct ResourceOptions {
    double connectTimeoutSeconds = 10.0;
    double stallSeconds = 15.0;
    size_t maxBytes = size_t(1) << 31;
    const std::atomic<bool>* cancel = nullptr;
};
bool isUrl(const std::string& s);
std::string resolveUri(const std::string& base, const std::string& relative);
std::vector<unsigned char> readResource(const std::string& uriOrPath, const ResourceOptions& options = {});

}  // namespace sg
