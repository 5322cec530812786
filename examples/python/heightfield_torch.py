"""The heightfield experiment (experiments/heightfield/tof.experiment.json) as a PyTorch loop:
recover 121 heights and an albedo from 12 time-gated images (3 laser positions x 4 gaussian gates),
with torch.optim.Adam, the experiment's learning-rate schedule and bounds, and a smoothness prior
written here in torch. `vktg optimize` on the same file reaches a parameter error (RMS over the 122
unknowns) of about 0.003 in 150 iterations; this loop prints its own.

    PYTHONPATH=build/release/python python examples/python/heightfield_torch.py [iterations]
"""

import json
import sys
from pathlib import Path

import numpy as np
import torch

import vktg
import vktg.torch

root = Path(__file__).resolve().parents[2]
experiment = json.loads((root / "experiments" / "heightfield" / "tof.experiment.json").read_text())
scene = vktg.Scene(root / "experiments" / "heightfield" / "scene.json")  # the file holds the truth: θ = 0
names = scene.select("h*") + ["grey"]
heights = experiment["parameters"][0]
initial = np.array(heights.get("initial", [0.0] * (len(names) - 1)) + [experiment["parameters"][1]["initial"]])
spp = experiment["render"]["spp"]

# The targets, grouped by gate: one render holds a gate's three laser positions (views).
groups = {}
for k, target in enumerate(experiment["targets"]):
    groups.setdefault(target["gate"]["spec"], []).append((k, target["view"]["lights"]))
targets = {gate: torch.from_numpy(np.stack(vktg.render_views(
    scene, gate=gate, spp=1024, views=[vktg.view(scene, 1000 + k, lights) for k, lights in views])))
    for gate, views in groups.items()}
views = {gate: [vktg.view(scene, k, lights) for k, lights in members] for gate, members in groups.items()}


def smoothness(theta):
    """The user's own prior: squared discrete Laplacian of the 11 x 11 height grid."""
    h = theta[:-1].reshape(11, 11)
    lap = h[1:-1, 1:-1] - 0.25 * (h[:-2, 1:-1] + h[2:, 1:-1] + h[1:-1, :-2] + h[1:-1, 2:])
    return (lap ** 2).mean()


theta = torch.tensor(initial, requires_grad=True)
optimizer = torch.optim.Adam([theta], lr=experiment["optimizer"]["learning_rate"])
schedule = torch.optim.lr_scheduler.ExponentialLR(optimizer, experiment["optimizer"]["schedule"]["decay"])
iterations = int(sys.argv[1]) if len(sys.argv) > 1 else experiment["stop"]["iterations"]
for iteration in range(iterations):
    optimizer.zero_grad()
    loss = 0.002 * smoothness(theta)
    for gate, target in targets.items():
        image = vktg.torch.render(theta, scene, names, gate=gate, views=views[gate], spp=spp)
        loss = loss + ((image - target) ** 2).mean(dim=(1, 2, 3)).sum()
    loss.backward()
    optimizer.step()
    schedule.step()
    with torch.no_grad():
        theta[:-1].clamp_(*heights["range"])
    error = theta.detach().pow(2).mean().sqrt().item()  # the truth is θ = 0
    print(f"iteration {iteration}  loss {loss.item():.4e}  parameter error {error:.4f}", flush=True)
