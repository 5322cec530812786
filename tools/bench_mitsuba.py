#!/usr/bin/env python3
"""Equal-time comparison of vktg against Mitsuba 3's LLVM backend with mitransient on one scene.

Both renderers render the same scene (translated from vktg's JSON: rectangles, cubes, diffuse
materials, area emitters, a perspective camera) under the same gates at the same resolution,
samples per pixel and longest path (segments), several times with independent seeds. Per renderer
and gate it reports the median render time and the measured relMSE of one render: the across-seed
variance of each pixel over the pooled mean, relMSE = mean_p var_p / (m_p^2 + 0.01 mean(m)^2)
(vktg's bench formula; both renderers are unbiased, so no reference is needed), and their product.
The image means must agree within their noise, which checks the translation.

Gates: a box [a, b] is one bin of mitransient's transient film; a gaussian (mu, sigma) is a stack
of bins sigma/4 wide over mu +- 4 sigma, each weighted by the gaussian at its centre (mitransient
1.3 films only box-filter time), rendered in the same pass.

Usage: bench_mitsuba.py VKTG SCENE.json OUTDIR [--spp N] [--runs R] [--resolution WxH] [--max-depth D]
Run through tools/bench-mitsuba, which installs Mitsuba and mitransient into a virtual environment.
"""
import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np


def fail(message):
    sys.exit(f"bench_mitsuba: {message}")


def transform_of(mi, t):
    """vktg's p_world = T Rz Ry Rx S p (docs/scene-format.md) as a Mitsuba transform."""
    scale = t.get("scale", 1)
    scale = [scale] * 3 if isinstance(scale, (int, float)) else scale
    ax, ay, az = t.get("rotate", [0, 0, 0])
    m = mi.ScalarTransform4f().translate(t.get("translate", [0, 0, 0]))
    m = m.rotate([0, 0, 1], az).rotate([0, 1, 0], ay).rotate([1, 0, 0], ax)
    return m.scale(scale)


def mitsuba_scene(mi, scene, resolution, max_depth, start, width, bins):
    camera = scene["camera"]
    if camera.get("type", "perspective") != "perspective":
        fail("only perspective cameras are translated")
    out = {
        "type": "scene",
        "integrator": {"type": "transient_path", "max_depth": max_depth, "rr_depth": 4},
        "sensor": {
            # Mitsuba starts camera rays near_clip along the ray and mitransient counts the path
            # length from there: the default 1 cm would shift every gate by 1 cm.
            "type": "perspective", "fov_axis": "y", "fov": camera.get("fov_y", 40), "near_clip": 1e-5,
            "to_world": mi.ScalarTransform4f().look_at(origin=camera["position"], target=camera["look_at"],
                                                       up=camera.get("up", [0, 1, 0])),
            "sampler": {"type": "independent"},
            "film": {"type": "transient_hdr_film", "width": resolution[0], "height": resolution[1],
                     "temporal_bins": bins, "bin_width_opl": width, "start_opl": start,
                     "rfilter": {"type": "box"}},
        },
    }
    materials = scene.get("materials", {})
    for shape in scene["shapes"]:
        kind = {"rectangle": "rectangle", "cube": "cube"}.get(shape["type"])
        if kind is None:
            fail(f"shape '{shape['name']}': type '{shape['type']}' is not translated")
        material = materials.get(shape.get("material"), {"type": "diffuse", "albedo": 0.8})
        if material.get("type") != "diffuse":
            fail(f"shape '{shape['name']}': only diffuse materials are translated")
        entry = {"type": kind, "to_world": transform_of(mi, shape.get("transform", {})),
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": material.get("albedo", 0.8)}}}
        if shape.get("emission", 0) > 0:
            entry["emitter"] = {"type": "area", "radiance": {"type": "uniform", "value": shape["emission"]}}
        out[shape["name"]] = entry
    if scene.get("point_lights"):
        fail("point lights are not translated")
    return out


def gate_bins(gate):
    """(start, bin width, bins, weight per bin) of a gate spec 'box:a,b' or 'gaussian:mu,sigma'."""
    kind, values = gate.split(":")
    a, b = (float(v) for v in values.split(","))
    if kind == "box":
        return a, b - a, 1, np.ones(1)
    if kind == "gaussian":
        width = b / 4
        bins = 32
        start = a - 4 * b
        centres = start + width * (np.arange(bins) + 0.5)
        return start, width, bins, np.exp(-0.5 * ((centres - a) / b) ** 2)
    fail(f"gate '{gate}': only box and gaussian gates are compared")


def relmse_of(images):
    """Measured relMSE of one render from R independent renders (R x pixels)."""
    stack = np.asarray(images, dtype=np.float64)
    mean = stack.mean(axis=0)
    variance = stack.var(axis=0, ddof=1)
    eps = 1e-2 * mean.mean() ** 2
    return float(np.mean(variance / (mean * mean + eps))), float(stack.mean())


def render_mitsuba(mi, dr, scene, resolution, max_depth, gate, spp, runs):
    start, width, bins, weights = gate_bins(gate)
    loaded = mi.load_dict(mitsuba_scene(mi, scene, resolution, max_depth, start, width, bins))
    images, seconds = [], []
    for run in range(-1, runs):  # run -1 compiles the kernels and is not counted
        t0 = time.perf_counter()
        _, transient = mi.render(loaded, spp=spp, seed=1000 + run)
        dr.eval(transient)
        dr.sync_thread()
        elapsed = time.perf_counter() - t0
        if run < 0:
            continue
        stack = np.array(transient)  # (H, W, bins, channels)
        stack = stack.reshape(resolution[1], resolution[0], bins, -1)[..., 0]
        images.append((stack * weights).sum(axis=2).ravel())
        seconds.append(elapsed)
    return images, seconds


def render_vktg(vktg, scene_path, resolution, max_depth, gate, spp, runs, nee, workdir):
    images, seconds = [], []
    for run in range(runs):
        out = os.path.join(workdir, f"vktg_{nee}_{run}.exr")
        result = subprocess.run([vktg, "render", scene_path, "--gate", gate, "--spp", str(spp), "--seed", str(run + 1),
                                 "--resolution", f"{resolution[0]}x{resolution[1]}", "--max-depth", str(max_depth),
                                 "--nee", nee, "--npy", "--out", out], capture_output=True, text=True)
        if result.returncode != 0:
            fail(f"vktg render failed:\n{result.stderr}")
        match = re.search(r"vktg: ([0-9.]+) s render", result.stderr)
        if not match:
            fail(f"no render time in vktg's output:\n{result.stderr}")
        seconds.append(float(match.group(1)))
        images.append(np.load(out[:-4] + ".npy")[..., 0].ravel())
    return images, seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("vktg")
    parser.add_argument("scene")
    parser.add_argument("outdir")
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--runs", type=int, default=4)
    parser.add_argument("--resolution", default="64x64")
    parser.add_argument("--max-depth", type=int, default=8)
    parser.add_argument("--gates", default="box:5,6;gaussian:5.5,0.055;gaussian:5.5,0.0055")
    args = parser.parse_args()
    resolution = [int(v) for v in args.resolution.split("x")]
    if args.runs < 2:
        fail("--runs must be at least 2 (the relMSE is an across-seed variance)")

    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_mono")
    import mitransient  # noqa: F401  (registers the transient plugins)

    with open(args.scene) as f:
        scene = json.load(f)
    os.makedirs(args.outdir, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as workdir:
        for gate in args.gates.split(";"):
            print(f"bench_mitsuba: {gate}", file=sys.stderr)
            cases = [("mitsuba (llvm_ad_mono, mitransient)",
                      render_mitsuba(mi, dr, scene, resolution, args.max_depth, gate, args.spp, args.runs))]
            for nee in ("standard", "ellipsoidal", "mis"):
                cases.append((f"vktg {nee}", render_vktg(args.vktg, args.scene, resolution, args.max_depth, gate, args.spp,
                                                         args.runs, nee, workdir)))
            for name, (images, seconds) in cases:
                relmse, mean = relmse_of(images)
                t = statistics.median(seconds)
                sem = float(np.std([img.mean() for img in images], ddof=1) / math.sqrt(len(images)))
                rows.append((gate, name, t, relmse, relmse * t, mean, sem))
                print(f"bench_mitsuba:   {name}: {t:.3g} s, relMSE {relmse:.3g}, relMSE x time {relmse * t:.3g}, "
                      f"image mean {mean:.6g} +- {sem:.2g}", file=sys.stderr)
            # The renderers compute the same integral: means further apart than their noise allows
            # mean the translation (or a renderer) is wrong, and the comparison with it.
            reference = rows[-len(cases)]
            for _, name, _, _, _, mean, sem in rows[-len(cases) + 1:]:
                z = abs(mean - reference[5]) / max(math.hypot(sem, reference[6]), 1e-30)
                if z > 4:
                    print(f"bench_mitsuba: warning: {name}'s image mean is {z:.1f} standard errors from Mitsuba's",
                          file=sys.stderr)

    lines = [f"`tools/bench-mitsuba {os.path.relpath(args.scene)} --spp {args.spp} --runs {args.runs} --resolution "
             f"{args.resolution} --max-depth {args.max_depth} --gates '{args.gates}'`: {args.runs} renders per renderer "
             f"and gate (medians of their times).", "",
             "| gate | renderer | seconds | relMSE | relMSE x time | Mitsuba's relMSE x time over this one's | image mean |",
             "|---|---|---|---|---|---|---|"]
    for gate in args.gates.split(";"):
        base = next(r[4] for r in rows if r[0] == gate and r[1].startswith("mitsuba"))
        for g, name, t, relmse, product, mean, sem in rows:
            if g == gate:
                lines.append(f"| {g} | {name} | {t:.3g} | {relmse:.3g} | {product:.3g} | {base / product:.2f} "
                             f"| {mean:.5g} ± {sem:.1g} |")
    with open(os.path.join(args.outdir, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
