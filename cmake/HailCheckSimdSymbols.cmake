# cmake -DNM=nm -DOBJECTS="a.o|b.o|..." [-DSTAMP=file] -P HailCheckSimdSymbols.cmake
#
# The check of cmake/HailSimdPaths.cmake. Objects named <name>.<path>.cpp.o hold one SIMD path's
# code (kernel/simd/, compiled with that path's -march); the others are the base. A weak symbol
# (an inline function or template instance that several objects may define, the linker keeping
# one) in a path's object is only safe when no object built with other flags defines it too:
#   1. it must name the path's own namespace (hail::simd_<path>, kernel/dispatch/simd_arch.h) or its own
#      xsimd architecture (xsimd::sse4_2, xsimd::avx2, xsimd::avx512bw), so that code outside
#      hail cannot define it either, and
#   2. no object of another path or of the base may define it.
# Anything else (a std::vector method, std::sort, an Eigen or hail inline helper the compiler
# did not inline) could be the copy every caller gets: AVX-512 instructions on an AVX2 CPU.
string(REPLACE "|" ";" objects "${OBJECTS}")
# Marks of the mangled names: the namespace hail::simd_<path>, and xsimd's architecture type as
# the last part of a nested name (5xsimd4avx2E, or NS_4avx2E once "xsimd" was substituted).
set(own_sse4_2 "4hail11simd_sse4_2" "6sse4_2E")
set(own_avx2 "4hail9simd_avx2" "4avx2E")
set(own_avx512 "4hail11simd_avx512" "8avx512bwE")
set(problems "")
set(path_objects 0)
set(weak_seen 0)
foreach(object IN LISTS objects)
  if(object MATCHES "\\.(sse4_2|avx2|avx512)\\.cpp\\.o(bj)?$")
    set(kind ${CMAKE_MATCH_1})
    math(EXPR path_objects "${path_objects} + 1")
  else()
    set(kind base)
  endif()
  execute_process(COMMAND ${NM} --defined-only ${object} OUTPUT_VARIABLE listing RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "hail: ${NM} failed on ${object}: ${err}")
  endif()
  string(REPLACE "\n" ";" lines "${listing}")
  foreach(line IN LISTS lines)
    if(NOT line MATCHES "^[0-9a-fA-F]* *([WVu]) (.+)$")
      continue()
    endif()
    set(symbol "${CMAKE_MATCH_2}")
    if(symbol MATCHES "^DW\\.ref\\.")
      continue()  # a data word holding an address (the C++ personality routine): the same in every object
    endif()
    string(MAKE_C_IDENTIFIER "${symbol}" key)
    list(APPEND kinds_${key} ${kind})
    list(REMOVE_DUPLICATES kinds_${key})
    set(name_${key} "${symbol}")
    list(APPEND all_keys ${key})
    if(NOT kind STREQUAL "base")
      math(EXPR weak_seen "${weak_seen} + 1")
      set(owned FALSE)
      foreach(mark IN LISTS own_${kind})
        string(FIND "${symbol}" "${mark}" at)
        if(at GREATER_EQUAL 0)
          set(owned TRUE)
        endif()
      endforeach()
      if(NOT owned)
        get_filename_component(object_name ${object} NAME)
        list(APPEND problems "${object_name}: weak symbol outside the ${kind} path's namespace: ${symbol}")
      endif()
    endif()
  endforeach()
endforeach()
if(path_objects EQUAL 0)
  message(FATAL_ERROR "hail: no per-path SIMD objects among the objects given: is the naming of cmake/HailSimdPaths.cmake still <name>.<path>.cpp?")
endif()
if(all_keys)
  list(REMOVE_DUPLICATES all_keys)
endif()
foreach(key IN LISTS all_keys)
  list(LENGTH kinds_${key} count)
  if(count GREATER 1)
    list(JOIN kinds_${key} ", " where)
    list(APPEND problems "defined with different flags (${where}): ${name_${key}}")
  endif()
endforeach()
if(problems)
  list(JOIN problems "\n  " text)
  message(FATAL_ERROR "hail: SIMD code that the linker could merge across paths (see kernel/dispatch/simd_arch.h; "
                      "demangle with c++filt):\n  ${text}")
endif()
message(STATUS "hail: ${path_objects} per-path SIMD objects; their ${weak_seen} weak symbols all lie in their own path's namespace")
if(STAMP)
  file(TOUCH ${STAMP})
endif()
