"""A live view of a :class:`bounce.World` in a notebook: ``bounce.widget.View``.

An `anywidget <https://anywidget.dev>`_ widget, so it works in JupyterLab, Notebook 7 and
VS Code (``pip install anywidget``)::

    import bounce
    from bounce.widget import View

    world = bounce.World.from_scenario("scenarios/gas.toml")
    view = View(world, every=5)
    view                      # shows the canvas, the controls and the speed histogram
    view.run(2000)            # steps 2,000 steps, drawing every 5th

The page (``widget.js``) draws the discs with WebGL on a GPU (a CPU raster on a 2D canvas
where WebGL is missing or software),
coloured by speed (or radius), the obstacles, and the speed histogram against the 2D
Maxwell–Boltzmann curve at the discs' temperature. Its ``play`` button asks Python for a frame
each time it has drawn one, so a playing view runs as fast as the page draws and never queues
frames; ``step`` advances ``every`` steps. While a cell runs (``view.run``), the kernel reads
no button until the cell ends: ``run`` is the way to animate from code.

Positions travel as binary buffers, not JSON: f32 ``x, y`` a disc, f32 radii (sent again only
when the discs change) and one byte a disc for the colour.
"""

import math
import pathlib
import time

try:
    import anywidget
    import traitlets
except ImportError as e:  # pragma: no cover - the message is the point
    raise ImportError(
        "bounce.widget needs anywidget: pip install anywidget (it brings ipywidgets)"
    ) from e

import numpy as np

from ._native import World, speed_histogram

__all__ = ["View"]


def _bounds(world, margin=0.05):
    """The rectangle the view shows: the box, or in an open world the discs' extent."""
    config = world.config
    if config.min is not None and config.max is not None:
        (x0, y0), (x1, y1) = config.min, config.max
        return [float(x0), float(y0), float(x1), float(y1)]
    if len(world) == 0:
        return [-10.0, -10.0, 10.0, 10.0]
    p = world.positions
    r = world.radii.max()
    lo = p.min(axis=0) - r
    hi = p.max(axis=0) + r
    pad = margin * max(hi[0] - lo[0], hi[1] - lo[1], 1e-9)
    return [float(lo[0] - pad), float(lo[1] - pad), float(hi[0] + pad), float(hi[1] + pad)]


def _obstacles(world):
    """Segments and pegs where they are now, as the page draws them."""
    out = []
    for o in world.obstacles:
        if o.kind == "segment":
            a, b = o.ends
            out.append({"kind": "segment", "a": list(a), "b": list(b)})
        else:
            out.append({"kind": "peg", "centre": list(o.centre), "radius": o.radius})
    return out


class View(anywidget.AnyWidget):
    """A live view of ``world``: ``View(world, every=1, colour_by="speed", width=640,
    histogram=True, renderer="auto", max_fps=30)``.

    - ``every``: steps between frames (``run``, the ``step`` button, each frame while playing).
    - ``colour_by``: ``"speed"`` (the ramp up to ``speed_scale``, by default three times the
      discs' RMS speed when the view was made, so colours compare across frames) or
      ``"radius"`` (smallest to largest).
    - ``width``: the canvas's width in CSS pixels; its height follows the box's shape.
    - ``histogram``: show the speed histogram against Maxwell–Boltzmann (computed in Rust,
      :func:`bounce.speed_histogram`, with ``bins`` bins).
    - ``renderer``: ``"auto"`` (WebGL on a GPU; where WebGL is missing or drawn in software,
      a CPU raster on a 2D canvas, faster there), ``"webgl"`` or ``"raster"``.
    - ``max_fps``: ``run`` sends at most this many frames a second, waiting in between, so
      the page shows every frame it is sent.
    """

    _esm = pathlib.Path(__file__).parent / "widget.js"

    positions = traitlets.Bytes(b"").tag(sync=True)
    radii = traitlets.Bytes(b"").tag(sync=True)
    shades = traitlets.Bytes(b"").tag(sync=True)
    bounds = traitlets.List([0.0, 0.0, 1.0, 1.0]).tag(sync=True)
    obstacles = traitlets.List([]).tag(sync=True)
    frame = traitlets.Dict({}).tag(sync=True)
    playing = traitlets.Bool(False).tag(sync=True)
    width = traitlets.Int(640).tag(sync=True)
    histogram = traitlets.Bool(True).tag(sync=True)
    renderer = traitlets.Unicode("auto").tag(sync=True)

    def __init__(
        self,
        world,
        every=1,
        colour_by="speed",
        width=640,
        histogram=True,
        renderer="auto",
        max_fps=30.0,
        speed_scale=None,
        bins=30,
    ):
        if not isinstance(world, World):
            raise TypeError(f"View needs a bounce.World, got {type(world).__name__}")
        if colour_by not in ("speed", "radius"):
            raise ValueError(f'colour_by = {colour_by!r}: expected "speed" or "radius"')
        if renderer not in ("auto", "webgl", "raster"):
            raise ValueError(f'renderer = {renderer!r}: expected "auto", "webgl" or "raster"')
        super().__init__(width=int(width), histogram=bool(histogram), renderer=renderer)
        self.world = world
        self.every = every
        self.max_fps = max_fps
        self.bins = int(bins)
        self.colour_by = colour_by
        self.frames_sent = 0
        self._radii_of = None
        self._last_sent = 0.0
        self.speed_scale = speed_scale if speed_scale is not None else self._default_speed_scale()
        self.on_msg(self._on_message)
        self.fit()
        self.push()

    @property
    def every(self):
        """Steps between frames (at least 1)."""
        return self._every

    @every.setter
    def every(self, value):
        value = int(value)
        if value < 1:
            raise ValueError(f"every = {value}: expected at least 1 step between frames")
        self._every = value

    def _default_speed_scale(self):
        v = self.world.velocities
        rms = math.sqrt(float((v**2).sum(axis=1).mean())) if len(v) else 0.0
        return 3.0 * rms if rms > 0 else 1.0

    def fit(self):
        """Frames the view on the box (or, in an open world, on where the discs are now)."""
        self.bounds = _bounds(self.world)

    def _shades(self, radii, vx, vy):
        if self.colour_by == "radius":
            lo, hi = (float(radii.min()), float(radii.max())) if len(radii) else (0.0, 0.0)
            t = (radii - lo) / (hi - lo) if hi > lo else np.full(len(radii), 0.5)
        else:
            t = np.hypot(vx, vy) / self.speed_scale
        return (np.clip(np.nan_to_num(t, nan=1.0), 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)

    def push(self):
        """Sends the world as it is now to the page (one frame)."""
        world = self.world
        with world.storage_view() as v:
            x, y, vx, vy, r = v.x, v.y, v.vx, v.vy, v.radius
            positions = np.empty((len(x), 2), dtype=np.float32)
            positions[:, 0] = x
            positions[:, 1] = y
            radii = r.astype(np.float32)
            shades = self._shades(r, vx, vy)
        frame = {"step": int(world.step_count), "time": float(world.time), "discs": len(world)}
        if self.histogram and len(world) > 0:
            h = speed_histogram(world, self.bins)
            frame["histogram"] = {
                "width": h["width"],
                "density": h["density"].tolist(),
                "kt": h["kt"],
                "curve": h["curve"][::4].tolist(),
            }
        radii_bytes = radii.tobytes()
        with self.hold_sync():
            self.positions = positions.tobytes()
            # Radii change only when discs are added or removed: sent again only then.
            if radii_bytes != self._radii_of:
                self.radii = radii_bytes
                self._radii_of = radii_bytes
            self.shades = shades.tobytes()
            self.obstacles = _obstacles(world)
            self.frame = frame
        self.frames_sent += 1
        self._last_sent = time.monotonic()

    def step(self, frames=1):
        """Steps ``frames`` frames of ``every`` steps, sending each."""
        for _ in range(int(frames)):
            self.world.step(self.every)
            self.push()

    def run(self, steps, every=None):
        """Steps the world ``steps`` steps, sending a frame every ``every`` steps (default:
        the view's ``every``) and at the end, at most ``max_fps`` frames a second."""
        if every is not None:
            self.every = every
        left = int(steps)
        while left > 0:
            n = min(self.every, left)
            self.world.step(n)
            left -= n
            if self.max_fps:
                wait = self._last_sent + 1.0 / self.max_fps - time.monotonic()
                if wait > 0:
                    time.sleep(wait)
            self.push()

    def _on_message(self, _widget, content, _buffers):
        kind = content.get("type") if isinstance(content, dict) else None
        if kind == "step" or (kind == "tick" and self.playing):
            self.step()
