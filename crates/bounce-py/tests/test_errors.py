"""Every bad input raises with a message that names the problem; nothing half-done."""

import numpy as np
import pytest

import bounce


def test_config_errors_name_the_field_and_value():
    with pytest.raises(ValueError, match=r"`coefficient_of_restitution` = -1"):
        bounce.Config(coefficient_of_restitution=-1.0)
    with pytest.raises(ValueError, match=r"`substeps` = 0"):
        bounce.Config(substeps=0)
    with pytest.raises(ValueError, match=r"`restitution_model` = \"elastic\""):
        bounce.Config(restitution_model="elastic")
    with pytest.raises(ValueError, match=r"`min` is missing"):
        bounce.Config(boundary="walls", max=(1, 1))
    with pytest.raises(ValueError, match="boundary"):
        bounce.Config(boundary="box", min=(0, 0), max=(1, 1))
    with pytest.raises(ValueError, match=r"`boundary` = min \[0.0, 0.0\], max \[0.0, 1.0\]"):
        bounce.Config(boundary="walls", min=(0, 0), max=(0, 1))
    with pytest.raises(TypeError, match="unexpected keyword argument 'restitution'"):
        bounce.Config(restitution=0.5)
    with pytest.raises(TypeError, match=r"gravity=...\): expected two numbers"):
        bounce.Config(gravity=(1, 2, 3))
    with pytest.raises(TypeError, match="substeps"):
        bounce.Config(substeps="four")


def test_config_round_trips_its_options():
    config = bounce.Config(
        boundary="walls",
        min=(0, 0),
        max=(10, 20),
        wall_restitution=0.5,
        gravity=(0, -9.81),
        solver_iterations=4,
        max_travel=0.25,
        mass_model="area",
        restitution_model="relative_normal_velocity",
        velocity_update="approaching_only",
        resting_contacts="rest",
    )
    assert config.max == (10.0, 20.0) and config.wall_restitution == 0.5
    assert config.gravity == (0.0, -9.81) and config.solver_iterations == 4
    assert config.max_travel == 0.25 and config.mass_model == "area"
    assert config.restitution_model == "relative_normal_velocity"
    assert config.velocity_update == "approaching_only"
    assert config.resting_contacts == "rest" and bounce.Config().resting_contacts == "bounce"
    with pytest.raises(ValueError, match=r"`resting_contacts` = \"still\": must be one of"):
        bounce.Config(resting_contacts="still")
    assert bounce.World(config).config == config
    assert "wall_restitution=0.5" in repr(config)


def test_bad_discs_name_their_row_and_leave_the_world_unchanged():
    world = bounce.World(bounce.Config(boundary="walls", min=(0, 0), max=(10, 10)), dt=0.1)
    world.add_discs([[5, 5]], [[0, 0]], 1.0)
    cases = [
        ([[2, 2], [np.nan, 3]], [[0, 0], [0, 0]], 0.5, "disc 1: .*position"),
        ([[2, 2], [3, 3]], [[0, 0], [np.inf, 0]], 0.5, "disc 1: .*velocity"),
        ([[2, 2], [3, 3]], [[0, 0], [0, 0]], [0.5, -1.0], "disc 1: .*radius"),
        ([[2, 2], [30, 3]], [[0, 0], [0, 0]], 0.5, r"disc 1: centre \[30.0, 3.0\] is outside"),
        ([[2, 2], [3, 3]], [[0, 0]], 0.5, "velocities has 1 rows; expected 2"),
        ([2, 2], [0, 0], 0.5, r"positions must have shape \(N, 2\); got \(2,\)"),
        ([[2, 2, 2]], [[0, 0]], 0.5, r"got \(1, 3\)"),
        ([[2, 2]], [[0, 0]], [0.5, 0.5], "radii has 2 rows; expected 1"),
        ([["a", "b"]], [[0, 0]], 0.5, "positions: cannot be read as an array of numbers"),
    ]
    for positions, velocities, radii, message in cases:
        with pytest.raises(ValueError, match=message):
            world.add_discs(positions, velocities, radii)
        assert len(world) == 1
    with pytest.raises(ValueError, match="disc 0: .*mass"):
        world.add_discs([[2, 2]], [[0, 0]], 0.5, masses=[0.0])


def test_stepping_needs_a_valid_time_step():
    world = bounce.World()
    world.add_discs([[0, 0]], [[1, 0]], 1.0)
    with pytest.raises(ValueError, match="step\\(\\) needs dt"):
        world.step()
    with pytest.raises(RuntimeError, match="dt = -1"):
        world.step(dt=-1.0)
    with pytest.raises(ValueError, match="dt = 0"):
        bounce.World(dt=0.0)
    world.step(dt=0.5)
    assert world.time == 0.5 and world.step_count == 1


def test_a_step_that_overflows_raises_and_names_the_disc():
    world = bounce.World(bounce.Config(gravity=(0, -1e308)), dt=1e10)
    world.add_discs([[0, 0], [10, 0]], [[0, 0], [0, 0]], 1.0)
    with pytest.raises(RuntimeError, match="non-finite"):
        world.step()


def test_files_that_are_missing_or_wrong_are_named(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere.toml"):
        bounce.World.from_scenario(tmp_path / "nowhere.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[world]\nboundary = 'walls'\nmin = [0, 0]\nmax = [10, 10]\n"
                   "coefficient_of_restitution = 2.0\n[time]\ndt = 0.01\nsteps = 10\n")
    with pytest.raises(ValueError, match=r"bad.toml.*coefficient_of_restitution"):
        bounce.World.from_scenario(bad)
    with pytest.raises(FileNotFoundError, match="nothing.bin"):
        bounce.World.load(tmp_path / "nothing.bin")
    junk = tmp_path / "junk.bin"
    junk.write_bytes(b"not a checkpoint")
    with pytest.raises(ValueError, match="junk.bin"):
        bounce.World.load(junk)
    with pytest.raises(ValueError, match="every = 0"):
        bounce.GSDWriter(tmp_path / "t.gsd", every=0)


def test_a_profile_of_a_trillion_bins_is_refused_not_an_abort():
    """Issue 60: `profiles(axis, 10**12)` aborted the interpreter allocating its bins; the
    command line's limit holds for Python too."""
    world = bounce.World(bounce.Config(boundary="walls", min=(0, 0), max=(10, 10)), dt=0.01)
    world.add_discs([[5, 5]], [[1, 0]], 0.5)
    with pytest.raises(ValueError, match=r"bins = 1000000000000: a profile has 1 to 100000 bins"):
        world.profiles("y", 10**12)
    assert len(world.profiles("y", 4)["count"]) == 4
