# The layers of sg/ form a DAG read bottom up (docs/architecture.md): a source may include headers of its own
# layer and of the layers below it only. Checked at configure time so that a change breaking it fails at once.
set(_below_core core)
set(_below_nodes core nodes)
set(_below_scene core nodes scene)
set(_below_lod core nodes scene intersect lod)
set(_below_cull core nodes scene lod cull)
set(_below_intersect core nodes scene intersect)
set(_below_io io)
set(_below_paging core nodes scene paging)
set(_below_gl core nodes scene lod cull io gl)
set(_below_viewer core nodes scene intersect lod cull io gl paging viewer)
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
  file(STRINGS ${f} _includes REGEX "^#include \"(sg/[^/]+|nodes)/")
  foreach(inc IN LISTS _includes)
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" inc "${inc}")
    if(inc MATCHES "^nodes/")
      set(to nodes)
    else()
      string(REGEX REPLACE "^sg/([^/]+)/.*" "\\1" to "${inc}")
    endif()
    if(NOT to IN_LIST _below_${layer})
      message(FATAL_ERROR "${f} (sg layer ${layer}) includes ${inc} (layer ${to}), which is not below it")
    endif()
  endforeach()
endforeach()

# Internal headers: kernels and helpers of the traversals, whose shape may change with any release. Not
# installed; a public header must not include one (CMakeLists.txt), and neither may the testbed or the examples,
# which use the library as an application would. (The kernel benchmarks in bench/kernels measure them directly.)
set(SGKIT_INTERNAL_HEADERS sg/viewer/StageThread.h sg/cull/FrustumKernel.h sg/cull/CullContext.h sg/scene/BspBuilder.h sg/scene/LodChooser.h
  sg/scene/ImageWalk.h sg/intersect/IntersectPrimitives.h sg/gl/GlProgram.h sg/gl/Shaders.h sg/gl/GpuCache.h
  sg/gl/DepthTarget.h sg/core/MeshClosed.h sg/gl/BackFaces.h sg/scene/DistinctGeometries.h sg/scene/OccluderShapes.h
  sg/scene/MeshOccludersParts.h)

# The testbed and the examples use the library as an application would: none of them includes an internal header.
file(GLOB_RECURSE _apps RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} CONFIGURE_DEPENDS testbed/*.h testbed/*.cpp
  examples/*.h examples/*.cpp)
foreach(f IN LISTS _apps)
  file(STRINGS ${f} _includes REGEX "^#include \"sg/")
  foreach(inc IN LISTS _includes)
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" inc "${inc}")
    if(inc IN_LIST SGKIT_INTERNAL_HEADERS)
      message(FATAL_ERROR "${f} includes ${inc}, an internal header (SGKIT_INTERNAL_HEADERS in cmake/LayerCheck.cmake)")
    endif()
  endforeach()
endforeach()
