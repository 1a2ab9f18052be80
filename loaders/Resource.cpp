#include "loaders/Resource.h"

#include <fstream>
#include <iterator>

namespace sg {

bool isUrl(const std::string& s) { return s.rfind("http://", 0) == 0 || s.rfind("https://", 0) == 0; }

std::string resolveUri(const std::string& base, const std::string& relative) {
    if (isUrl(relative) || (!relative.empty() && relative[0] == '/')) return relative;
    const size_t slash = base.find_last_of('/');
    return slash == std::string::npos ? relative : base.substr(0, slash + 1) + relative;
}

std::vector<unsigned char> readResource(const std::string& path, const ResourceOptions&) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw LoadError(path, "", "no such file");
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(f), {});
}

}  // namespace sg
