#!/usr/bin/env sh
# Copies the native library cargo built into the package's Runtime/Plugins folder (the
# .meta import settings are committed; the binaries are not).
#   cargo build --release && bindings/unity/build-plugins.sh
set -eu
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../../target/release}
for f in libarbor.so:Linux/x86_64 arbor.dll:Windows/x86_64 libarbor.dylib:macOS; do
  name=${f%%:*}
  dir=${f#*:}
  if [ -f "$build/$name" ]; then
    cp "$build/$name" "$here/Runtime/Plugins/$dir/$name"
    echo "copied $name to Runtime/Plugins/$dir"
  fi
done
