"""The heightfield experiment (experiments/heightfield/tof.experiment.json) as a data-parallel
PyTorch loop over torch.distributed: every process renders its share of the experiment's gates
(each gate's three laser positions are one render), its loss and gradient by autograd through
vktg.torch.render, and the processes all-reduce the gradient before each identical Adam step.

    torchrun --standalone --nproc_per_node 2 examples/python/torch_distributed.py [iterations] [--out FILE.npy]
    python3 examples/python/torch_distributed.py ...     (one process, no launcher)

(with PYTHONPATH=build/release/python; Debian 12's torchrun, torch 1.13 under Python 3.11, fails
to parse its own default `--redirects 0 --tee 0`: give it `--redirects 1 --tee 1`). The all-reduce
sums integers: each gate's loss and gradient are rounded to 64-bit fixed point on one scale that every process agrees on (the largest
magnitude over all gates, itself an all-reduce), so the sum is exact and its order does not matter.
The parameters after any number of iterations then have the same bits for any number of processes,
one without a launcher included (docs/mpi.md, "From Python"), which a floating-point all_reduce,
adding in an order that depends on the number of processes, would not give.

Every process opens its own vktg.Context: the local rank's GPU where there are several, the
default device otherwise (on a CPU they all share lavapipe). With VKTG_VALIDATION=1 the contexts
run the validation layer and any message it reports fails the run. The gloo backend carries the
reductions (they are a few hundred bytes per iteration; the renders are the work).
"""

import json
import math
import os
import sys
from pathlib import Path

import numpy as np
import torch
import torch.distributed as dist

import vktg
import vktg.torch

# One process without a launcher is a world of one: the same code path, the same bits.
launched = "RANK" in os.environ
if launched:
    dist.init_process_group("gloo")
rank, size = (dist.get_rank(), dist.get_world_size()) if launched else (0, 1)
local_rank = int(os.environ.get("LOCAL_RANK", "0"))

validation = os.environ.get("VKTG_VALIDATION") == "1"
context = vktg.Context(validation=validation)
if not context.cpu_device:
    try:
        context = vktg.Context(device=str(local_rank), validation=validation)
    except vktg.Error:
        pass  # fewer GPUs than processes on this node: share the default one

arguments = sys.argv[1:]
out = None
if "--out" in arguments:
    at = arguments.index("--out")
    out = arguments[at + 1]
    del arguments[at:at + 2]

root = Path(__file__).resolve().parents[2]
experiment = json.loads((root / "experiments" / "heightfield" / "tof.experiment.json").read_text())
scene = vktg.Scene(root / "experiments" / "heightfield" / "scene.json")  # the truth: θ = 0
names = scene.select("h*") + ["grey"]
heights = experiment["parameters"][0]
initial = np.array(heights.get("initial", [0.0] * (len(names) - 1)) + [experiment["parameters"][1]["initial"]])
spp = experiment["render"]["spp"]
iterations = int(arguments[0]) if arguments else experiment["stop"]["iterations"]
# The estimator by the planner's rule, not by a timed pilot, whose choice goes by measured time and
# so may differ between processes.
fixed = {"pilot": False, "context": context, "spp": spp}

# The experiment's targets grouped by gate, in file order; this process takes a consecutive block.
groups = {}
for k, target in enumerate(experiment["targets"]):
    groups.setdefault(target["gate"]["spec"], []).append((k, target["view"]["lights"]))
gates = list(groups)
mine = [int(g) for g in np.array_split(np.arange(len(gates)), size)[rank]]
views = {g: [vktg.view(scene, k, lights) for k, lights in groups[gates[g]]] for g in mine}
targets = {g: torch.from_numpy(np.stack(vktg.render_views(
    scene, gate=gates[g], spp=1024, pilot=False, context=context,
    views=[vktg.view(scene, 1000 + k, lights) for k, lights in groups[gates[g]]]))) for g in mine}


def all_reduce(tensor: torch.Tensor, op) -> torch.Tensor:
    if launched:
        dist.all_reduce(tensor, op=op)
    return tensor


def exact_sum(parts: dict) -> np.ndarray:
    """The sum over all gates of every process's per-gate vectors, exactly: each rounded to int64
    on the scale 2^e that keeps the sum of all gates' magnitudes below 2^62, then all-reduced."""
    largest = max((float(np.abs(v).max()) for v in parts.values()), default=0.0)
    largest = all_reduce(torch.tensor([largest], dtype=torch.float64), dist.ReduceOp.MAX).item()
    exponent = 0 if largest == 0 else 62 - math.frexp(largest * len(gates))[1]
    total = torch.zeros(len(names) + 1, dtype=torch.int64)
    for v in parts.values():
        total += torch.from_numpy(np.rint(np.ldexp(v, exponent)).astype(np.int64))
    return np.ldexp(all_reduce(total, dist.ReduceOp.SUM).numpy().astype(np.float64), -exponent)


theta = torch.tensor(initial, requires_grad=True)
optimizer = torch.optim.Adam([theta], lr=experiment["optimizer"]["learning_rate"])
schedule = torch.optim.lr_scheduler.ExponentialLR(optimizer, experiment["optimizer"]["schedule"]["decay"])
trajectory = []
for iteration in range(iterations):
    # Each gate's loss and gradient on their own; seeds by iteration and gate, whichever process
    # renders the gate.
    parts = {}
    for g in mine:
        image = vktg.torch.render(theta, scene, names, gate=gates[g], views=views[g], seed=7919 * (iteration * len(gates) + g) + 1,
                                  **fixed)
        loss = ((image - targets[g]) ** 2).mean(dim=(1, 2, 3)).sum()
        (gradient,) = torch.autograd.grad(loss, theta)
        parts[g] = np.concatenate([[loss.item()], gradient.numpy()])
    total = exact_sum(parts)
    optimizer.zero_grad()
    theta.grad = torch.from_numpy(total[1:])
    optimizer.step()
    schedule.step()
    with torch.no_grad():
        theta[:-1].clamp_(*heights["range"])
    error = theta.detach().pow(2).mean().sqrt().item()  # the truth is θ = 0
    trajectory.append(error)
    if rank == 0:
        print(f"iteration {iteration}  loss {total[0]:.4e}  parameter error {error:.4f}", flush=True)

if rank == 0:
    print(f"{size} process(es) on {context.device_name}")
    if out:
        # θ, the error after every iteration, and the last iteration's summed loss and gradient (an
        # Adam step hardly depends on the gradient's last bits; the sum does).
        np.save(out, np.concatenate([theta.detach().numpy(), trajectory, total]))
if validation and context.validation_messages:
    sys.exit(f"rank {rank}: the validation layer reported {context.validation_messages} problem(s)")
if launched:
    dist.destroy_process_group()
