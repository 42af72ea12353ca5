"""The notebook view, bounce.widget.View: what Python sends (binary buffers, the histogram),
how run, step and play drive the world, the front-end module drawing in headless Chromium
(discs where the world has them, in the ramp's colours; the controls; the frame rate at
10^5 discs, recorded), and the example notebook executed."""

import json
import pathlib
import sys

import nbclient
import nbformat
import numpy as np
import pytest
from matplotlib.image import imread

import bounce
from bounce.widget import View

sys.path.insert(0, str(pathlib.Path(__file__).parent / "widget"))
import harness  # noqa: E402

ROOT = __import__("conftest").ROOT

# bounce_scenario::colour::ramp's stops and the view's background, as 0–255.
STOPS = np.array(
    [[59, 76, 192], [40, 140, 200], [60, 180, 140], [170, 210, 60], [250, 230, 40]], float
)
BACKGROUND = np.array([24, 26, 32], float)


def ramp(shade):
    t = min(max(shade, 0), 255) / 255 * 4
    k = min(int(t), 3)
    return STOPS[k] + (STOPS[k + 1] - STOPS[k]) * (t - k)


def scene():
    """32 discs on a grid, each at its own speed, a peg and a segment, between walls."""
    config = bounce.Config(
        boundary="walls",
        min=(0, 0),
        max=(60, 40),
        obstacles=[bounce.Obstacle.peg((50, 30), 2.0), bounce.Obstacle.segment((5, 35), (25, 35))],
    )
    world = bounce.World(config, dt=0.01)
    positions = [[5 + 6 * i, 5 + 6 * j] for i in range(8) for j in range(4)]
    velocities = [[0.1 * k, 0.0] for k in range(32)]
    world.add_discs(positions=positions, velocities=velocities, radii=1.5)
    return world


def test_the_view_sends_the_world_as_binary_buffers():
    world = scene()
    view = View(world, speed_scale=3.2)
    positions = np.frombuffer(view.positions, dtype=np.float32).reshape(-1, 2)
    order = np.lexsort((positions[:, 1], positions[:, 0]))
    expected = world.positions[np.lexsort((world.positions[:, 1], world.positions[:, 0]))]
    assert np.array_equal(positions[order], expected.astype(np.float32))
    assert np.array_equal(np.frombuffer(view.radii, dtype=np.float32), np.full(32, 1.5, np.float32))
    # One byte a disc: speed / speed_scale along the ramp, by hand: the disc at grid place k
    # moves at 0.1 k.
    shades = np.frombuffer(view.shades, dtype=np.uint8)
    for (x, y), shade in zip(positions, shades):
        k = int(round((x - 5) / 6)) * 4 + int(round((y - 5) / 6))
        assert shade == min(np.floor(0.1 * k / 3.2 * 255 + 0.5), 255), (k, shade)
    assert view.bounds == [0.0, 0.0, 60.0, 40.0]
    assert view.obstacles == [
        {"kind": "peg", "centre": [50.0, 30.0], "radius": 2.0},
        {"kind": "segment", "a": [5.0, 35.0], "b": [25.0, 35.0]},
    ]
    frame = view.frame
    assert (frame["step"], frame["time"], frame["discs"]) == (0, 0.0, 32)
    h = frame["histogram"]
    assert abs(sum(h["density"]) * h["width"] - 1) < 1e-12


def test_colours_by_radius_and_frames_an_open_world():
    world = bounce.World(bounce.Config(), dt=0.01)
    world.add_discs(positions=[[0, 0], [10, 0], [20, 5]], velocities=np.zeros((3, 2)), radii=[1.0, 2.0, 3.0])
    view = View(world, colour_by="radius")
    assert list(np.frombuffer(view.shades, dtype=np.uint8)) == [0, 128, 255]
    x0, y0, x1, y1 = view.bounds
    # The discs' extent (to the rims) and a 5 % margin.
    assert x0 < -1 and x1 > 23 and y0 < -3 and y1 > 8
    assert "histogram" not in View(world, histogram=False).frame


def test_the_speed_histogram_is_the_viewers():
    world = bounce.World.from_scenario(str(ROOT / "scenarios" / "gas.toml"))
    world.step(200)
    h = bounce.speed_histogram(world, bins=40)
    assert len(h["density"]) == 40 and h["curve"].shape == (201, 2)
    assert abs(h["density"].sum() * h["width"] - 1) < 1e-12
    # kT in the centre-of-mass frame, by hand from the masses and velocities.
    m, v = world.masses, world.velocities
    drift = (m[:, None] * v).sum(axis=0)
    kt = (0.5 * (m * (v**2).sum(axis=1)).sum() - (drift**2).sum() / (2 * m.sum())) / len(m)
    assert abs(h["kt"] - kt) < 1e-9 * kt
    # The curve is a density: it integrates to about 1 over the bins' range.
    v, d = h["curve"].T
    assert abs(np.trapezoid(d, v) - 1) < 0.02
    with pytest.raises(ValueError, match="bins = 0"):
        bounce.speed_histogram(world, bins=0)


def test_run_step_and_play_drive_the_world():
    world = bounce.World.from_scenario(str(ROOT / "scenarios" / "gas.toml"))
    view = View(world, every=10, max_fps=None)
    sent = []
    view.observe(lambda change: sent.append(change["new"]["step"]), names="frame")
    view.run(45)
    # Frames after 10, 20, 30 and 40 steps, and the last 5.
    assert sent == [10, 20, 30, 40, 45] and world.step_count == 45
    view._on_message(view, {"type": "step"}, [])
    assert world.step_count == 55 and view.frame["step"] == 55
    # A tick (the page asking for its next frame) steps only while playing.
    view._on_message(view, {"type": "tick"}, [])
    assert world.step_count == 55
    view.playing = True
    view._on_message(view, {"type": "tick"}, [])
    assert world.step_count == 65 and view.frame["time"] == pytest.approx(world.time)
    view.run(4, every=2)
    assert world.step_count == 69 and view.every == 2


def test_bad_arguments_are_named():
    world = scene()
    with pytest.raises(TypeError, match="bounce.World"):
        View("gas.toml")
    with pytest.raises(ValueError, match='colour_by = "spin"|colour_by = \'spin\''):
        View(world, colour_by="spin")
    with pytest.raises(ValueError, match="every = 0"):
        View(world, every=0)
    with pytest.raises(ValueError, match="renderer"):
        View(world, renderer="vulkan")


def pixel(image, x, y):
    return image[int(y), int(x), :3] * 255


@pytest.mark.parametrize("renderer", ["auto", "webgl", "raster"])
def test_the_page_draws_the_discs_where_the_world_has_them(tmp_path, renderer):
    world = scene()
    view = View(world, speed_scale=3.2)
    harness.prepare(tmp_path)
    harness.save_frame(view, tmp_path, 0)
    with harness.serve(tmp_path) as url:
        report = harness.drive(url, tmp_path / "shot.png", "render", renderer)
    assert report["errors"] == [] and "error" not in report, report
    # Headless Chromium draws WebGL in software (SwiftShader): "auto" takes the raster there.
    assert report["renderer"] == ("raster" if renderer == "auto" else renderer)
    assert report["status"].startswith("step 0 · t = 0.0000 · 32 discs")
    image = imread(tmp_path / "shot.png")
    left, top, width, height = report["canvas"]
    assert (width, height) == (640, round(640 * 40 / 60))
    # The box fitted into the canvas, centred, y up (worked out here, not read from the page).
    scale = min(width / 60, height / 40)
    ox, oy = (width - 60 * scale) / 2, (height - 40 * scale) / 2 + 40 * scale

    def at(x, y):
        return pixel(image, left + ox + x * scale, top + oy - y * scale)

    shades = np.frombuffer(view.shades, dtype=np.uint8)
    for (x, y), shade in zip(np.frombuffer(view.positions, np.float32).reshape(-1, 2), shades):
        for dx, dy in [(0, 0), (1.1, 0), (0, -1.1)]:  # the centre and inside the rim (r = 1.5)
            assert np.abs(at(x + dx, y + dy) - ramp(shade)).max() < 10, (x, y, dx, dy)
        for dx, dy in [(1.9, 0), (0, 1.9)]:  # just outside the rim
            assert np.abs(at(x + dx, y + dy) - BACKGROUND).max() < 10, (x, y, dx, dy)
    assert np.abs(at(8, 8) - BACKGROUND).max() < 10  # between four discs
    assert at(50, 30).min() > 200  # the peg
    line = [at(15, 35 + d).min() for d in np.linspace(-0.15, 0.15, 7)]
    assert max(line) > 150  # the segment
    # The histogram canvas is there and drew bars (blue) and the curve (red).
    hl, ht, hw, hh = report["histogram"]
    patch = image[int(ht) : int(ht + hh), int(hl) : int(hl + hw), :3] * 255
    assert (np.abs(patch - [120, 160, 220]).max(axis=2) < 4).sum() > 500
    assert (np.abs(patch - [220, 40, 40]).max(axis=2) < 40).sum() > 50


def frames_of(world, folder, count, every, **options):
    view = View(world, every=every, max_fps=None, **options)
    for k in range(count):
        if k:
            view.step()
        harness.save_frame(view, folder, k)
    return view


def test_the_page_plays_pauses_and_steps(tmp_path):
    world = bounce.World.from_scenario(str(ROOT / "scenarios" / "gas.toml"))
    harness.prepare(tmp_path)
    frames_of(world, tmp_path, 3, every=5)
    with harness.serve(tmp_path) as url:
        report = harness.drive(url, tmp_path / "shot.png", "controls")
    assert report["errors"] == [] and "error" not in report, report
    assert report["first"].startswith("step 0 ")
    # Playing asks for a frame after each one drawn; pausing stops asking.
    assert report["sent"][0] == "tick" and report["sent"].count("tick") >= 3
    assert report["saved"][:2] == [{"playing": True}, {"playing": False}]
    assert report["paused_answers"][0] == report["paused_answers"][1]
    assert report["button"] == "play"
    assert report["sent"][-1] == "step"
    assert report["stepped_status"] != report["paused_status"]


def hundred_thousand():
    """10^5 discs of radius 0.5 on a square grid in a periodic box, at random velocities."""
    n = 400
    spacing = 1.25
    config = bounce.Config(boundary="periodic", min=(0, 0), max=(n * spacing, 250 * spacing))
    world = bounce.World(config, dt=0.02)
    i, j = np.meshgrid(np.arange(n), np.arange(250), indexing="ij")
    positions = np.stack([(i.ravel() + 0.5) * spacing, (j.ravel() + 0.5) * spacing], axis=1)
    rng = np.random.default_rng(1)
    world.add_discs(positions=positions, velocities=rng.normal(size=(len(positions), 2)), radii=0.5)
    return world


def test_the_page_keeps_up_with_a_hundred_thousand_discs(tmp_path):
    # The frame rate is recorded (BENCHMARKS.md, from bench.py), not asserted: this checks the
    # pull loop runs at 10^5 discs and the page draws every disc of every frame it is sent.
    world = hundred_thousand()
    assert len(world) == 100_000
    harness.prepare(tmp_path)
    frames_of(world, tmp_path, 8, every=1)
    with harness.serve(tmp_path) as url:
        report = harness.drive(url, tmp_path / "shot.png", "fps")
    assert report["errors"] == [] and "error" not in report, report
    assert report["discs"] == 100_000 and report["renderer"] == "raster"
    assert report["fps"] > 0 and report["answers"] > 0
    print(f"\n10^5 discs: {report['fps']:.1f} frames/s drawn, median draw {report['draw_ms_median']:.1f} ms")


def test_the_example_notebook_runs(tmp_path):
    path = ROOT / "examples" / "python" / "live_view.ipynb"
    notebook = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        notebook, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}
    )
    client.execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    views = [o for o in outputs if "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert len(views) == 2  # the gas and the board, each displayed as a live widget
    text = "".join(o.get("text", "") for o in outputs)
    assert "step 1500 frames sent 301" in text
    assert "step 600 discs 500" in text
    json.dumps(notebook)  # the executed notebook is plain JSON


def test_the_view_plays_in_jupyterlab(tmp_path):
    # A real JupyterLab (its anywidget front end, its comm over the websocket, a real kernel):
    # the module loads, play steps the kernel's world frame after frame, pause stops it, step
    # advances one frame.
    harness.notebook(
        tmp_path / "gas.ipynb",
        "import bounce\nfrom bounce.widget import View\n"
        f"world = bounce.World.from_scenario({str(ROOT / 'scenarios' / 'gas.toml')!r})\n"
        "view = View(world, every=1)",
    )
    with harness.jupyterlab(tmp_path) as url:
        report = harness.drive_jupyterlab(url, "gas.ipynb", tmp_path / "lab.png", seconds=3)
    assert report["errors"] == [] and "error" not in report, report
    assert report["first"].startswith("step 0 · t = 0.0000 · 2000 discs")
    assert report["frames_per_second"] > 1 and report["draws_per_second"] > 1
    paused, later = report["paused"]
    assert paused == later
    assert report["stepped"].startswith(f"step {paused + 1} ")
