"""Rough discs from Python: the friction keywords, angular velocities and orientations,
a disc rolling down an incline, the stats, the storage view and the trajectory."""

import math

import numpy as np
import pytest

import bounce


def rough_box(**kwargs):
    config = bounce.Config(boundary="walls", min=(0, 0), max=(20, 20), **kwargs)
    world = bounce.World(config, dt=0.01)
    return world


def test_the_friction_keywords_round_trip_and_bad_values_are_refused():
    config = bounce.Config(
        friction=0.4,
        wall_friction=0.8,
        tangential_restitution=0.2,
        rolling_resistance=0.01,
        inertia_factor=0.4,
    )
    assert (config.friction, config.wall_friction, config.tangential_restitution) == (
        0.4,
        0.8,
        0.2,
    )
    assert (config.rolling_resistance, config.inertia_factor) == (0.01, 0.4)
    assert "friction=0.4" in repr(config)
    # The seed's smooth discs by default.
    plain = bounce.Config()
    assert (plain.friction, plain.wall_friction, plain.inertia_factor) == (0.0, None, 0.5)
    assert "friction" not in repr(plain)
    for key, value in [
        ("friction", -1.0),
        ("tangential_restitution", 1.5),
        ("rolling_resistance", float("nan")),
        ("inertia_factor", 0.0),
    ]:
        with pytest.raises(ValueError, match=key):
            bounce.Config(**{key: value})
    with pytest.raises(ValueError, match="friction"):
        bounce.Obstacle.segment((0, 0), (1, 0), friction=-0.5)
    assert bounce.Obstacle.peg((0, 0), 1.0, friction=0.3).friction == 0.3
    assert all(s.friction == 0.7 for s in bounce.polyline([(0, 0), (1, 0), (1, 1)], friction=0.7))


def test_angular_velocities_are_set_and_read_in_id_order():
    world = rough_box()
    world.add_discs([(5, 5), (10, 10), (15, 5)], [(0, 0)] * 3, 0.5)
    np.testing.assert_array_equal(world.angular_velocities, [0, 0, 0])
    with world.storage_view() as v:
        assert len(v.omega) == 0  # smooth discs that never turned keep no rotation
    world.angular_velocities = [1.0, -2.0, 0.5]
    np.testing.assert_array_equal(world.angular_velocities, [1.0, -2.0, 0.5])
    world.step(10)  # 0.1 time units, nothing touches: each turns by ω t
    np.testing.assert_allclose(
        world.orientations, np.mod([0.1, -0.2, 0.05], 2 * np.pi), atol=1e-12
    )
    with world.storage_view() as v:
        assert sorted(v.omega) == [-2.0, 0.5, 1.0]
    with pytest.raises(ValueError, match="disc 1"):
        world.angular_velocities = [1.0, float("inf"), 0.0]
    with pytest.raises(ValueError):
        world.angular_velocities = [1.0]


def test_a_disc_rolls_down_an_incline_at_two_thirds_of_g_sin_theta():
    theta = math.radians(20)
    c, s = math.cos(theta), math.sin(theta)
    slope = bounce.Obstacle.segment((-40 * c, 40 * s), (40 * c, -40 * s))
    config = bounce.Config(gravity=(0, -10), friction=0.5, substeps=4, obstacles=[slope])
    world = bounce.World(config, dt=0.001)
    start = np.array([-20 * c + 0.5 * s, 20 * s + 0.5 * c])
    world.add_discs([start], [(0, 0)], 0.5)
    world.step(1500)
    travelled = np.dot(world.positions[0] - start, [c, -s])
    assert 2 * travelled / 1.5**2 == pytest.approx(2 / 3 * 10 * s, rel=0.01)
    v2 = np.sum(world.velocities[0] ** 2)
    rotational = 0.5 * (0.5 * 0.5 * 0.25) * world.angular_velocities[0] ** 2
    assert rotational / (0.5 * 0.5 * v2) == pytest.approx(0.5, rel=0.01)


def test_the_stats_balance_energy_with_friction_work():
    world = rough_box(friction=0.3)
    rng = np.random.default_rng(3)
    k = np.arange(100)
    positions = np.stack([2 + 1.6 * (k % 10), 2 + 1.6 * (k // 10)], axis=1)
    world.add_discs(positions, rng.uniform(-3, 3, (100, 2)), 0.5)
    world.angular_velocities = rng.uniform(-4, 4, 100)
    start = world.stats["kinetic_energy"] + world.stats["rotational_energy"]
    world.step(300)
    stats = world.stats
    assert world.friction_work > 0.01 * start
    assert stats["kinetic_energy"] + stats["rotational_energy"] + world.friction_work == (
        pytest.approx(start, rel=1e-9)
    )
    assert isinstance(stats["angular_momentum"], float)


def test_the_trajectory_holds_the_rotation_as_hoomd_writes_it(tmp_path):
    import gsd.hoomd as gsd_hoomd  # scripts/test installs it

    world = rough_box(friction=0.5)
    world.add_discs([(5, 5), (10, 10)], [(1, 0), (0, 0)], 0.5)
    world.angular_velocities = [2.0, -1.0]
    world.step(30)
    path = tmp_path / "spin.gsd"
    world.write_gsd(path)
    with gsd_hoomd.open(path) as trajectory:
        p = trajectory[0].particles
        inertia = 0.5 * 0.5 * 0.25  # k m r², the seed's mass = radius
        np.testing.assert_allclose(p.moment_inertia, [[0, 0, inertia]] * 2, rtol=1e-6)
        half = world.orientations / 2
        np.testing.assert_allclose(
            p.orientation,
            np.stack([np.cos(half), 0 * half, 0 * half, np.sin(half)], axis=1),
            atol=1e-6,
        )
        l = inertia * world.angular_velocities
        np.testing.assert_allclose(
            p.angmom,
            np.stack([-2 * np.sin(half) * l, 0 * l, 0 * l, 2 * np.cos(half) * l], axis=1),
            atol=1e-6,
        )
