#!/usr/bin/env python3
"""Draws the parameter error and the loss of several `vktg optimize` runs against the iteration,
and the parameter error against the run's wall time (runs compared at equal time), one line per
run, side by side on log axes.
Usage: compare_runs.py OUT.png LABEL=RUN_DIR [LABEL=RUN_DIR ...]"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def columns(log_path):
    with open(log_path) as f:
        rows = list(csv.DictReader(f))
    return {key: [float(r[key]) for r in rows] for key in rows[0]} if rows else {}


def main(out, runs):
    fig, (error_axis, loss_axis, time_axis) = plt.subplots(1, 3, figsize=(16, 4))
    for run in runs:
        label, _, directory = run.partition("=")
        log = columns(f"{directory}/log.csv")
        if not log:
            continue
        if "parameter_error" in log:
            error_axis.plot(log["iteration"], log["parameter_error"], label=label)
            elapsed, total = [], 0.0
            for seconds in log["seconds"]:
                total += seconds
                elapsed.append(total)
            time_axis.plot(elapsed, log["parameter_error"], label=label)
        loss_axis.plot(log["iteration"], [v / log["loss"][0] for v in log["loss"]], label=label)
    error_axis.set(yscale="log", xlabel="iteration", ylabel="parameter error (RMS of θ − truth)")
    loss_axis.set(yscale="log", xlabel="iteration", ylabel="loss / initial loss")
    time_axis.set(yscale="log", xlabel="seconds (wall time of the iterations)", ylabel="parameter error")
    for axis in (error_axis, loss_axis, time_axis):
        axis.grid(True, which="both", alpha=0.3)
        axis.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
