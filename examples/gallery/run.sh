#!/usr/bin/env sh
# The main job: build arbor and the gallery, then open the window (or, with no display,
# render the 3 x 3 grid to gallery.png under xvfb-run). Extra arguments go to the gallery.
# On a fresh Debian/Ubuntu machine it installs what it needs (GLFW, libpng, a C compiler,
# pkg-config, xvfb) when it may (root, or sudo without a password); otherwise it stops
# with the one command to run.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
cd "$here/../.."

packages="gcc pkg-config libglfw3-dev libpng-dev libgl-dev libgl1-mesa-dri xvfb xauth"
missing=""
command -v cc >/dev/null 2>&1 || missing="yes"
command -v pkg-config >/dev/null 2>&1 || missing="yes"
if [ -z "$missing" ]; then
  pkg-config --exists glfw3 libpng 2>/dev/null || missing="yes"
fi
if [ -z "${DISPLAY:-}" ] && [ -z "${WAYLAND_DISPLAY:-}" ]; then
  command -v xvfb-run >/dev/null 2>&1 || missing="yes"
fi
if [ -n "$missing" ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "installing: $packages"
    DEBIAN_FRONTEND=noninteractive apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $packages
  elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null && command -v apt-get >/dev/null 2>&1; then
    echo "installing: $packages"
    sudo DEBIAN_FRONTEND=noninteractive apt-get update -qq
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $packages
  else
    echo "the gallery needs GLFW, libpng, a C compiler, pkg-config and (without a display) xvfb:" >&2
    echo "  sudo apt-get install $packages" >&2
    exit 1
  fi
fi

cargo build --release --lib
make -s -C "$here" gallery
if [ -n "${DISPLAY:-}" ] || [ -n "${WAYLAND_DISPLAY:-}" ]; then
  exec "$here/gallery" "$@"
else
  echo "no display: rendering to gallery.png with xvfb-run"
  exec xvfb-run -a -s "-screen 0 1280x1280x24" "$here/gallery" --screenshot gallery.png --frames 3 "$@"
fi
