#!/usr/bin/env bash
# Builds arbor's native library for the Unity package and copies it into
# Runtime/Plugins/<platform>/, beside the committed .meta import settings (the binaries
# themselves are not committed: .gitignore).
#
#   bindings/unity/build-plugins.sh                 # this machine's platform
#   bindings/unity/build-plugins.sh linux windows   # any of: linux windows macos
#
# linux:   x86_64 libarbor.so (on Linux).
# windows: x86_64 arbor.dll: on Windows with the MSVC toolchain; on Linux cross-built with
#          mingw-w64 (apt-get install gcc-mingw-w64-x86-64; rustup target add
#          x86_64-pc-windows-gnu; this script adds the target itself).
# macos:   a universal (x86_64 + arm64) libarbor.dylib, on a Mac with Xcode's command-line
#          tools (Apple's SDK cannot be redistributed, so there is no cross-build).
# CARGO_TARGET_DIR is honoured.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
target_dir=${CARGO_TARGET_DIR:-$root/target}
plugins="$here/Runtime/Plugins"
host=$(uname -s)

if [ $# -eq 0 ]; then
  case "$host" in
    Linux) set -- linux ;;
    Darwin) set -- macos ;;
    MINGW* | MSYS* | CYGWIN*) set -- windows ;;
    *) echo "unknown platform $host: name one of linux windows macos" >&2; exit 2 ;;
  esac
fi

build() { # target
  (cd "$root" && cargo build --release --lib --no-default-features --target "$1")
}

for platform in "$@"; do
  case "$platform" in
    linux)
      [ "$host" = Linux ] || { echo "linux: build on Linux" >&2; exit 1; }
      build x86_64-unknown-linux-gnu
      cp "$target_dir/x86_64-unknown-linux-gnu/release/libarbor.so" "$plugins/Linux/x86_64/libarbor.so"
      ;;
    windows)
      case "$host" in
        MINGW* | MSYS* | CYGWIN*) triple=x86_64-pc-windows-msvc ;;
        *)
          triple=x86_64-pc-windows-gnu
          command -v x86_64-w64-mingw32-gcc >/dev/null 2>&1 || {
            echo "windows: the cross-build needs mingw-w64: sudo apt-get install gcc-mingw-w64-x86-64" >&2
            exit 1
          }
          rustup target list --installed | grep -qx "$triple" || rustup target add "$triple"
          export CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER=x86_64-w64-mingw32-gcc
          ;;
      esac
      build "$triple"
      cp "$target_dir/$triple/release/arbor.dll" "$plugins/Windows/x86_64/arbor.dll"
      ;;
    macos)
      [ "$host" = Darwin ] || {
        echo "macos: build on a Mac (Apple's SDK is needed; no cross-build)" >&2
        exit 1
      }
      for t in x86_64-apple-darwin aarch64-apple-darwin; do
        rustup target list --installed | grep -qx "$t" || rustup target add "$t"
        build "$t"
      done
      lipo -create -output "$plugins/macOS/libarbor.dylib" \
        "$target_dir/x86_64-apple-darwin/release/libarbor.dylib" \
        "$target_dir/aarch64-apple-darwin/release/libarbor.dylib"
      ;;
    *) echo "unknown platform $platform: one of linux windows macos" >&2; exit 2 ;;
  esac
  echo "built the $platform plugin into $plugins"
done
