#!/usr/bin/env sh
# Installs arbor for C and C++ hosts: headers, the static and shared libraries, a
# pkg-config file and a CMake package config.
#
#   cargo build --release
#   packaging/install.sh /usr/local            # or any prefix; a third argument may name
#                                              # the build directory (default target/release)
#
# Then:  cc app.c $(pkg-config --cflags --libs arbor)
#   or:  find_package(arbor CONFIG REQUIRED)   target_link_libraries(app PRIVATE arbor::arbor)
set -eu
prefix=${1:?usage: install.sh PREFIX [BUILD_DIR]}
root=$(cd "$(dirname "$0")/.." && pwd)
build=${2:-$root/target/release}
version=$(sed -n 's/^version = "\(.*\)"$/\1/p' "$root/Cargo.toml" | head -n 1)

mkdir -p "$prefix/include" "$prefix/lib/pkgconfig" "$prefix/lib/cmake/arbor"
cp "$root/include/arbor.h" "$root/include/arbor.hpp" "$prefix/include/"
cp "$build/libarbor.a" "$build/libarbor.so" "$prefix/lib/"

cat > "$prefix/lib/pkgconfig/arbor.pc" <<PC
prefix=$prefix
includedir=\${prefix}/include
libdir=\${prefix}/lib

Name: arbor
Description: Grow 3-D trees from L-systems and turn them into GPU-ready meshes
Version: $version
Cflags: -I\${includedir}
Libs: -L\${libdir} -larbor
Libs.private: -lpthread -ldl -lm
PC

cat > "$prefix/lib/cmake/arbor/arborConfig.cmake" <<CMAKE
# arbor $version: imported targets arbor::arbor (shared) and arbor::arbor_static.
get_filename_component(_arbor_prefix "\${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET arbor::arbor)
  add_library(arbor::arbor SHARED IMPORTED)
  set_target_properties(arbor::arbor PROPERTIES
    IMPORTED_LOCATION "\${_arbor_prefix}/lib/libarbor.so"
    INTERFACE_INCLUDE_DIRECTORIES "\${_arbor_prefix}/include")
  add_library(arbor::arbor_static STATIC IMPORTED)
  set_target_properties(arbor::arbor_static PROPERTIES
    IMPORTED_LOCATION "\${_arbor_prefix}/lib/libarbor.a"
    INTERFACE_INCLUDE_DIRECTORIES "\${_arbor_prefix}/include"
    INTERFACE_LINK_LIBRARIES "pthread;dl;m")
endif()
set(arbor_VERSION $version)
unset(_arbor_prefix)
CMAKE

cat > "$prefix/lib/cmake/arbor/arborConfigVersion.cmake" <<CMAKE
set(PACKAGE_VERSION $version)
if(PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION)
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
else()
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
endif()
CMAKE
echo "arbor $version installed in $prefix"
