"""Image sums of `vktg grad` (each term apart) over independent seeds against `vktg fd` over its own
seeds: mean, standard error and spread over seeds, and the t statistic of their difference. Run by
tools/grad-vs-fd, which builds vktg first; see that script for the arguments."""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np


def summary(values):
    v = np.asarray(values, dtype=np.float64)
    sd = v.std(ddof=1) if len(v) > 1 else float("nan")
    return v.mean(), sd / math.sqrt(len(v)), sd


def run(command):
    result = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        sys.exit(f"tools/grad-vs-fd: {' '.join(command)} failed:\n{result.stderr}")


def main():
    parser = argparse.ArgumentParser(prog="tools/grad-vs-fd", description=__doc__)
    parser.add_argument("vktg", help="the vktg binary")
    parser.add_argument("scene")
    parser.add_argument("--param", required=True, help="one parameter name")
    parser.add_argument("--seeds", type=int, default=12, help="gradient seeds (default 12)")
    parser.add_argument("--spp", type=int, default=1024, help="gradient samples per pixel (default 1024)")
    parser.add_argument("--fd-eps", type=float, required=True, help="finite-difference step")
    parser.add_argument("--fd-spp", type=int, default=4096, help="finite-difference samples per pixel (default 4096)")
    parser.add_argument("--fd-seeds", type=int, default=4, help="finite-difference seeds (default 4)")
    argv = sys.argv[1:]
    split = argv.index("--") if "--" in argv else len(argv)
    args = parser.parse_args(argv[:split])
    extra = argv[split + 1:]  # options for both commands
    terms = ["interior", "edge", "pathlength"]
    sums = {name: [] for name in ["total"] + terms}
    fd = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.seeds + 1):
            out = os.path.join(tmp, f"grad{seed}.exr")
            run([args.vktg, "grad", args.scene, "--param", args.param, "--spp", str(args.spp), "--seed", str(seed),
                 "--split-terms", "--npy", "--quiet", "--out", out] + extra)
            sums["total"].append(np.load(out[:-4] + ".npy").astype(np.float64).sum())
            for term in terms:
                path = out[:-4] + f".{term}.npy"
                if os.path.exists(path):
                    sums[term].append(np.load(path).astype(np.float64).sum())
        for seed in range(1, args.fd_seeds + 1):
            out = os.path.join(tmp, f"fd{seed}.exr")
            run([args.vktg, "fd", args.scene, "--param", args.param, "--eps", str(args.fd_eps), "--spp",
                 str(args.fd_spp), "--seed", str(seed), "--npy", "--quiet", "--out", out] + extra)
            fd.append(np.load(out[:-4] + ".npy").astype(np.float64).sum())
    print(f"{args.scene}, d/d{args.param}, image sums (mean ± standard error, sd over seeds):")
    for name, values in sums.items():
        if values:
            mean, se, sd = summary(values)
            print(f"  grad {name:<10} {mean:+10.4f} ± {se:.4f}  (sd {sd:.4f}; {min(values):+.3f} to {max(values):+.3f})"
                  f"  {len(values)} seeds x {args.spp} spp")
    mean, se, sd = summary(fd)
    print(f"  fd   eps {args.fd_eps:<6g} {mean:+10.4f} ± {se:.4f}  (sd {sd:.4f})  {len(fd)} seeds x {args.fd_spp} spp")
    g_mean, g_se, _ = summary(sums["total"])
    print(f"  t = {(g_mean - mean) / math.hypot(g_se, se):+.2f} (grad total against fd)")


if __name__ == "__main__":
    main()
