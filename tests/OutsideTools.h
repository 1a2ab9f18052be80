// A test that needs something from outside the project (an npm tool, the map's source data, a model package,
// xvfb-run) skips without it, saying how to get it; where SGKIT_REQUIRE_OUTSIDE is set (.ci/run sets it) it fails
// instead: there, a check that did not run is a failure, not a pass.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace testutil {
// node_modules holding the npm tools (gltf-validator, three): $SGKIT_NPM_MODULES, else the build's (the tiles-tools
// target); empty when neither says.
inline std::filesystem::path npmModules() {
    if (const char* e = std::getenv("SGKIT_NPM_MODULES")) return e;
#ifdef SGKIT_NPM_MODULES
    return SGKIT_NPM_MODULES;
#else
    return {};
#endif
}

inline bool outsideRequired() {
    const char* v = std::getenv("SGKIT_REQUIRE_OUTSIDE");
    return v && *v && std::strcmp(v, "0") != 0;
}
}  // namespace testutil

// SG_SKIP_OR_FAIL(a << b): GTEST_SKIP() << a << b, or FAIL() with the same message where outside tools are required.
#define SG_SKIP_OR_FAIL(message)                                                         \
    do {                                                                                 \
        if (::testutil::outsideRequired()) {                                             \
            FAIL() << message << " [SGKIT_REQUIRE_OUTSIDE is set: it is required here]"; \
        } else {                                                                         \
            GTEST_SKIP() << message;                                                     \
        }                                                                                \
    } while (0)
