"""The heightfield experiment (experiments/heightfield/tof.experiment.json) as a PyTorch loop:
recover 121 heights and an albedo from 12 time-gated images (3 laser positions x 4 gaussian gates),
with torch.optim.Adam, the experiment's learning-rate schedule and bounds, and a smoothness prior
written here in torch. On lavapipe (2 cores) `vktg optimize` on the same file ends at a parameter
error (RMS over the 122 unknowns) of 0.0021 after 150 iterations in 25 s; this loop at 0.0016 in
61 s (docs/python.md).

    PYTHONPATH=build/release/python python examples/python/heightfield_torch.py [iterations] [--expect-error E]

With --expect-error, the exit status is 1 unless the final error is below E (a slow test uses it).
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
scene_file = root / "experiments" / "heightfield" / "scene.json"
scene = vktg.Scene(scene_file)  # the file holds the truth: θ = 0
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


# The user's own prior: the squared uniform Laplacian of the surface's heights (the file's heights,
# which θ displaces, on the 11 x 11 grid with its four neighbours), as a mean over the vertices.
terrain = next(s for s in json.loads(scene_file.read_text())["shapes"] if s["name"] == "terrain")
base = torch.tensor(terrain["heights"], dtype=torch.float64).reshape(11, 11)
neighbours = torch.nn.functional.conv2d(torch.ones(1, 1, 11, 11, dtype=torch.float64),
                                        torch.tensor([[[[0.0, 1, 0], [1, 0, 1], [0, 1, 0]]]], dtype=torch.float64),
                                        padding=1)[0, 0]


def smoothness(theta):
    h = (base + theta[:-1].reshape(11, 11))[None, None]
    kernel = torch.tensor([[[[0.0, 1, 0], [1, 0, 1], [0, 1, 0]]]], dtype=torch.float64)
    mean = torch.nn.functional.conv2d(h, kernel, padding=1)[0, 0] / neighbours
    return ((h[0, 0] - mean) ** 2).mean()


theta = torch.tensor(initial, requires_grad=True)
optimizer = torch.optim.Adam([theta], lr=experiment["optimizer"]["learning_rate"])
schedule = torch.optim.lr_scheduler.ExponentialLR(optimizer, experiment["optimizer"]["schedule"]["decay"])
arguments = sys.argv[1:]
expected = None
if "--expect-error" in arguments:
    at = arguments.index("--expect-error")
    expected = float(arguments[at + 1])
    del arguments[at:at + 2]
iterations = int(arguments[0]) if arguments else experiment["stop"]["iterations"]
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
if expected is not None and not error < expected:
    sys.exit(f"the parameter error {error:.4f} is not below {expected}")
