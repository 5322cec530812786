#!/usr/bin/env python3
"""Plots relMSE versus time per (scene, gate) from a `vktg bench render` CSV: one panel per
case, one line per estimator, log-log. Usage: plot_bench.py bench.csv plot.png"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    series = defaultdict(lambda: defaultdict(list))
    with open(csv_path) as f:
        for row in csv.DictReader(f):
            case = f"{row['scene']}: {row['gate']}"
            series[case][row["estimator"]].append((float(row["seconds"]), float(row["relmse"])))
    cases = sorted(series)
    cols = 4
    rows = (len(cases) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 3.2 * rows), squeeze=False)
    for ax, case in zip(axes.flat, cases):
        for estimator, points in sorted(series[case].items()):
            points.sort()
            ax.loglog([p[0] for p in points], [max(p[1], 1e-12) for p in points], "o-", label=estimator)
        ax.set_title(case, fontsize=9)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("relMSE")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    for ax in list(axes.flat)[len(cases):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
