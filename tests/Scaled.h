// Case counts for the heavy accuracy tests: the sanitizer build (SGKIT_SANITIZED) runs a quarter of them. It runs
// 5-10x slower and looks for memory and undefined-behaviour errors, which the same code paths show on fewer
// views; the Release build runs every case and checks the pixels of all of them.
#pragma once
#include <algorithm>

namespace testutil {

#ifdef SGKIT_SANITIZED
constexpr int kSanitizerDivisor = 4;
#else
constexpr int kSanitizerDivisor = 1;
#endif

constexpr int scaled(int n) { return std::max(1, n / kSanitizerDivisor); }

}  // namespace testutil
