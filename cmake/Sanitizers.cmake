# SGKIT_SANITIZE=ON builds everything with AddressSanitizer and UndefinedBehaviorSanitizer (CI runs the
# suite this way too); UBSan findings abort so that a test fails on them. SGKIT_ASSERTS keeps the internal
# invariant checks (sg/core/Assert.h) on in this optimised build, which defines NDEBUG.
option(SGKIT_SANITIZE "Build with AddressSanitizer + UndefinedBehaviorSanitizer" OFF)
if(SGKIT_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g)
  add_link_options(-fsanitize=address,undefined)
  add_compile_definitions(SGKIT_ASSERTS)
endif()
