"""Emitters and sinks from Python, and the command line's GSD with a varying N."""

import gsd.hoomd
import numpy as np
import pytest

import bounce
from conftest import run_cli


def flow(threads=1):
    config = bounce.Config(
        boundary="walls",
        min=(0, 0),
        max=(40, 20),
        emitters=[bounce.Emitter((1, 2), (3, 18), rate=50, radius=(0.3, 0.4), velocity=(8, 0), seed=4)],
        sinks=[bounce.Sink((35, 0), (40, 20))],
    )
    return bounce.World(config, dt=0.02, threads=threads)


def test_discs_come_in_at_the_rate_and_leave_through_the_sink():
    world = flow()
    emitted = removed = 0
    for _ in range(300):
        world.step()
        emitted += world.stats["emitted"]
        removed += world.stats["removed"]
    # 6 time units at 50 per unit.
    assert 280 <= emitted <= 300
    assert removed > 60
    assert len(world) == emitted - removed
    # Ids are never reused: arrays in id order skip the removed ones.
    ids = world.ids
    assert len(ids) == len(world) and np.all(np.diff(ids) > 0)
    assert ids[0] >= removed - 50  # the oldest have left
    assert np.all(world.positions[:, 0] < 35)


def test_the_same_bits_on_any_thread_count():
    a, b = flow(1), flow(2)
    a.step(200)
    b.step(200)
    assert a.state_hash() == b.state_hash()


def test_bad_emitters_and_sinks_are_refused():
    with pytest.raises(ValueError, match="rate"):
        bounce.Emitter((0, 0), (1, 1), rate=-1, radius=0.5)
    with pytest.raises(ValueError, match="min below max"):
        bounce.Sink((1, 1), (0, 2))


def test_the_gsd_of_an_emptying_box_has_a_varying_number_of_discs(bounce_bin, tmp_path):
    scenario = tmp_path / "effusion.toml"
    run_cli(bounce_bin, "new", "effusion", "--out", scenario)
    run_cli(bounce_bin, "run", scenario, "--steps", 3000, "--out", tmp_path / "run", "-q")
    with gsd.hoomd.open(tmp_path / "run" / "trajectory.gsd") as trajectory:
        counts = [frame.particles.N for frame in trajectory]
        last = trajectory[-1]
    assert counts[0] == 600 and counts[-1] < counts[0]
    assert all(b <= a for a, b in zip(counts, counts[1:]))
    assert last.particles.position.shape == (counts[-1], 3)
    csv = (tmp_path / "run" / "stats.csv").read_text().splitlines()
    assert csv[0].split(",")[12] == "particles"
    assert int(csv[-1].split(",")[12]) == counts[-1]


def test_discs_an_emitter_adds_keep_its_type_in_gsd_files(tmp_path):
    """A scenario's emitter of `type = "grain"`: the discs it adds are grains in the GSD
    file Python writes, as in the command line's (not the first type, as they once were)."""
    scenario = tmp_path / "pour.toml"
    scenario.write_text(
        "[world]\nmin = [0.0, 0.0]\nmax = [20.0, 20.0]\ngravity = [0.0, -9.81]\n"
        "[time]\ndt = 0.01\nsteps = 100\n"
        "[[disc]]\nposition = [10.0, 1.0]\nradius = 0.5\ntype = \"ball\"\n"
        "[[emitter]]\nregion = { min = [5.0, 15.0], max = [15.0, 18.0] }\nrate = 40\n"
        "radius = 0.3\ntype = \"grain\"\n"
    )
    world = bounce.World.from_scenario(scenario)
    path = tmp_path / "pour.gsd"
    with bounce.GSDWriter(path, every=50) as gsd_file:
        world.add_writer(gsd_file)
        world.step(100)
    with gsd.hoomd.open(str(path)) as frames:
        last = frames[-1]
        types = [last.particles.types[t] for t in last.particles.typeid]
    assert types[0] == "ball"
    assert len(types) > 20 and all(t == "grain" for t in types[1:]), types
