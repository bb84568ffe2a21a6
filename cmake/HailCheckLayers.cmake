# The layers of hail's own code, and a check that none includes a layer above it.
#
# Lowest first; a file may include files of its own layer and of the layers before it:
#
#   public     include/hail/ (the installed API: includes only include/hail/), soa/
#   jobs       jobs/: parallel blocks, the stage crew, phase timing (no physics)
#   files      kernel/files/: what hail may open and how much of it it reads (no physics)
#   dispatch   kernel/dispatch/: SIMD path detection and the kernel table
#   geometry   kernel/geometry/: boxes, Morton codes, sphere-triangle and ray-triangle tests
#   bvh        kernel/bvh/: the flat BVH, its build and its walks
#   broadphase kernel/broadphase/: sphere-sphere pair searches and the Morton re-sort
#   terrain    kernel/terrain/: heightmaps, terrain triangles and contacts, planes
#   mesh       kernel/mesh/: triangle meshes, their files, colliders and contacts
#   solver     kernel/solver/: impulses, colouring, SIMD batches, shock propagation, integration
#   ccd        kernel/ccd/: continuous collision of fast spheres
#   simd       kernel/simd/: the per-path SIMD kernels of all the layers above
#   world      kernel/world/, include/hail/world.h and hail.h: World and its step pipeline
#
# examples/ may include the public headers only. python/ (the Python module) is a top layer, as
# bench/ and view/ are: it may include the public headers and scenes/, never soa/, jobs/ or
# kernel/ (an embedder's view of hail: the bindings use only what the API promises). Included
# from the top-level CMakeLists.txt, it adds the check to every build (target hail_layers: a
# wrong include fails the build) and, in script mode, checks the tree at -DHAIL_LAYER_ROOT=<dir>
# (tests/CMakeLists.txt also runs it on tests/layering/, a tree with an upward include, which it
# must refuse).

set(hail_layer_names public jobs files dispatch geometry bvh broadphase terrain mesh solver ccd simd world)

# Layer index of a repository-relative path, or -1 when it is not in a layer.
function(hail_layer_of path out)
  set(layer -1)
  if(path STREQUAL "include/hail/world.h" OR path STREQUAL "include/hail/hail.h" OR path MATCHES "^kernel/world/")
    list(FIND hail_layer_names world layer)
  elseif(path MATCHES "^(include/hail|soa)/")
    set(layer 0)
  elseif(path MATCHES "^jobs/")
    set(layer 1)
  elseif(path MATCHES "^kernel/([a-z_]+)/")
    list(FIND hail_layer_names "${CMAKE_MATCH_1}" layer)
  endif()
  set(${out} ${layer} PARENT_SCOPE)
endfunction()

function(hail_check_layers root)
  file(GLOB_RECURSE files RELATIVE ${root} ${root}/include/hail/*.h ${root}/soa/*.h ${root}/soa/*.cpp
       ${root}/jobs/*.h ${root}/kernel/*.h ${root}/kernel/*.cpp ${root}/examples/*.cpp ${root}/examples/*.h
       ${root}/python/*.cpp ${root}/python/*.h)
  set(errors "")
  foreach(file IN LISTS files)
    hail_layer_of(${file} layer)
    if(layer EQUAL -1 AND NOT file MATCHES "^(examples|python)/")
      string(APPEND errors "  ${file}: in no layer (add its folder to cmake/HailCheckLayers.cmake)\n")
      continue()
    endif()
    file(STRINGS ${root}/${file} lines REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
    foreach(line IN LISTS lines)
      if(NOT line MATCHES "#[ \t]*include[ \t]*[<\"]([^>\"]+)[>\"]")
        continue()
      endif()
      set(target ${CMAKE_MATCH_1})
      if(target MATCHES "^hail/")
        set(target "include/${target}")
      elseif(NOT target MATCHES "^(soa|jobs|kernel)/")
        continue()  # a standard or third-party header
      endif()
      hail_layer_of(${target} target_layer)
      if(file MATCHES "^(include/hail|examples|python)/" AND NOT target MATCHES "^include/hail/")
        string(APPEND errors "  ${file}: includes ${target}, not a public header (include/hail/)\n")
      elseif(file MATCHES "^(examples|python)/")
        continue()  # a program using the API: any public header (scenes/ is not checked here)
      elseif(target_layer EQUAL -1)
        string(APPEND errors "  ${file}: includes ${target}, which is in no layer\n")
      elseif(target_layer GREATER layer)
        list(GET hail_layer_names ${layer} from)
        list(GET hail_layer_names ${target_layer} to)
        string(APPEND errors "  ${file} (${from}) includes ${target} (${to}), a layer above it\n")
      endif()
    endforeach()
  endforeach()
  if(errors)
    message(FATAL_ERROR "hail: includes that break the layers (cmake/HailCheckLayers.cmake):\n${errors}")
  endif()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE)
  hail_check_layers(${HAIL_LAYER_ROOT})
else()
  file(GLOB_RECURSE hail_layered_files CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/include/hail/*.h
       ${PROJECT_SOURCE_DIR}/soa/* ${PROJECT_SOURCE_DIR}/jobs/* ${PROJECT_SOURCE_DIR}/kernel/*.h
       ${PROJECT_SOURCE_DIR}/kernel/*.cpp ${PROJECT_SOURCE_DIR}/examples/*.cpp ${PROJECT_SOURCE_DIR}/python/*.cpp
       ${PROJECT_SOURCE_DIR}/python/*.h)
  add_custom_command(OUTPUT ${PROJECT_BINARY_DIR}/hail_layers.stamp
    COMMAND ${CMAKE_COMMAND} -DHAIL_LAYER_ROOT=${PROJECT_SOURCE_DIR} -P ${CMAKE_CURRENT_LIST_FILE}
    COMMAND ${CMAKE_COMMAND} -E touch ${PROJECT_BINARY_DIR}/hail_layers.stamp
    DEPENDS ${hail_layered_files} ${CMAKE_CURRENT_LIST_FILE}
    COMMENT "Checking that no include points up a layer"
    VERBATIM)
  add_custom_target(hail_layers ALL DEPENDS ${PROJECT_BINARY_DIR}/hail_layers.stamp)
  add_dependencies(hail hail_layers)
endif()
