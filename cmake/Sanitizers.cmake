# SGKIT_SANITIZE=ON builds everything with AddressSanitizer and UndefinedBehaviorSanitizer (CI runs the
# suite this way too); UBSan findings abort so that a test fails on them. SGKIT_SANITIZE=thread builds
# with ThreadSanitizer instead (it cannot be combined with AddressSanitizer): CI runs the threaded tests so.
# ON also keeps the internal invariant checks (sg/core/Assert.h) on in that optimised build (NDEBUG).
# Both build at -O1 with line tables only (-g1): reports keep their file:line stacks, and the build takes
# half the time of -O2 -g (the suite is compiled twice more in CI).
set(SGKIT_SANITIZE OFF CACHE STRING "Sanitizers: OFF, ON (address + undefined) or thread")
set_property(CACHE SGKIT_SANITIZE PROPERTY STRINGS OFF ON thread)
string(TOLOWER "${SGKIT_SANITIZE}" _sgkit_sanitize)
if(_sgkit_sanitize STREQUAL "thread")
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # GCC's target_clones resolvers (the frustum kernel) run before the TSan runtime is up and crash.
    message(WARNING "SGKIT_SANITIZE=thread: build with clang (CC=clang CXX=clang++); GCC builds crash at startup")
  endif()
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer -O1 -g1)
  add_link_options(-fsanitize=thread)
elseif(_sgkit_sanitize MATCHES "^(on|yes|true|y|1)$")
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -O1 -g1)
  add_link_options(-fsanitize=address,undefined)
  add_compile_definitions(SGKIT_ASSERTS SGKIT_SANITIZED)  # SANITIZED: the tests run fewer cases (tests/Scaled.h)
elseif(NOT _sgkit_sanitize MATCHES "^(off|no|false|n|0|)$")
  message(FATAL_ERROR "SGKIT_SANITIZE=${SGKIT_SANITIZE}: expected OFF, ON (address + undefined) or thread")
endif()
