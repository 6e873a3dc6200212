#!/usr/bin/env sh
# Build + mesh speed against a baseline commit, alternating in one run on this machine:
# catches a mesher regression the day it lands (the machine's noise cancels in the ratio).
#
#   benches/regression/run.sh [BASE] [ROUNDS]     (default aa4945f, version 0.1; 3 rounds)
#
# Builds two scratch crates under target/regression/: one against a worktree of BASE, one
# against this checkout, both from main.rs; runs them in turn ROUNDS times and prints
# M triangles/s for each, and the median ratio this checkout / BASE per tree.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
base=${1:-aa4945f}
rounds=${2:-3}
work="$root/target/regression"
mkdir -p "$work"
src="$work/base-src"
if [ ! -d "$src" ] || [ "$(git -C "$src" rev-parse HEAD)" != "$(git -C "$root" rev-parse "$base^{commit}")" ]; then
  rm -rf "$src"
  git -C "$root" worktree prune
  git -C "$root" worktree add --detach "$src" "$base" >/dev/null
fi
crate() { # name, arbor path, adapter
  mkdir -p "$work/$1/src"
  cat > "$work/$1/Cargo.toml" <<TOML
[package]
name = "arbor-regression-$1"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
arbor = { path = "$2" }

[workspace]
TOML
  cp "$root/benches/regression/main.rs" "$work/$1/src/main.rs"
  printf '%s\n' "$3" > "$work/$1/src/adapter.rs"
  (cd "$work/$1" && cargo build --release --quiet)
}
# The 0.1 API (arbor::honda, MeshOptions by struct literal) and today's.
if [ -f "$src/src/honda.rs" ]; then
  old='fn build_mesh(name: char, steps: u32, sides: u32) -> usize {
    let mut p = arbor::honda::HondaParams::preset(name).unwrap();
    p.steps = steps;
    let o = arbor::MeshOptions { radial_segments: sides, ..Default::default() };
    let s = arbor::honda::build(&p).unwrap();
    arbor::mesh::tubes(&s, &o).unwrap().indices.len() / 3
}'
else
  old=""
fi
new='fn build_mesh(name: char, steps: u32, sides: u32) -> usize {
    let mut p = arbor::models::honda::HondaParams::preset(name).unwrap();
    p.steps = steps;
    let o = arbor::mesh::MeshOptions::default().radial_segments(sides);
    let s = arbor::models::honda::build(&p).unwrap();
    arbor::mesh::tubes(&s, &o).unwrap().indices.len() / 3
}'
crate base "$src" "${old:-$new}"
crate head "$root" "$new"
: > "$work/runs.txt"
i=0
while [ "$i" -lt "$rounds" ]; do
  "$work/base/target/release/arbor-regression-base" | sed 's/^/base /' >> "$work/runs.txt"
  "$work/head/target/release/arbor-regression-head" | sed 's/^/head /' >> "$work/runs.txt"
  i=$((i + 1))
done
python3 - "$work/runs.txt" "$base" <<'PY'
import sys, statistics
rows = [l.split() for l in open(sys.argv[1])]
trees = []
for r in rows:
    if r[1] not in trees:
        trees.append(r[1])
print(f"| tree (8 sides, list) | triangles | {sys.argv[2]}: M triangles/s | this checkout | ratio (median of rounds) |")
print("|---|---|---|---|---|")
for t in trees:
    b = [float(r[4]) for r in rows if r[0] == "base" and r[1] == t]
    h = [float(r[4]) for r in rows if r[0] == "head" and r[1] == t]
    tris = next(r[3] for r in rows if r[1] == t)
    ratios = [y / x for x, y in zip(b, h)]
    print(f"| {t} | {tris} | {min(b):.1f}–{max(b):.1f} | {min(h):.1f}–{max(h):.1f} | {statistics.median(ratios):.2f} |")
PY
