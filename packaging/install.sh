#!/usr/bin/env sh
# Installs arbor for C and C++ hosts: headers, the static and shared libraries, a
# pkg-config file and a CMake package config.
#
#   cargo build --release
#   packaging/install.sh /usr/local            # or any prefix; a third argument may name
#                                              # the build directory (default target/release)
#
# Then (a prefix the dynamic loader searches, such as /usr/local, needs `ldconfig` once
# after installing; any other prefix needs -Wl,-rpath,PREFIX/lib or LD_LIBRARY_PATH):
#   shared:  cc app.c $(pkg-config --cflags --libs arbor)
#   static:  cc app.c $(pkg-config --cflags --libs arbor-static)
#   CMake:   find_package(arbor CONFIG REQUIRED)
#            target_link_libraries(app PRIVATE arbor::arbor)   # or arbor::arbor_static
set -eu
prefix=${1:?usage: install.sh PREFIX [BUILD_DIR]}
root=$(cd "$(dirname "$0")/.." && pwd)
build=${2:-$root/target/release}
version=$(sed -n 's/^version = "\(.*\)"$/\1/p' "$root/Cargo.toml" | head -n 1)

major=${version%%.*}
rest=${version#*.}
minor=${rest%%.*}
if [ "$major" = 0 ]; then soname="libarbor.so.0.$minor"; else soname="libarbor.so.$major"; fi
real="libarbor.so.$version"
# The static library's system libraries, as rustc prints them for this platform
# (`cargo rustc --release --lib --crate-type staticlib -- --print native-static-libs`;
# tests/packaging.rs fails when the committed list drifts).
static_libs=$(cat "$root/packaging/native-static-libs.txt")

mkdir -p "$prefix/include" "$prefix/lib/pkgconfig" "$prefix/lib/cmake/arbor" "$prefix/share/arbor"
cp "$root/include/arbor.h" "$root/include/arbor.hpp" "$prefix/include/"
# For hosts that run valgrind on a `parallel` build (its worker threads outlive main).
cp "$root/ffi-tests/valgrind.supp" "$prefix/share/arbor/"
cp "$build/libarbor.a" "$prefix/lib/"
# The archive carries the Rust standard library's debug info and LLVM bitcode (25 MB);
# a host links none of it. Stripped it is about 7 MB.
if command -v strip >/dev/null 2>&1; then
  strip --strip-debug -R .llvmbc -R .llvmcmd "$prefix/lib/libarbor.a"
fi
# The shared library under its full version, with the SONAME and development links.
cp "$build/libarbor.so" "$prefix/lib/$real"
ln -sf "$real" "$prefix/lib/$soname"
ln -sf "$soname" "$prefix/lib/libarbor.so"

cat > "$prefix/lib/pkgconfig/arbor.pc" <<PC
prefix=$prefix
includedir=\${prefix}/include
libdir=\${prefix}/lib

Name: arbor
Description: Grow 3-D trees from L-systems and turn them into GPU-ready meshes
Version: $version
Cflags: -I\${includedir}
Libs: -L\${libdir} -larbor
Libs.private: $static_libs
PC

# Static linking by name: `pkg-config --static --libs arbor` still says -larbor, which a
# linker resolves to the shared library when both are installed; this one names the archive.
cat > "$prefix/lib/pkgconfig/arbor-static.pc" <<PC
prefix=$prefix
includedir=\${prefix}/include
libdir=\${prefix}/lib

Name: arbor-static
Description: arbor, linked statically (libarbor.a and the system libraries it needs)
Version: $version
Cflags: -I\${includedir}
Libs: \${libdir}/libarbor.a $static_libs
PC

if command -v cmake >/dev/null 2>&1; then
  cmake_libs=$(printf '%s' "$static_libs" | sed 's/-l//g; s/ /;/g')
  cmake -DARBOR_SOURCE="$root" -DARBOR_PREFIX="$prefix" -DARBOR_VERSION="$version" \
    -DARBOR_SHARED_REAL="$real" -DARBOR_SONAME="$soname" -DARBOR_STATIC_LIBS="$cmake_libs" \
    -P "$root/packaging/config.cmake"
else
  echo "cmake not found: no CMake package config written" >&2
fi
echo "arbor $version installed in $prefix"
