"""vktg.torch: the backward of a user's loss against finite differences of that loss, a PyTorch
loop with Adam and a regulariser of its own that converges, and bad input. Skipped, saying so,
only where torch cannot be imported."""

import numpy as np
import pytest

import vktg
from conftest import OCCLUDER

torch = pytest.importorskip("torch", reason="torch is not installed (tools/setup installs Debian's python3-torch)")
import vktg.torch as vt  # noqa: E402

NAMES = ["floor_albedo", "occluder_x"]
SETTINGS = dict(resolution=(16, 16), pilot=False)


def user_loss(image, target):
    return ((image - target) ** 2).sum() + 0.1 * image.sum()


def test_backward_of_a_user_loss_matches_finite_differences(context):
    scene = vktg.Scene(OCCLUDER)
    target = torch.from_numpy(vktg.render(scene, spp=1024, seed=999, context=context, **SETTINGS))
    theta0 = np.array([0.05, 0.1])
    # Autograd's gradient over independent seeds.
    grads = []
    for s in range(6):
        theta = torch.tensor(theta0, requires_grad=True)
        user_loss(vt.render(theta, scene, NAMES, spp=256, seed=10 + s, context=context, **SETTINGS), target).backward()
        grads.append(theta.grad.numpy().copy())
    grads = np.array(grads)
    # Central differences of the same loss, both sides with the same random numbers, over seeds.
    h = np.array([0.02, 0.02])
    fd = []
    for s in range(4):
        row = []
        for k in range(len(NAMES)):
            step = np.zeros(2)
            step[k] = h[k]
            losses = []
            for sign in (1, -1):
                t = torch.tensor(theta0 + sign * step)
                image = vt.render(t, scene, NAMES, spp=1024, seed=500 + s, context=context, **SETTINGS)
                losses.append(float(user_loss(image, target)))
            row.append((losses[0] - losses[1]) / (2 * h[k]))
        fd.append(row)
    fd = np.array(fd)
    for k, name in enumerate(NAMES):
        se = np.sqrt(grads[:, k].var(ddof=1) / len(grads) + fd[:, k].var(ddof=1) / len(fd))
        assert abs(grads[:, k].mean() - fd[:, k].mean()) < 4 * se + 0.02 * abs(fd[:, k].mean()), \
            (name, grads[:, k].mean(), fd[:, k].mean(), se)


def test_a_pytorch_loop_with_adam_and_a_regulariser_converges(context):
    scene = vktg.Scene(OCCLUDER)
    truth = vktg.Scene(OCCLUDER)
    truth["occluder_x"] = 0.3
    target = torch.from_numpy(vktg.render(truth, spp=256, seed=7, context=context, **SETTINGS))
    theta = torch.tensor([0.0], requires_grad=True)
    optimizer = torch.optim.Adam([theta], lr=0.03)
    for it in range(40):
        optimizer.zero_grad()
        image = vt.render(theta, scene, ["occluder_x"], spp=32, context=context, **SETTINGS)
        loss = ((image - target) ** 2).mean() + 1e-4 * (theta ** 2).sum()  # the user's own prior
        loss.backward()
        optimizer.step()
    assert abs(theta.item() - 0.3) < 0.1, theta.item()


def test_bad_theta_raises_vktg_error(context):
    scene = vktg.Scene(OCCLUDER)
    with pytest.raises(vktg.Error, match="theta"):
        vt.render(torch.zeros(3), scene, NAMES, context=context, **SETTINGS)
    with pytest.raises(vktg.Error, match="not finite"):
        vt.render(torch.tensor([float("nan"), 0.0]), scene, NAMES, context=context, **SETTINGS)
