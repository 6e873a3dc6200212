#!/usr/bin/env python3
"""Plots the scale sweep: nanoseconds per internode against internodes, one line per
stage, from criterion's results (run `cargo bench --bench scale` first). Writes
docs/scale.png and prints the table and each stage's largest/smallest cost ratio.

    python3 benches/plot_scale.py        (needs matplotlib: pip install matplotlib)
"""
import json
import pathlib

root = pathlib.Path(__file__).resolve().parent.parent
criterion = root / "target" / "criterion"
stages = ["direct_build", "derive", "interpret", "mesh_write"]
rows = {}
for stage in stages:
    group = criterion / f"scale_{stage}"
    points = []
    for d in group.iterdir() if group.exists() else []:
        est = d / "new" / "estimates.json"
        if d.name.isdigit() and est.exists():
            n = int(d.name)
            median_ns = json.loads(est.read_text())["median"]["point_estimate"]
            points.append((n, median_ns / n))
    rows[stage] = sorted(points)

print("| stage | " + " | ".join(f"{n:,}" for n, _ in rows[stages[0]]) + " | largest / smallest |")
print("|---|" + "---|" * (len(rows[stages[0]]) + 1))
for stage in stages:
    costs = [c for _, c in rows[stage]]
    if not costs:
        continue
    ratio = costs[-1] / costs[0]
    print(f"| {stage} | " + " | ".join(f"{c:.1f}" for c in costs) + f" | {ratio:.2f} |")

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, ax = plt.subplots(figsize=(7, 4.2), dpi=110)
for stage in stages:
    if rows[stage]:
        xs, ys = zip(*rows[stage])
        ax.plot(xs, ys, marker="o", label=stage.replace("_", " "))
ax.set_xscale("log")
ax.set_xlabel("internodes (1996 tree a, n = 10 … 22)")
ax.set_ylabel("ns per internode (median)")
ax.set_ylim(bottom=0)
ax.set_title("arbor: cost per internode stays flat as trees grow")
ax.grid(True, which="both", alpha=0.3)
ax.legend()
fig.tight_layout()
out = root / "docs" / "scale.png"
fig.savefig(out)
print(f"wrote {out}")
