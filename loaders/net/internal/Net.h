// What the readers of loaders/net share: the failure they throw, scheme tests, percent-decoding, and the read of
// an http(s) URL (HttpRead.cpp).
#pragma once
#include "loaders/net/Resource.h"

#include <string>
#include <vector>

namespace sg::net {

[[noreturn]] void fail(const std::string& name, const std::string& reason);

// Whether s starts with the lower-case `prefix`, ignoring the case of s.
bool startsWithNoCase(const std::string& s, const char* prefix);

// "%20" and the like decoded; a "%" not followed by two hex digits kept as it is.
std::string percentDecoded(const std::string& s);

bool cancelled(const ResourceOptions& o);

// The bytes of an http:// or https:// URL (libcurl); throws LoadError(url, "", reason).
std::vector<unsigned char> readUrl(const std::string& url, const ResourceOptions& o);

}  // namespace sg::net
