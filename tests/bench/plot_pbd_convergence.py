"""Draws bench_pbd's convergence CSV as the PBD thesis's Figures 5.3 and 5.4: the residual
against the iteration count and against the solver's time, one panel pair per cloth.

Run with pvpython (matplotlib ships with Debian's ParaView packages):
    pvpython tests/bench/plot_pbd_convergence.py bench_pbd_convergence.csv pbd_convergence.png
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    series = defaultdict(lambda: ([], [], []))  # (cloth, label) -> iterations, residuals, seconds
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            label = f"{row['solver']} ({row['threads']} thr)"
            it, res, sec = series[(row["cloth"], label)]
            it.append(int(row["iteration"]))
            res.append(float(row["residual"]))
            sec.append(1e3 * float(row["seconds"]))
    cloths = sorted({cloth for cloth, _ in series}, key=lambda c: int(c.split("x")[0]))
    fig, axes = plt.subplots(len(cloths), 2, figsize=(12, 4.5 * len(cloths)), squeeze=False)
    for row, cloth in enumerate(cloths):
        for (c, label), (it, res, sec) in sorted(series.items()):
            if c != cloth:
                continue
            axes[row][0].semilogy(it, res, label=label)
            axes[row][1].semilogy(sec, res, label=label)
        axes[row][0].set(title=f"{cloth} cloth stretched 16x: residual per iteration",
                         xlabel="iteration", ylabel="residual [m]")
        axes[row][1].set(title=f"{cloth} cloth: residual against solver time",
                         xlabel="time [ms]", ylabel="residual [m]")
        for ax in axes[row]:
            ax.grid(True, which="both", alpha=0.3)
        axes[row][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png_path, dpi=100)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_pbd_convergence.py <bench_pbd_convergence.csv> <out.png>")
    main(sys.argv[1], sys.argv[2])
