"""Draws bench_error_control's CSV: the achieved error over what the tolerance allows over the
run (tolerance x simulated time; the line at 1 is the allowance) against the tolerance, and the cost against the best fixed step against the tolerance, one line per
scene, integrator and judge (embedded estimate or step doubling).

Run with pvpython (matplotlib ships with Debian's ParaView packages):
    pvpython tests/bench/plot_error_control.py error_control.csv error_control.png
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    # (scene, integrator, judge) -> tolerance, error over the allowance, cost ratio
    series = defaultdict(lambda: ([], [], []))
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            tolerance, error, ratio = series[(row["scene"], row["integrator"], row["judge"])]
            tolerance.append(float(row["tolerance"]))
            error.append(float(row["achieved_error"]) / float(row["allowed_error"]))
            ratio.append(float(row["cost_ratio"]))
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.8))
    left.axhline(1.0, color="black", linestyle="--", label="the allowance")
    # One colour per scene and integrator; the judge is the line style (more series than one
    # colour cycle holds).
    colours = {}
    for (scene, integrator, judge), (tolerance, error, ratio) in sorted(series.items()):
        label = f"{integrator} ({judge}), {scene}"
        colour = colours.setdefault((scene, integrator), f"C{len(colours) % 10}")
        style = dict(color=colour, marker="o" if scene == sorted({k[0] for k in series})[0] else "s",
                     linestyle="-" if judge == "embedded" else "--", label=label)
        left.loglog(tolerance, error, **style)
        right.loglog(tolerance, ratio, **style)
    left.set(title="achieved error over the allowance", xlabel="ErrorTolerance [m per s]",
             ylabel="largest error over the frames / (tolerance x simulated time)")
    right.axhline(1.0, color="black", linestyle="--")
    right.set(title="cost against the best fixed step in hindsight", xlabel="ErrorTolerance [m per s]",
              ylabel="wall time / best fixed step's")
    for ax in (left, right):
        ax.grid(True, which="both", alpha=0.3)
    right.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
