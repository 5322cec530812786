"""vktg inside a PyTorch graph (``import vktg.torch`` needs torch).

:func:`render` is a differentiable function of a parameter tensor: its forward renders the image of
every view at theta, its backward runs vktg's adjoint passes with the dloss/dI that autograd hands
it, so a backward costs a few renders whatever the number of parameters. A loss, a regulariser or a
network of the caller's own, and any ``torch.optim`` optimiser, work on it as on any other function.

The backward renders with random numbers of its own, independent of the forward's (as ``vktg
optimize`` does): dloss/dI is then independent of the paths that estimate dI/dtheta, and the
gradient of a loss that is not linear in the image (an L2 loss, say) is unbiased. With the same
random numbers it would not be.
"""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np
import torch

import vktg

__all__ = ["render"]

# The backward's seeds: derived from the forward's so that a seeded run repeats, and distinct
# from them.
_BACKWARD_SEED_OFFSET = 0x5BD1E995


def _seeded(settings: dict, seed: int) -> dict:
    """The settings of one render with random numbers from ``seed``: its own seed, and each view's
    mixed with it (views carry seeds of their own)."""
    out = dict(settings, seed=seed)
    if settings.get("views"):
        out["views"] = vktg._vktg.reseeded(list(settings["views"]), seed)
    return out


class _Render(torch.autograd.Function):
    @staticmethod
    def forward(ctx, theta: torch.Tensor, scene: vktg.Scene, names: tuple, settings: dict, context, seed: int):
        model = scene.copy()
        model.set_values(names, theta.detach().to(torch.float64).cpu().numpy())
        images = vktg.render_views(model, context=context, **_seeded(settings, seed))
        ctx.model, ctx.names, ctx.settings, ctx.context, ctx.seed = model, names, settings, context, seed
        ctx.theta_dtype, ctx.theta_device = theta.dtype, theta.device
        stacked = np.stack(images) if settings.get("views") else images[0]
        return torch.from_numpy(stacked).to(device=theta.device)

    @staticmethod
    def backward(ctx, grad_image: torch.Tensor):
        adjoint = grad_image.detach().to(torch.float32).cpu().numpy()
        backward_seed = (ctx.seed + _BACKWARD_SEED_OFFSET) & 0xFFFFFFFF
        theta_grad = vktg.render_backward(ctx.model, list(ctx.names), adjoint, context=ctx.context,
                                          **_seeded(ctx.settings, backward_seed))
        grad_theta = torch.from_numpy(theta_grad).to(dtype=ctx.theta_dtype, device=ctx.theta_device)
        return grad_theta, None, None, None, None, None


_calls = 0


def render(theta: torch.Tensor, scene: vktg.Scene, parameters: Sequence[str], *, seed: Optional[int] = None,
           context: Optional[vktg.Context] = None, **settings) -> torch.Tensor:
    """The image of ``scene`` with ``parameters`` at ``theta`` (a 1-D tensor, one value per name):
    a float32 tensor (height, width, layers), or (views, height, width, layers) with ``views=``.
    Differentiable in ``theta``. ``seed`` sets the forward render's random numbers (by default a
    new seed per call, so that successive iterations do not share their noise); the backward
    derives its own from it. Settings as :func:`vktg.render`.
    """
    global _calls
    names = tuple(parameters)
    if theta.ndim != 1 or theta.shape[0] != len(names):
        raise vktg.Error(f"theta: shape {tuple(theta.shape)} is not ({len(names)},), one value per parameter")
    if not torch.isfinite(theta).all():
        raise vktg.Error("theta: a value is not finite")
    if seed is None:
        seed = (scene._native.seed + 7919 * _calls) & 0xFFFFFFFF
        _calls += 1
    return _Render.apply(theta, scene, names, settings, context, int(seed))
