// SG_ASSERT: checks an internal invariant in debug builds and in builds with SGKIT_ASSERTS (the sanitizer
// build), printing where and why to stderr before aborting; elsewhere it compiles to nothing.
#pragma once

// API misuse throws a named exception instead: these are for states only a bug in sgkit can reach.
#if !defined(NDEBUG) || defined(SGKIT_ASSERTS)
#define SG_ASSERTS_ENABLED 1
#include <cstdio>
#include <cstdlib>

namespace sg {
namespace detail {
[[noreturn]] inline void assertFailed(const char* file, int line, const char* cond, const char* msg) noexcept {
    std::fprintf(stderr, "%s:%d: assertion '%s' failed: %s\n", file, line, cond, msg);
    std::fflush(stderr);
    std::abort();
}
}  // namespace detail
}  // namespace sg

#define SG_ASSERT(cond, msg) \
    (static_cast<bool>(cond) ? void(0) : ::sg::detail::assertFailed(__FILE__, __LINE__, #cond, msg))
#else
#define SG_ASSERTS_ENABLED 0
// Unevaluated operand: the condition is still compiled (no stale asserts), its variables count as used.
#define SG_ASSERT(cond, msg) static_cast<void>(sizeof(static_cast<bool>(cond)))
#endif
