"""bounce: a fast, faithful, deterministic 2D particle collision simulator.

The same engine as the ``bounce`` command, driven from Python with NumPy arrays::

    import numpy as np
    import bounce

    config = bounce.Config(boundary="walls", min=(0, 0), max=(50, 50))
    world = bounce.World(config, dt=0.01)
    world.add_discs(positions=[[10, 25], [40, 25]], velocities=[[5, 0], [-5, 0]], radii=1.0)
    world.step(100)
    print(world.positions, world.stats["kinetic_energy"])

``World.from_scenario(path)`` runs the TOML scenarios of the command line with the same
ids and bits: ``world.state_hash()`` after N steps equals the hash ``bounce run`` prints.

Obstacles (segments and pegs, fixed or moving) go in ``Config(obstacles=[...])`` or
``world.add_obstacles([...])``; ``polyline`` and ``rectangle`` make lists of segments.
``Config(emitters=[Emitter(...)], sinks=[Sink(...)])`` add and remove discs during a run
(ids are never reused; arrays in id order skip the removed ones); ``Config(sensors=[Sensor(...)])``
count the discs entering and leaving regions (``World.sensors``), and
``Config(contact_events=True)`` records what began and ended touching
(``World.contact_events()``). ``rdf``, ``psi6`` and ``msd`` read a GSD trajectory's
structure (g(r), the bond order |ψ6| per frame, the mean-square displacement), as
``bounce analyze`` does; ``speed_histogram`` is a world's speeds against Maxwell–Boltzmann.
``bounce.widget.View(world)`` is a live view in a notebook (needs ``anywidget``).

Classes: :class:`Config`, :class:`World`, :class:`Obstacle`, :class:`StorageView`,
:class:`GSDWriter`.
"""

from ._native import (
    Config,
    Emitter,
    GSDWriter,
    Obstacle,
    Queries,
    Sensor,
    Sink,
    StorageView,
    World,
    __version__,
    msd,
    polyline,
    psi6,
    rdf,
    rectangle,
    speed_histogram,
)

__all__ = [
    "Config",
    "World",
    "Obstacle",
    "polyline",
    "rectangle",
    "Emitter",
    "Sink",
    "Sensor",
    "Queries",
    "StorageView",
    "GSDWriter",
    "rdf",
    "psi6",
    "msd",
    "speed_histogram",
    "sweep",
    "__version__",
]


def sweep(sweep_file, out="sweep", jobs=1, command="bounce"):
    """Runs ``bounce sweep SWEEP_FILE --out OUT --jobs JOBS`` (the command line's parameter
    sweep into a signac workspace; ``command`` is the ``bounce`` executable) and returns the
    workspace as a signac project when signac is installed, else ``summary.csv``'s rows as
    a list of dicts (one per finished job: its id, settings and last stats row).

    Raises ``RuntimeError`` with the command's message when the sweep fails.
    """
    import csv
    import pathlib
    import subprocess

    done = subprocess.run(
        [str(command), "sweep", str(sweep_file), "--out", str(out), "--jobs", str(int(jobs))],
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        raise RuntimeError((done.stderr or done.stdout).strip())
    try:
        import signac
    except ImportError:
        with open(pathlib.Path(out) / "summary.csv", newline="") as f:
            return list(csv.DictReader(f))
    return signac.get_project(str(out))
