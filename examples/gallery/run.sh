#!/usr/bin/env sh
# The main job: build arbor and the gallery, then open the window (or, with no display,
# render the 3 x 3 grid to gallery.png under xvfb-run). Extra arguments go to the gallery.
# On a fresh Debian/Ubuntu machine it installs what it needs (GLFW, libpng, a C compiler,
# pkg-config, xvfb) when it may (root, or sudo without a password); otherwise it stops
# with the one command to run.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
cd "$here/../.."

# What it needs (tools/deps.txt, group gallery): installed when it may (root, or sudo
# without a password), otherwise it stops with the one line to run.
"$here/../../tools/deps" gallery

cargo build --release --lib
make -s -C "$here" gallery
if [ -n "${DISPLAY:-}" ] || [ -n "${WAYLAND_DISPLAY:-}" ]; then
  exec "$here/gallery" "$@"
else
  echo "no display: rendering to gallery.png with xvfb-run"
  exec xvfb-run -a -s "-screen 0 1280x1280x24" "$here/gallery" --screenshot gallery.png --frames 3 "$@"
fi
