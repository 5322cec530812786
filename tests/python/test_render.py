"""vktg.render and vktg.grad against the command line (bit for bit), render_backward against the
forward derivatives (within their statistical error), and how they fail, report and let go."""

import threading
import time

import numpy as np
import pytest

import vktg
from conftest import OCCLUDER, ROOT, SCENES, SMALL, run_cli


def test_render_is_the_command_lines_image_bit_for_bit(tmp_path, context):
    run_cli("render", OCCLUDER, "--spp", 16, "--resolution", "16x16", "--npy", "--out", tmp_path / "r.exr")
    image = vktg.render(vktg.Scene(OCCLUDER), context=context, **SMALL)
    cli = np.load(tmp_path / "r.npy")
    assert image.dtype == np.float32 and image.shape == cli.shape == (16, 16, 1)
    assert np.array_equal(image, cli)


def test_transient_stack_is_the_command_lines_bit_for_bit(tmp_path, context):
    scene = SCENES / "transient_stack.json"
    run_cli("render", scene, "--spp", 8, "--resolution", "12x12", "--npy", "--out", tmp_path / "s.exr")
    stack = vktg.render(vktg.Scene(scene), spp=8, resolution=(12, 12), context=context)
    cli = np.load(tmp_path / "s.npy")
    assert stack.shape == cli.shape and stack.shape[2] > 1
    assert np.array_equal(stack, cli)


def test_a_scan_renders_as_the_command_lines_scan(tmp_path, context):
    scene_file = ROOT / "experiments" / "confocal_scan" / "scene.json"
    scan_file = ROOT / "experiments" / "confocal_scan" / "scan.json"
    run_cli("render", scene_file, "--scan", scan_file, "--spp", 4, "--npy", "--out", tmp_path / "scan.exr")
    cli = np.load(tmp_path / "scan.npy")
    scene = vktg.Scene(scene_file)
    views = vktg.scan_views(scene, scan_file)
    images = vktg.render_views(scene, views=views, spp=4, context=context)
    assert len(images) == cli.shape[0] * cli.shape[1]
    # At a point sensor each view is one pixel; the command line lays them out as the scan's grid.
    assert np.array_equal(np.concatenate(images, axis=0).reshape(cli.shape), cli)


def test_gate_objects_and_strings_are_the_same_gate(context):
    scene = vktg.Scene(OCCLUDER)
    by_object = vktg.render(scene, gate=vktg.Gate.box(5.0, 7.0), context=context, **SMALL)
    by_string = vktg.render(scene, gate="box:5,7", context=context, **SMALL)
    assert np.array_equal(by_object, by_string)
    assert vktg.Gate.bins(3, 0.1, 40).layers == 40


def test_interior_derivatives_are_the_command_lines_bit_for_bit(tmp_path, context):
    run_cli("grad", OCCLUDER, "--param", "occluder_x,floor_albedo", "--terms", "interior", "--spp", 16,
            "--resolution", "16x16", "--npy", "--out", tmp_path / "g.exr")
    d = vktg.grad(vktg.Scene(OCCLUDER), ["occluder_x", "floor_albedo"], terms=["interior"], context=context, **SMALL)
    cli = np.load(tmp_path / "g.npy")  # (height, width, parameters x layers)
    assert d.total.shape == (2, 16, 16, 1) and d.edge is None
    assert np.array_equal(np.moveaxis(d.total[:, :, :, 0], 0, -1), cli)


def test_render_backward_is_the_adjoint_weighted_sum_of_the_forward_derivatives(context):
    """Σ_pixels w · dI/dθ from forward lanes against the adjoint pass given w, over 6 seeds."""
    scene = vktg.Scene(OCCLUDER)
    names = ["occluder_x", "floor_albedo"]
    d = vktg.grad(scene, names, spp=64, resolution=(16, 16), seed=1, context=context)
    w = 1.0 + np.linspace(0.0, 1.0, 16, dtype=np.float32)[None, :, None] * np.ones((16, 16, 1), np.float32)
    backward = np.array([vktg.render_backward(scene, names, w, spp=64, resolution=(16, 16), seed=50 + s,
                                              context=context) for s in range(6)])
    for k, name in enumerate(names):
        forward = float((w * d.total[k]).sum())
        forward_var = float((w ** 2 * d.variance[k]).sum())
        se = np.sqrt(forward_var + backward[:, k].var(ddof=1) / len(backward))
        assert se > 0
        assert abs(backward[:, k].mean() - forward) < 4 * se, (name, backward[:, k].mean(), forward, se)


def test_values_set_in_python_move_the_render(context):
    scene = vktg.Scene(OCCLUDER)
    at_zero = vktg.render(scene, context=context, **SMALL)
    scene["occluder_x"] = 0.4
    assert scene["occluder_x"] == 0.4
    moved = vktg.render(scene, context=context, **SMALL)
    assert not np.array_equal(at_zero, moved)
    scene.set_values(["occluder_x"], [0.0])
    assert np.array_equal(vktg.render(scene, context=context, **SMALL), at_zero)


@pytest.mark.parametrize("call, needle", [
    (lambda s, c: vktg.grad(s, ["no_such_parameter"], context=c, **SMALL), "no_such_parameter"),
    (lambda s, c: vktg.render_backward(s, ["occluder_x"], np.ones((3, 3, 1), np.float32), context=c, **SMALL),
     "adjoints[0]"),
    (lambda s, c: vktg.render_backward(s, ["occluder_x"], np.ones((16, 16, 1), np.int32), context=c, **SMALL),
     "dtype"),
    (lambda s, c: vktg.render_backward(s, ["occluder_x"], np.full((16, 16, 1), np.nan, np.float32), context=c,
                                       **SMALL), "not finite"),
    (lambda s, c: s.__setitem__("occluder_x", float("nan")), "not finite"),
    (lambda s, c: vktg.render(s, gate="box:2,1", context=c), "gate"),
    (lambda s, c: vktg.render(s, spp=0, context=c), "spp"),
    (lambda s, c: vktg.grad(s, ["occluder_x"], terms=["interior", "glow"], context=c), "glow"),
])
def test_bad_input_raises_vktg_error_naming_the_problem(context, call, needle):
    with pytest.raises(vktg.Error) as error:
        call(vktg.Scene(OCCLUDER), context)
    assert needle in str(error.value)


def test_a_scene_file_error_names_the_file_and_field(tmp_path):
    import json
    scene = json.loads(OCCLUDER.read_text())
    scene["camera"]["fov_y"] = "wide"
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(scene))
    with pytest.raises(vktg.Error) as error:
        vktg.Scene(bad)
    assert "bad.json" in str(error.value) and "fov_y" in str(error.value)
    with pytest.raises(vktg.Error, match="inline"):
        vktg.Scene.from_json("{", name="inline")


def test_renders_release_the_gil_and_report_progress(context):
    """Another Python thread runs while a render does; progress reaches 1."""
    scene = vktg.Scene(OCCLUDER)
    fractions, ticks, done = [], [0], threading.Event()

    def count():
        while not done.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    before = ticks[0]
    vktg.render(scene, spp=256, resolution=(32, 32), pilot=False, progress=fractions.append, context=context)
    during = ticks[0] - before
    done.set()
    counter.join()
    assert during > 10, "the other thread did not run during the render"
    assert fractions and fractions[-1] == 1.0 and fractions == sorted(fractions)


def test_ctrl_c_stops_a_render_as_keyboard_interrupt():
    """A SIGINT during a render ends it after the batch it arrived in, as KeyboardInterrupt; the
    next render runs. (A small memory budget makes the render many batches.)"""
    import _thread

    small = vktg.Context(memory_mib=16)
    fractions = []

    def interrupt_first(fraction):
        fractions.append(fraction)
        if len(fractions) == 1:
            _thread.interrupt_main()

    with pytest.raises(KeyboardInterrupt):
        vktg.render(vktg.Scene(OCCLUDER), spp=2048, resolution=(64, 64), pilot=False, progress=interrupt_first,
                    context=small)
    assert len(fractions) <= 2 and fractions[-1] < 1.0, fractions
    assert vktg.render(vktg.Scene(OCCLUDER), context=small, **SMALL).shape == (16, 16, 1)


def test_the_default_scene_renders_and_differentiates(context):
    scene = vktg.Scene()
    assert scene.parameters == ["short_box_x", "tall_box_spin", "light_emission", "left_albedo"]
    image = vktg.render(scene, context=context, **SMALL)
    d = vktg.grad(scene, scene.parameters, context=context, **SMALL)
    assert image.shape == (16, 16, 1) and image.sum() > 0
    assert d.total.shape == (4, 16, 16, 1) and np.all(np.isfinite(d.total))
    assert np.abs(d.total).sum(axis=(1, 2, 3)).min() > 0, "every parameter changes the image"
