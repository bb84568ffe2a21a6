# Every dependency comes from a Debian 12 package; a missing one stops the configure step
# with the package name, so nobody has to guess what to install.
function(hail_require package debian_package)
  find_package(${package} ${ARGN} QUIET)
  if(NOT ${package}_FOUND)
    message(FATAL_ERROR "hail: ${package} not found. On Debian/Ubuntu install it with:\n"
                        "    sudo apt-get install ${debian_package}\n"
                        "(or run ./scripts/quickstart.sh, which installs every missing package)")
  endif()
endfunction()

hail_require(TBB libtbb-dev CONFIG)
hail_require(xsimd libxsimd-dev CONFIG)
hail_require(Eigen3 libeigen3-dev CONFIG)
if(HAIL_BUILD_TESTS)
  # Debian 12 ships Catch2 v2; v3 is accepted elsewhere (tests/catch.h hides the difference).
  find_package(Catch2 3 CONFIG QUIET)
  if(NOT Catch2_FOUND)
    hail_require(Catch2 catch2 CONFIG)
  endif()
endif()

# Debian 12's xsimd 8.1 config names an optional `xtl` link dependency that no Debian package
# provides, which turns into a failing `-lxtl`. xsimd is header-only and hail uses none of xtl.
if(TARGET xsimd AND NOT TARGET xtl)
  get_target_property(hail_xsimd_links xsimd INTERFACE_LINK_LIBRARIES)
  if(hail_xsimd_links)
    list(REMOVE_ITEM hail_xsimd_links xtl)
    set_target_properties(xsimd PROPERTIES INTERFACE_LINK_LIBRARIES "${hail_xsimd_links}")
  endif()
endif()
