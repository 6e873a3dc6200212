# Run by install.sh in CMake's script mode: writes arborConfig.cmake and
# arborConfigVersion.cmake with CMake's own helpers.
include(CMakePackageConfigHelpers)
set(ARBOR_LIBDIR "lib")
set(ARBOR_INCLUDEDIR "include")
configure_package_config_file(
  "${ARBOR_SOURCE}/packaging/config.cmake.in"
  "${ARBOR_PREFIX}/lib/cmake/arbor/arborConfig.cmake"
  INSTALL_DESTINATION "lib/cmake/arbor"
  INSTALL_PREFIX "${ARBOR_PREFIX}"
  PATH_VARS ARBOR_LIBDIR ARBOR_INCLUDEDIR)
# 0.y releases may change the ABI between minors: only the same minor is compatible.
write_basic_package_version_file(
  "${ARBOR_PREFIX}/lib/cmake/arbor/arborConfigVersion.cmake"
  VERSION "${ARBOR_VERSION}"
  COMPATIBILITY SameMinorVersion)
