"""One loss gradient of the heightfield experiment (experiments/heightfield/tof.experiment.json)
spread over processes with mpi4py: each process renders its share of the experiment's gates (each
gate's three laser positions are one render), forms its part of the loss and its adjoint, and
takes the gradient of that part by vktg.render_backward; the parts are then gathered and added in
gate order on every process, so that the gradient has the same bits for any number of processes,
one without MPI included (docs/mpi.md, "From Python").

    mpirun -np 2 env PYTHONPATH=build/release/python python3 examples/python/mpi_gradients.py [--out FILE.npy]

Every process opens its own vktg.Context (one device per process: the local rank picks among GPUs
here; on a CPU they all share lavapipe). examples/python/torch_distributed.py does the same over
torch.distributed with an all-reduce, exact because it sums the parts as 64-bit fixed point.
"""

import json
import os
import sys
from pathlib import Path

import numpy as np
from mpi4py import MPI

import vktg

comm = MPI.COMM_WORLD
rank, size = comm.Get_rank(), comm.Get_size()

# One device per process: the local rank's GPU where there are several, else the default device.
local_rank = int(os.environ.get("OMPI_COMM_WORLD_LOCAL_RANK", os.environ.get("MPI_LOCALRANKID", "0")))
context = vktg.Context()
if not context.cpu_device:
    try:
        context = vktg.Context(device=str(local_rank))
    except vktg.Error:
        pass  # fewer GPUs than processes on this node: share the default one

root = Path(__file__).resolve().parents[2]
experiment = json.loads((root / "experiments" / "heightfield" / "tof.experiment.json").read_text())
scene = vktg.Scene(root / "experiments" / "heightfield" / "scene.json")
names = scene.select("h*") + ["grey"]
initial = experiment["parameters"][0]["initial"] + [experiment["parameters"][1]["initial"]]
spp = experiment["render"]["spp"]
# The estimator by the planner's rule, not by a timed pilot: a pilot's choice goes by measured
# time, which differs between processes and runs.
fixed = {"pilot": False, "context": context}

# The experiment's targets grouped by gate, in file order; this process takes a consecutive block.
gates = {}
for k, target in enumerate(experiment["targets"]):
    gates.setdefault(target["gate"]["spec"], []).append((k, target["view"]["lights"]))
order = list(gates)
share = np.array_split(np.arange(len(order)), size)[rank]

# The measurement, at the truth (θ = 0, the file as written), then the model at the initial θ.
model = scene.copy()
model.set_values(names, np.array(initial, dtype=np.float64))
parts = {}
for g in share:
    gate = order[g]
    members = gates[gate]
    target = np.stack(vktg.render_views(scene, gate=gate, spp=1024, **fixed,
                                        views=[vktg.view(scene, 1000 + k, lights) for k, lights in members]))
    image = np.stack(vktg.render_views(model, gate=gate, spp=spp, **fixed,
                                       views=[vktg.view(model, k, lights) for k, lights in members]))
    n = image[0].size
    loss = float(((image - target) ** 2).mean(axis=(1, 2, 3)).sum())
    adjoint = (2.0 / n) * (image - target)
    # The backward pass with random numbers of its own (other view seeds than the image's).
    gradient = vktg.render_backward(model, names, adjoint, gate=gate, spp=spp, **fixed,
                                    views=[vktg.view(model, 500 + k, lights) for k, lights in members])
    parts[g] = (loss, gradient)

# Every process's parts on every process, added in gate order: the same bits for any N.
gathered = {}
for mine in comm.allgather(parts):
    gathered.update(mine)
loss = 0.0
gradient = np.zeros(len(names))
for g in range(len(order)):
    loss += gathered[g][0]
    gradient = gradient + gathered[g][1]

if rank == 0:
    print(f"{size} process(es) on {context.device_name}: loss {loss:.6e}, |gradient| {np.linalg.norm(gradient):.6e}")
    if "--out" in sys.argv:
        np.save(sys.argv[sys.argv.index("--out") + 1], np.concatenate([[loss], gradient]))
