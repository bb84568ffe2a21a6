# Install rules of the relocatable CMake package `hail` (included when HAIL_INSTALL is ON, the
# default when hail is the top-level project):
#
#   <prefix>/include/hail/*.h                      the public headers (include/hail/ and the
#                                                  generated version.h), only those
#   <prefix>/lib/libhail.a
#   <prefix>/lib/cmake/hail/hail{Config,ConfigVersion,Targets*}.cmake
#   <prefix>/share/doc/hail/LICENSE
#
# A consumer writes find_package(hail 0.2 CONFIG REQUIRED) and links hail::hail; it gets the
# include directory <prefix>/include (for <hail/world.h>, ...), C++20, and
# oneTBB, xsimd and Eigen through find_dependency (hailConfig.cmake.in). It gets none of hail's
# compile flags: hail_compile_options is linked privately, inside $<BUILD_INTERFACE:>.
#
# Only the `hail` target is exported. Object libraries reach it as $<TARGET_OBJECTS:...> sources,
# so they need no export; anything *linked* to hail must be an imported target found again in
# hailConfig.cmake.in (PUBLIC), or wrapped in $<BUILD_INTERFACE:> (PRIVATE build-only helpers),
# or install(EXPORT) below stops with "requires target ... that is not in any export set".
# scripts/check_package.sh installs, moves and consumes the package.

include(CMakePackageConfigHelpers)

set(hail_install_cmakedir ${CMAKE_INSTALL_LIBDIR}/cmake/hail)
# The folders whose headers make up the library (docs/design.md's layout). bench/ and tests/ are not
# installed; check_package.sh verifies that no installed header includes anything else.

install(TARGETS hail EXPORT hailTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# Only the public headers (include/hail/) are installed; the kernel's internals are not.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/hail/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hail
        FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/include/hail/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hail)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})

install(EXPORT hailTargets NAMESPACE hail:: DESTINATION ${hail_install_cmakedir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/hailConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/hailConfig.cmake
                              INSTALL_DESTINATION ${hail_install_cmakedir})
# Semantic versioning gives no compatibility promise across 0.x minor versions (0.2 may break
# 0.1's API), so while the major version is 0 a request for 0.1 accepts only 0.1.z (z >= the
# requested patch): SameMinorVersion. From 1.0 on, any 1.y satisfies a request for 1.x:
# SameMajorVersion. Not ARCH_INDEPENDENT: libhail.a is built for one pointer size.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(hail_version_compatibility SameMinorVersion)
else()
  set(hail_version_compatibility SameMajorVersion)
endif()
write_basic_package_version_file(${PROJECT_BINARY_DIR}/hailConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION}
                                 COMPATIBILITY ${hail_version_compatibility})
install(FILES ${PROJECT_BINARY_DIR}/hailConfig.cmake ${PROJECT_BINARY_DIR}/hailConfigVersion.cmake
        DESTINATION ${hail_install_cmakedir})
