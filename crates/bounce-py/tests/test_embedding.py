"""Embedding from Python: World.contact_events() as a structured array, Sensor counts."""

import numpy as np
import pytest

import bounce


def head_on(**options):
    """Two discs of radius 1 (the seed's masses, 1 each), the second at rest."""
    world = bounce.World(bounce.Config(contact_events=True, **options), dt=0.01)
    world.add_discs([[0.0, 0.0], [2.5, 0.0]], [[1.0, 0.0], [0.0, 0.0]], 1.0)
    return world


def test_a_head_on_pair_begins_with_the_hand_impulse_and_ends():
    world = head_on()
    assert world.config.contact_events
    world.step(100)
    events = world.contact_events()
    assert events.dtype.names[:5] == ("step", "time", "substep", "kind", "a")
    assert list(events["kind"]) == ["begin", "end"]
    begin, end = events
    assert (begin["a"], begin["b_kind"], begin["b"]) == (0, "disc", 1)
    # Equal masses at e = 1 swap: the first stops, the second takes 1.
    assert begin["normal_impulse"] == pytest.approx(1.0, abs=1e-12)
    assert (begin["nx"], begin["ny"]) == (1.0, 0.0)
    assert begin["approach_speed"] == pytest.approx(1.0, abs=1e-15)
    assert end["step"] == begin["step"] + 1
    assert begin["time"] == pytest.approx(begin["step"] * 0.01)


def test_events_cover_every_step_of_a_call_and_walls_and_obstacles():
    config = bounce.Config(
        contact_events=True,
        boundary="walls",
        min=(0, 0),
        max=(10, 10),
        obstacles=[bounce.Obstacle.peg((5.0, 8.0), 1.0)],
    )
    world = bounce.World(config, dt=0.01)
    # Radius 0.5 (mass 0.5) at speed 2 into the left wall; one rising into the peg.
    world.add_discs([[3.0, 2.0], [5.0, 3.0]], [[-2.0, 0.0], [0.0, 2.0]], 0.5)
    world.step(300)
    events = world.contact_events()
    assert np.all(np.diff(events["step"].astype(np.int64)) >= 0)
    wall = events[(events["b_kind"] == "wall") & (events["kind"] == "begin")][0]
    assert (wall["a"], wall["b"]) == (0, 0)  # the left wall
    assert wall["normal_impulse"] == pytest.approx(2.0, abs=1e-12)
    peg = events[(events["b_kind"] == "obstacle") & (events["kind"] == "begin")][0]
    assert (peg["a"], peg["b"]) == (1, 0)
    assert peg["normal_impulse"] == pytest.approx(2.0, abs=1e-12)
    assert (peg["x"], peg["y"]) == pytest.approx((5.0, 7.0))
    # A later call starts a new list; without the switch there are none.
    world.step(1)
    assert len(world.contact_events()) <= 2
    quiet = bounce.World(bounce.Config(), dt=0.01)
    quiet.add_discs([[0.0, 0.0], [1.5, 0.0]], [[0.0, 0.0], [0.0, 0.0]], 1.0)
    quiet.step(3)
    assert len(quiet.contact_events()) == 0


def test_the_threshold_and_its_checks():
    world = head_on(contact_event_threshold=2.0)
    world.step(100)
    assert len(world.contact_events()) == 0, "an impulse of 1 is below 2"
    with pytest.raises(ValueError, match="contact_event_threshold"):
        bounce.Config(contact_event_threshold=-1.0)
    with pytest.raises(TypeError, match="contact_events"):
        bounce.Config(contact_events="yes")
    assert "contact_events=True" in repr(bounce.Config(contact_events=True))


def test_sensors_count_a_crossing_and_the_removals_of_a_sink():
    gate = bounce.Sensor("gate", min=(4.0, -1.0), max=(6.0, 1.0))
    ring = bounce.Sensor("ring", centre=(10.0, 0.0), radius=1.0)
    world = bounce.World(bounce.Config(sensors=[gate, ring]), dt=0.1)
    world.add_discs([[0.0, 0.0]], [[1.0, 0.0]], 0.1)
    world.step(100)
    assert world.sensors["gate"] == {
        "entered": 1,
        "left": 1,
        "inside": 0,
        "entered_last_step": 0,
        "left_last_step": 0,
    }
    # At x = 10 after 10 time units: inside the ring now.
    assert (world.sensors["ring"]["entered"], world.sensors["ring"]["inside"]) == (1, 1)
    # Rain into a sink under a sensor: every removal is counted as leaving.
    floor = bounce.Sensor("floor", min=(0.0, 0.0), max=(20.0, 2.0))
    config = bounce.Config(
        boundary="walls",
        min=(0, 0),
        max=(20, 30),
        gravity=(0, -9.81),
        emitters=[bounce.Emitter((2, 25), (18, 29), rate=50, radius=0.3)],
        sinks=[bounce.Sink((0, 0), (20, 2))],
        sensors=[floor],
    )
    rain = bounce.World(config, dt=0.01)
    removed = 0
    for _ in range(300):
        rain.step()
        removed += rain.stats["removed"]
    counts = rain.sensors["floor"]
    assert removed > 10 and counts["entered"] == counts["left"] == removed
    with pytest.raises(ValueError, match="box"):
        bounce.Sensor("half", min=(0.0, 0.0))
    with pytest.raises(ValueError, match="name of its own"):
        bounce.Config(sensors=[gate, gate])


def test_queries_answer_by_id_as_brute_force_does():
    rng = np.random.default_rng(7)
    config = bounce.Config(boundary="walls", min=(0, 0), max=(50, 40))
    world = bounce.World(config, dt=0.01)
    positions = rng.uniform((1, 1), (49, 39), size=(600, 2))
    radii = rng.uniform(0.1, 0.5, size=600)
    world.add_discs(positions, np.zeros((600, 2)), radii)
    queries = world.queries()
    assert len(queries) == 600
    for _ in range(200):
        p = rng.uniform((0, 0), (50, 40))
        r = rng.uniform(0, 5)
        distance = np.hypot(*(positions - p).T)
        assert list(queries.in_circle(tuple(p), r)) == list(np.flatnonzero(distance <= r + radii))
        gap = distance - radii
        nearest, d = queries.nearest(tuple(p))
        assert nearest == np.argmin(gap) and d == pytest.approx(gap.min(), abs=1e-12)
    hit = queries.ray_cast((0.0, 20.0), (1.0, 0.0), 50.0)
    assert hit is not None and hit["normal"][0] < 0
    first = min(
        (x - np.sqrt(r * r - (20 - y) ** 2), k)
        for k, ((x, y), r) in enumerate(zip(positions, radii))
        if abs(20 - y) < r
    )
    assert hit["id"] == first[1] and hit["fraction"] == pytest.approx(first[0], abs=1e-9)
    assert queries.ray_cast((0.0, 20.0), (-1.0, 0.0), 50.0) is None


def test_tags_follow_discs_through_steps_saves_and_gsd(tmp_path):
    config = bounce.Config(boundary="periodic", min=(0, 0), max=(30, 30))
    world = bounce.World(config, dt=0.05, threads=2)
    rng = np.random.default_rng(3)
    side = np.arange(15) * 2.0 + 1.0
    positions = np.stack(np.meshgrid(side, side), axis=-1).reshape(-1, 2)
    tags = rng.integers(0, 2**63, size=len(positions), dtype=np.uint64)
    tags[0] = 2**64 - 1
    world.add_discs(positions, rng.normal(size=positions.shape), 0.4, tags=tags)
    world.step(200)
    assert world.tags.dtype == np.uint64
    assert np.array_equal(world.tags, tags)
    world.tags = tags[::-1].copy()
    world.save(str(tmp_path / "w.bin"))
    loaded = bounce.World.load(str(tmp_path / "w.bin"), dt=0.05)
    assert np.array_equal(loaded.tags, tags[::-1])
    import gsd.hoomd

    with bounce.GSDWriter(str(tmp_path / "t.gsd"), every=1) as writer:
        loaded.add_writer(writer)
        loaded.step(2)
    with gsd.hoomd.open(str(tmp_path / "t.gsd")) as trajectory:
        assert np.array_equal(trajectory[-1].log["particles/tag"], tags[::-1])
    with pytest.raises(ValueError, match="tags has 2 values"):
        world.tags = [1, 2]
    with pytest.raises(TypeError, match="tags must be integers"):
        world.tags = [-1] * len(tags)
