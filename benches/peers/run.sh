#!/usr/bin/env sh
# Peers side by side, on this machine and in this run: builds a scratch crate under
# target/peers/ that depends on arbor (this checkout) and on the L-system crates symbios
# and dcc-lsystem from crates.io, and prints a table of modules per second (median of 7
# runs) with arbor's ratio to each peer. Nothing of the peers is committed.
#
#   benches/peers/run.sh
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
work="$root/target/peers/rust"
mkdir -p "$work/src"
cat > "$work/Cargo.toml" <<TOML
[package]
name = "arbor-peers"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
arbor = { path = "$root" }
symbios = "=1.5.1"
dcc-lsystem = "=0.6.3"

[profile.release]
debug = false

[workspace]
TOML
cp "$root/benches/peers/main.rs" "$work/src/main.rs"
cd "$work"
cargo run --release --quiet

# Mesh generators in JavaScript, if Node and npm are installed.
if command -v npm >/dev/null 2>&1; then
  node_dir="$root/target/peers/node"
  mkdir -p "$node_dir"
  cp "$root/benches/peers/ez-tree.mjs" "$node_dir/"
  (cd "$node_dir" && npm install --silent --no-audit --no-fund @dgreenheck/ez-tree@1.1.0 three@0.170.0 >/dev/null)
  echo
  echo "| mesh generator | bark triangles | vertices | M triangles/s |"
  echo "|---|---|---|---|"
  (cd "$node_dir" && node ez-tree.mjs)
  # The three.js tree generator ships in `three` itself from 0.187 on; ez-tree pins an
  # older three, so it gets a directory of its own.
  three_dir="$root/target/peers/three"
  mkdir -p "$three_dir"
  cp "$root/benches/peers/three-tree.mjs" "$three_dir/"
  (cd "$three_dir" && npm install --silent --no-audit --no-fund three@0.187.0 >/dev/null)
  (cd "$three_dir" && node three-tree.mjs)
  (cd "$work" && cargo run --release --quiet -- mesh)
fi
