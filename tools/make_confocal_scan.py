#!/usr/bin/env python3
"""Writes the confocal NLOS scan experiment (experiments/confocal_scan) at any size.

A relay wall at y = 1 m faces a hidden diffuse heightfield (1 m square, centred below it, a bump
and a dent). A laser and a single-pixel time-resolved sensor are focused on the same wall point,
and the scan moves that point over a square grid on the wall; every scan point measures a
transient stack (box bins). The legs from the device to the wall and back are known and taken out
of the data, as confocal NLOS reconstructions do, so each scan point is a point sensor facing the
hidden scene with a point light at the same place. The unknowns are every vertex height.

Usage: make_confocal_scan.py OUT_DIR [--heights N] [--scan M] [--bin-width W] [--iterations K]
  OUT_DIR receives scene.json (the truth), fine_bins.experiment.json and
  coarse_bins.experiment.json (the same scan with bins 4x wider), scan.json (the scan points as a
  scan file: `vktg render OUT_DIR/scene.json --scan OUT_DIR/scan.json --npy` renders the transient cube).
  The repository's copy: --heights 8 --scan 8 (lavapipe size). A GPU-size run:
  --heights 100 --scan 32 (10^4 heights, 1024 transients)."""
import argparse
import json
import math
import os

WALL_Y = 1.0       # relay wall height above the heightfield's base plane (m)
SIZE = 1.0         # side of the hidden heightfield (m)
SCAN_HALF = 0.45   # the scan grid covers [-0.45, 0.45]^2 on the wall (m)
FIRST_BIN = 1.6    # path lengths (m): twice the wall distance minus the bump, with margin
LAST_BIN = 2.6


def true_height(x, z):
    bump = 0.12 * math.exp(-((x - 0.15) ** 2 + (z + 0.1) ** 2) / (2 * 0.15 ** 2))
    dent = 0.08 * math.exp(-((x + 0.2) ** 2 + (z - 0.2) ** 2) / (2 * 0.12 ** 2))
    return bump - dent


def bins_gate(width):
    """A transient stack of box bins of `width` m covering [FIRST_BIN, LAST_BIN]."""
    return {"type": "bins", "start": FIRST_BIN, "width": width, "count": int(round((LAST_BIN - FIRST_BIN) / width))}


def scene(n, bin_width):
    heights = [round(true_height(-SIZE / 2 + SIZE * i / (n - 1), -SIZE / 2 + SIZE * j / (n - 1)), 5)
               for j in range(n) for i in range(n)]
    return heights, {
        "version": 1,
        "description": f"Confocal NLOS scan: a hidden {n} x {n} heightfield ({SIZE:g} m square) below a relay "
                       f"wall at y = {WALL_Y:g} m; the sensor and the laser share one wall point (the heights "
                       "here are the truth)",
        "camera": {"type": "point_sensor", "position": [0, WALL_Y, 0], "normal": [0, -1, 0]},
        "gate": bins_gate(bin_width),
        # One bounce in the hidden scene (sensor -> surface -> laser): 2 segments.
        "render": {"spp": 256, "max_depth": 2},
        "materials": {"hidden": {"type": "diffuse", "albedo": 0.5}},
        "shapes": [{"name": "hidden", "type": "heightfield", "material": "hidden", "resolution": [n, n],
                    "size": [SIZE, SIZE], "heights": heights}],
        "lights": [{"type": "point", "name": "laser", "position": [0, WALL_Y, 0], "intensity": 1.0}],
        "parameters": [{"type": "heightfield_heights", "shape": "hidden", "name_prefix": "h"}],
    }


def scan_grid(scan):
    """The experiment's scan points as a scan file for `vktg render --scan` (the same grid, row by row
    along z, the laser at every point): its image is the scan's transient cube."""
    return {
        "version": 1,
        "description": f"The {scan} x {scan} confocal scan of the relay wall (sensor and laser at each point)",
        "grid": {"corner": [-SCAN_HALF, WALL_Y, -SCAN_HALF], "across": [2 * SCAN_HALF, 0, 0],
                 "down": [0, 0, 2 * SCAN_HALF], "resolution": [scan, scan], "lights": ["laser"]},
    }


def large_steps_lambda(heights):
    n = math.isqrt(len(heights))
    return round(4 * (n - 1) ** 2 / 49)


def experiment(heights, gate, iterations, description):
    # One target per scan point (scan_<column>_<row>), all from scan.json (docs/optimize.md, "Scans").
    target = {"name": "scan", "scan": "scan.json", "image": {"synthesize": {"spp": 8192}}}
    if gate:
        target["gate"] = gate
    return {
        "version": 1,
        "description": description,
        "scene": "scene.json",
        # θ displaces the scene's (true) heights: starting at -truth starts from a flat surface.
        "parameters": [{"name": "h*", "initial": [-h for h in heights], "truth": 0, "range": [-0.5, 0.5]}],
        "targets": [target],
        "loss": {"type": "l2"},
        # Uniform Adam (one normaliser for all heights, docs/optimize.md): per-height Adam gave every
        # height a full step along its own noisy gradient and roughened the 10^4-height surface (0.023 m
        # of 0.035 after 150 iterations at learning rate 0.01 x 0.98^i; uniform at 0.03: 0.0066).
        # A warm-up of 10 steps: Adam's first steps are full-sized whatever the gradient, and the first
        # gradients mostly noise; without it the 10^4-height scan ended 0.0066-0.0148 m from the truth
        # over three seeds, with it 0.0042-0.0071 (docs/experiments.md).
        "optimizer": {"type": "adam", "learning_rate": 0.03, "uniform": True,
                      "schedule": {"type": "exponential", "decay": 0.98, "warmup": 10}},
        "regularizers": [{"type": "laplacian", "shape": "hidden", "weight": 0.05}],
        # Smooth steps (Nicolet et al. 2021): each height's gradient spread over its neighbours.
        # lambda counts in mesh spacings squared; scaling it with the square of the resolution keeps
        # the smoothing length in metres (4 at 8 x 8, the repository's size; 800 at 100 x 100, where
        # lambda = 4 left the 10^4-height scan at 0.033 m of 0.035 after 150 iterations and 800
        # reached 0.023, docs/experiments.md).
        "preconditioner": {"type": "large_steps", "shape": "hidden", "lambda": large_steps_lambda(heights)},
        "render": {"spp": 256, "spp_interior": 256, "spp_edge": 64, "spp_boundary": 256},
        "stop": {"iterations": iterations},
        "checkpoint_every": 10,
        "images_every": 40,
        "seed": 1,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("--heights", type=int, default=8, help="vertices per side of the heightfield")
    parser.add_argument("--scan", type=int, default=8, help="scan points per side of the wall grid")
    parser.add_argument("--bin-width", type=float, default=0.05, help="fine bin width (m)")
    parser.add_argument("--iterations", type=int, default=150)
    args = parser.parse_args()
    if args.heights < 2 or args.scan < 2:
        parser.error("--heights and --scan need at least 2 points per side")
    os.makedirs(args.out, exist_ok=True)
    heights, truth = scene(args.heights, args.bin_width)
    with open(os.path.join(args.out, "scene.json"), "w") as f:
        json.dump(truth, f, indent=1)
    n, m = args.heights, args.scan
    with open(os.path.join(args.out, "scan.json"), "w") as f:
        json.dump(scan_grid(m), f, indent=1)
    coarse = 4 * args.bin_width
    # The scene's gate holds the fine bins; the coarse run gives every target the coarse gate.
    for name, width, gate in (("fine_bins", args.bin_width, None), ("coarse_bins", coarse, bins_gate(coarse))):
        e = experiment(heights, gate, args.iterations,
                       f"Recover {n * n} hidden heights from a {m} x {m} confocal scan, bins of {width:g} m")
        with open(os.path.join(args.out, f"{name}.experiment.json"), "w") as f:
            json.dump(e, f, indent=1)


if __name__ == "__main__":
    main()
