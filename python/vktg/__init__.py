"""vktg: differentiable time-gated rendering on any Vulkan device.

Renders time-gated images and transient stacks of a scene, and their derivatives with respect to
the scene's parameters: forward (a derivative image per parameter, :func:`grad`) or backward (given
dloss/dI for every view, dloss/dtheta for every parameter at a cost that does not grow with their
number, :func:`render_backward`). Images are NumPy float32 arrays of shape (height, width, layers),
a layer per gate bin, as ``vktg render --npy`` writes them. ``vktg.torch`` puts the renderer inside
a PyTorch graph.

>>> import vktg
>>> scene = vktg.Scene("scenes/occluder_shadow.json")
>>> image = vktg.render(scene, spp=64)
>>> d = vktg.grad(scene, ["occluder_x"], spp=64)
>>> d.total.shape        # (parameters, height, width, layers)

Errors are :class:`vktg.Error` with the command line's message ("file: field: problem"); Ctrl-C
stops a render after its current batch (KeyboardInterrupt).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Callable, Iterable, Optional, Sequence, Union

import numpy as np

from . import _vktg
from ._vktg import Error

__all__ = [
    "Context", "Error", "Gate", "Scene", "Derivatives", "default_context", "render", "render_views", "grad",
    "render_backward", "scan_views", "view",
]


class Context:
    """A Vulkan device: the best available (a GPU, else lavapipe) unless ``device`` names one, as
    ``vktg --device`` takes it (an index or a name substring from ``vktg info``, or "gpu")."""

    def __init__(self, device: str = "", validation: bool = False, memory_mib: int = 0):
        self._native = _vktg.Context(device, validation, memory_mib)

    @property
    def device_name(self) -> str:
        """The device's name, as `vktg info` lists it."""
        return self._native.device_name

    @property
    def cpu_device(self) -> bool:
        """Whether the device is a CPU (lavapipe)."""
        return self._native.cpu_device

    @property
    def validation_messages(self) -> int:
        """Messages of the validation layer so far (0 unless created with validation=True)."""
        return self._native.validation_messages


_default_context: Optional[Context] = None


def default_context() -> Context:
    """The context renders use when given none: created on first use, from $VKTG_DEVICE if set."""
    global _default_context
    if _default_context is None:
        _default_context = Context(os.environ.get("VKTG_DEVICE", ""), os.environ.get("VKTG_VALIDATION") == "1")
    return _default_context


class Gate:
    """A time gate, as an object or as the command line's string (``"box:3.5,4.5"``).
    Path lengths in metres, or in nanoseconds with an ``ns`` suffix in a string."""

    def __init__(self, spec: str):
        self.spec = str(spec)
        self.layers = _vktg.gate_layers(self.spec)  # checks it: vktg.Error names what is wrong

    @staticmethod
    def gaussian(mu: float, sigma: float) -> "Gate":
        """W(L) a gaussian of mean ``mu`` and deviation ``sigma`` (metres)."""
        return Gate(f"gaussian:{mu!r},{sigma!r}")

    @staticmethod
    def box(start: float, end: float) -> "Gate":
        """W(L) = 1 for start <= L <= end."""
        return Gate(f"box:{start!r},{end!r}")

    @staticmethod
    def truncated_gaussian(mu: float, sigma: float, start: float, end: float) -> "Gate":
        """A gaussian cut to [start, end]."""
        return Gate(f"tgauss:{mu!r},{sigma!r},{start!r},{end!r}")

    @staticmethod
    def steady() -> "Gate":
        """Every path length: the steady-state image."""
        return Gate("steady")

    @staticmethod
    def bins(start: float, width: float, count: int) -> "Gate":
        """A transient stack: ``count`` box bins of ``width`` from ``start``."""
        return Gate(f"bins:{start!r},{width!r},{int(count)}")

    def __repr__(self) -> str:
        return f"Gate({self.spec!r})"

    def __str__(self) -> str:
        return _vktg.describe_gate(self.spec)


class Scene:
    """A scene file (.json, .gltf, .glb, or Mitsuba XML .xml at its defaults) and a value for each
    of its parameters, 0 as written.

    ``scene["name"]`` reads and sets one value; :meth:`values` and :meth:`set_values` several.
    """

    def __init__(self, path: Union[str, os.PathLike, None] = None, *, _native=None):
        if _native is not None:
            self._native = _native
        elif path is None:
            self._native = _vktg.Model.built_in()
        else:
            self._native = _vktg.Model.load(os.fspath(path))

    @staticmethod
    def from_json(text: str, name: str = "<string>", base_dir: Union[str, os.PathLike] = ".") -> "Scene":
        """A scene from JSON text (``name`` names it in errors, ``base_dir`` resolves its files)."""
        return Scene(_native=_vktg.Model.parse(text, name, os.fspath(base_dir)))

    @staticmethod
    def default() -> "Scene":
        """The built-in default scene (``vktg render`` without a file)."""
        return Scene()

    def copy(self) -> "Scene":
        """An independent copy, with the same values."""
        return Scene(_native=self._native.copy())

    @property
    def parameters(self) -> list[str]:
        """The names of the scene's parameters, in the file's order."""
        return self._native.parameter_names()

    def select(self, pattern: str) -> list[str]:
        """The parameters a comma-separated list with wildcards names (``"h*,light_x"``)."""
        return self._native.select(pattern)

    def __getitem__(self, name: str) -> float:
        return self._native.value(name)

    def __setitem__(self, name: str, value: float) -> None:
        self._native.set_value(name, _finite(value, name))

    def values(self, names: Sequence[str]) -> np.ndarray:
        """The values of ``names``, as float64."""
        return np.array(self._native.values(list(names)), dtype=np.float64)

    def set_values(self, names: Sequence[str], values) -> None:
        """Sets each of ``names`` to its value (each finite)."""
        names = list(names)
        theta = np.asarray(values, dtype=np.float64).reshape(-1)
        if theta.shape[0] != len(names):
            raise Error(f"values: {theta.shape[0]} values for {len(names)} parameters")
        self._native.set_values(names, [_finite(v, n) for n, v in zip(names, theta)])

    @property
    def width(self) -> int:
        """The image's width in pixels (the camera's)."""
        return self._native.width

    @property
    def height(self) -> int:
        """The image's height in pixels."""
        return self._native.height

    @property
    def gate(self) -> str:
        """The scene's own gate, described."""
        return self._native.gate

    def __repr__(self) -> str:
        return f"Scene({self._native.source or 'built-in'!r}, {len(self.parameters)} parameters)"


def _finite(value, name: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise Error(f"parameter: {name}: {value!r} is not a number") from None
    if not np.isfinite(v):
        raise Error(f"parameter: {name}: the value is not finite")
    return v


def scan_views(scene: Scene, scan_file: Union[str, os.PathLike]) -> list:
    """The views of a scan file (docs/scene-format.md, Scans), each with the seed ``vktg render
    --scan`` gives it: pass them as ``views=`` to render them together."""
    return _vktg.scan_views(scene._native, os.fspath(scan_file))


def view(scene: Scene, seed: int = 0, lights: Optional[dict] = None):
    """A view of the scene's camera with its own random numbers (``seed``) and its point lights
    moved: ``lights={"laser": (x, y, z)}``. Views render together (``views=[...]``)."""
    placed = [(str(name), [float(c) for c in position]) for name, position in (lights or {}).items()]
    return _vktg.view(scene._native, int(seed), placed)


def _settings(spp=None, seed=None, max_depth=None, resolution=None, gate=None, nee="auto", pilot=True, views=None,
              progress: Optional[Callable[[float], None]] = None):
    s = _vktg.Settings()
    for name, value in (("spp", spp), ("seed", seed), ("max_depth", max_depth)):
        if value is not None:
            if isinstance(value, bool) or int(value) != value or value < 0:
                raise Error(f"{name}: {value!r} is not a whole number")
            setattr(s, name, int(value))
    if resolution is not None:
        w, h = resolution
        s.resolution = (int(w), int(h))
    if gate is not None:
        s.gate = gate.spec if isinstance(gate, Gate) else str(gate)
    s.nee = str(nee)
    s.pilot = bool(pilot)
    if views is not None:
        s.views = list(views)
    if progress is not None:
        s.progress = progress
    return s


def _terms(terms: Optional[Iterable[str]]):
    if terms is None:
        return True, True, True
    chosen = set(terms)
    unknown = chosen - {"interior", "edge", "pathlength"}
    if unknown:
        raise Error(f"terms: unknown term '{sorted(unknown)[0]}' (interior, edge, pathlength)")
    return "interior" in chosen, "edge" in chosen, "pathlength" in chosen


def render(scene: Scene, *, context: Optional[Context] = None, **settings) -> np.ndarray:
    """The time-gated image of ``scene`` at its current values: float32 (height, width, layers).

    Settings (each overrides the scene file's): ``spp``, ``seed``, ``max_depth``, ``resolution``
    (width, height), ``gate`` (a :class:`Gate` or string), ``nee`` ("auto", "standard",
    "ellipsoidal", "mis"), ``pilot`` (let a timed pilot choose NEE, as ``vktg render``), ``progress``
    (called with the fraction done after every batch). With ``views`` (:func:`scan_views`), use
    :func:`render_views`.
    """
    if settings.get("views"):
        raise Error("views: render_views renders several views")
    return render_views(scene, context=context, **settings)[0]


def render_views(scene: Scene, *, context: Optional[Context] = None, **settings) -> list[np.ndarray]:
    """One image per view (``views=``, or the scene's camera alone), the views rendered together."""
    context = context or default_context()
    out = _vktg.render(context._native, scene._native, _settings(**settings))
    return out["images"]


@dataclass
class Derivatives:
    """Forward-mode derivatives: arrays of shape (parameters, height, width, layers)."""

    parameters: list
    image: np.ndarray     # the image itself, (height, width, layers)
    total: np.ndarray     # d image / d theta, the sum of the terms that ran
    variance: np.ndarray  # of each pixel of total (its squared standard error)
    interior: Optional[np.ndarray]
    edge: Optional[np.ndarray]
    pathlength: Optional[np.ndarray]
    plan: list


def _stack(arrays):
    return np.stack(arrays) if arrays else None


def grad(scene: Scene, parameters: Union[str, Sequence[str]], *, terms: Optional[Iterable[str]] = None,
         antithetic: Optional[bool] = None, context: Optional[Context] = None, **settings) -> Derivatives:
    """Derivative images of ``scene`` with respect to ``parameters`` (names, or one string with
    wildcards), as ``vktg grad``: each term (interior, edge, pathlength) its own pass, the planner
    dropping those that cannot contribute; ``terms`` limits them. Settings as :func:`render`."""
    names = scene.select(parameters) if isinstance(parameters, str) else list(parameters)
    context = context or default_context()
    interior, edge, pathlength = _terms(terms)
    out = _vktg.derivatives(context._native, scene._native, names, _settings(**settings), interior, edge, pathlength,
                            antithetic)
    return Derivatives(out["parameters"], out["image"], _stack(out["total"]), _stack(out["total_variance"]),
                       _stack(out["interior"]), _stack(out["edge"]), _stack(out["pathlength"]), out["plan"])


def render_backward(scene: Scene, parameters: Union[str, Sequence[str]], adjoint, *,
                    terms: Optional[Iterable[str]] = None, antithetic: Optional[bool] = None,
                    context: Optional[Context] = None, **settings) -> np.ndarray:
    """dloss/dtheta for each of ``parameters`` given ``adjoint`` = dloss/dI: an array of the image's
    shape (height, width, layers), or one per view (``views=``) as a list or a (views, height,
    width, layers) array. The adjoint passes of every term, with random numbers of their own (the
    ``seed`` setting and the views' seeds): give dloss/dI from an image rendered with other seeds,
    as ``vktg optimize`` does, or the gradient of a loss that is not linear in the image is biased.
    Its cost does not grow with the number of parameters."""
    names = scene.select(parameters) if isinstance(parameters, str) else list(parameters)
    context = context or default_context()
    views = settings.get("views")
    expected = len(views) if views else 1
    if isinstance(adjoint, np.ndarray) and adjoint.ndim == 4:
        adjoint = list(adjoint)
    elif not isinstance(adjoint, (list, tuple)):
        adjoint = [adjoint]
    if len(adjoint) != expected:
        raise Error(f"adjoint: {len(adjoint)} images for {expected} view(s)")
    arrays = [_adjoint_array(a, k) for k, a in enumerate(adjoint)]
    interior, edge, pathlength = _terms(terms)
    theta = _vktg.render_backward(context._native, scene._native, names, arrays, _settings(**settings), interior, edge,
                                  pathlength, antithetic)
    return np.array(theta, dtype=np.float64)


def _adjoint_array(a, k: int) -> np.ndarray:
    a = np.asarray(a)
    if a.dtype.kind != "f":
        raise Error(f"adjoint[{k}]: dtype {a.dtype} is not a floating-point type")
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3:
        raise Error(f"adjoint[{k}]: shape {a.shape} is not (height, width, layers)")
    if not np.all(np.isfinite(a)):
        raise Error(f"adjoint[{k}]: dloss/dI is not finite")
    return np.ascontiguousarray(a, dtype=np.float32)
