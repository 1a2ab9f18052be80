# The layers of sg/ form a DAG read bottom up (docs/architecture.md): a source may include headers of its own
# layer and of the layers below it only. `build` makes and precomputes content (terrain, LOD levels, light, PVS,
# occluders) from the run-time layers; none of them reads it. Checked at configure time so that a change breaking
# it fails at once.
set(_below_core core)
set(_below_nodes core nodes)
set(_below_style core style)
set(_below_scene core nodes scene)
set(_below_lod core nodes scene lod)
set(_below_cull core nodes scene lod cull)
set(_below_intersect core nodes scene lod style intersect)
set(_below_io io)
set(_below_paging core nodes scene paging)
set(_below_gl core nodes scene lod cull io style gl)
set(_below_viewer core nodes scene lod cull intersect io gl paging style viewer)
set(_below_build core nodes scene lod cull intersect io paging style build)

# Internal headers sit in an internal/ folder of their layer (sg/cull/internal/FrustumKernel.h) or loader
# (loaders/tiles/internal/TileFormats.h): kernels and helpers
# of the traversals, whose shape may change with any release. Not installed (CMakeLists.txt); no public header
# includes one, and neither do the testbed and the examples, which use the library as an application would. (The
# kernel benchmarks in bench/kernels measure them directly.)
function(_sgkit_includes file out)  # the project's includes of sg/, nodes/ and loaders/
  file(STRINGS ${file} _lines REGEX "^#include \"(sg|nodes|loaders)/")
  set(_found)
  foreach(inc IN LISTS _lines)
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" inc "${inc}")
    list(APPEND _found ${inc})
  endforeach()
  set(${out} ${_found} PARENT_SCOPE)
endfunction()

file(GLOB_RECURSE _layered RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} CONFIGURE_DEPENDS
  sg/*.h sg/*.cpp nodes/*.h nodes/*.cpp)
foreach(f IN LISTS _layered)
  if(f MATCHES "^nodes/")
    set(layer nodes)
  else()
    string(REGEX REPLACE "^sg/([^/]+)/.*" "\\1" layer "${f}")
  endif()
  if(NOT DEFINED _below_${layer})
    message(FATAL_ERROR "${f}: sg/${layer} is not a known layer (cmake/LayerCheck.cmake)")
  endif()
  _sgkit_includes(${f} _includes)
  foreach(inc IN LISTS _includes)
    if(inc MATCHES "^loaders/")
      message(FATAL_ERROR "${f} (sg layer ${layer}) includes ${inc}: file formats reach sg/ as load functions")
    elseif(inc MATCHES "^nodes/")
      set(to nodes)
    else()
      string(REGEX REPLACE "^sg/([^/]+)/.*" "\\1" to "${inc}")
    endif()
    if(NOT to IN_LIST _below_${layer})
      message(FATAL_ERROR "${f} (sg layer ${layer}) includes ${inc} (layer ${to}), which is not below it")
    endif()
    if(inc MATCHES "/internal/" AND f MATCHES "\\.h$" AND NOT f MATCHES "/internal/")
      message(FATAL_ERROR "public header ${f} includes the internal header ${inc}")
    endif()
  endforeach()
endforeach()

file(GLOB_RECURSE _apps RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} CONFIGURE_DEPENDS testbed/*.h testbed/*.cpp
  examples/*.h examples/*.cpp)
foreach(f IN LISTS _apps)
  _sgkit_includes(${f} _includes)
  foreach(inc IN LISTS _includes)
    if(inc MATCHES "/internal/")
      message(FATAL_ERROR "${f} includes ${inc}, an internal header (an internal/ folder: see cmake/LayerCheck.cmake)")
    endif()
  endforeach()
endforeach()
