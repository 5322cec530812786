"""What the Python tests share: the vktg binary to compare with, the repository's scenes, and a
context on the test device (lavapipe unless VKTG_TEST_DEVICE says otherwise) with validation on,
whose every message fails the test that produced it."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import vktg

# The device as the C++ tests choose it (tests/support/test_environment.cpp): lavapipe unless
# VKTG_TEST_DEVICE names another; set before the first context, which the loader reads it for.
_device = os.environ.get("VKTG_TEST_DEVICE", "")
if _device in ("", "lavapipe") and os.environ.get("VKTG_TEST_ICD"):
    os.environ.setdefault("VK_DRIVER_FILES", os.environ["VKTG_TEST_ICD"])
    os.environ.setdefault("VK_ICD_FILENAMES", os.environ["VK_DRIVER_FILES"])
elif _device not in ("", "lavapipe"):
    os.environ["VKTG_DEVICE"] = _device

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
OCCLUDER = SCENES / "occluder_shadow.json"
SMALL = dict(spp=16, resolution=(16, 16))


def vktg_binary() -> str:
    return os.environ.get("VKTG_BINARY", str(ROOT / "build" / "release" / "vktg"))


def run_cli(*args) -> None:
    """Runs the command line with the same device the tests use."""
    subprocess.run([vktg_binary(), *map(str, args), "--quiet"], check=True)


@pytest.fixture(scope="session")
def context():
    return vktg.Context("" if _device in ("", "lavapipe") else _device, validation=True)


@pytest.fixture(autouse=True)
def validation_silent(request):
    """Every validation message fails the test during which it appeared."""
    if "context" not in request.fixturenames:
        yield
        return
    ctx = request.getfixturevalue("context")
    before = ctx.validation_messages
    yield
    assert ctx.validation_messages == before, "the validation layer reported a problem"


def image_sum_error(images: np.ndarray, variances: np.ndarray, weights: np.ndarray):
    """Σ w·I and its standard error from the pixels' variances."""
    return float((weights * images).sum()), float(np.sqrt((weights ** 2 * variances).sum()))
