#!/usr/bin/env python3
"""Run time against error, one PNG per scene CSV of bench_accuracy (log-log, one curve per
method and integrator/solver, blown-up runs left out, the Pareto front of the scene marked).

Usage: plot_accuracy.py OUTDIR   (reads OUTDIR/<scene>.csv, writes OUTDIR/<scene>.png)
"""
import csv
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = ["scene", "method", "integrator_or_solver", "step", "iterations", "substeps", "threads",
           "wall_seconds", "steps", "error", "blew_up"]
FLOOR = 1e-16  # an exact answer (free fall with Verlet) is drawn at rounding level


def plot(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or list(rows[0].keys()) != COLUMNS:
        return None
    scene = rows[0]["scene"]
    curves = {}
    points = []
    for r in rows:
        if r["blew_up"] == "yes" or r["threads"] != "1":
            continue
        wall = max(float(r["wall_seconds"]), 1e-6)
        err = max(float(r["error"]), FLOOR)
        key = r["method"] + " " + r["integrator_or_solver"]
        if int(r["substeps"]) > 0:
            key += " (budget %d)" % (int(r["iterations"]) * int(r["substeps"]))
        curves.setdefault(key, []).append((wall, err))
        points.append((wall, err, key))
    if not points:
        return None
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for key, pts in sorted(curves.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=4, lw=1, label=key)
    # Pareto front: no other run is both faster and more accurate.
    front = []
    best = float("inf")
    for wall, err, _ in sorted(points):
        if err < best:
            front.append((wall, err))
            best = err
    ax.plot([p[0] for p in front], [p[1] for p in front], "k--", lw=2, label="Pareto front")
    ax.scatter([p[0] for p in front], [p[1] for p in front], s=90, facecolors="none",
               edgecolors="k", zorder=5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time [s] (1 thread; noisy shared 2-core VM)")
    ax.set_ylabel("relative error")
    ax.set_title("%s: run time against error" % scene)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2, loc="best")
    fig.tight_layout()
    png = os.path.splitext(path)[0] + ".png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    made = [p for p in (plot(c) for c in sorted(glob.glob(os.path.join(sys.argv[1], "*.csv")))) if p]
    for p in made:
        print("wrote", p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
