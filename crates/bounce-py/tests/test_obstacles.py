"""Obstacles from Python: the collision rule against an immovable body, by hand; a piston's
work; the same bits as the command line's scenarios with obstacles."""

import math
import re

import numpy as np
import pytest

import bounce
from conftest import run_cli


def test_a_disc_on_a_floor_segment_is_pushed_out_by_the_whole_overlap_and_bounces():
    # A floor from (-5, 0) to (5, 0) with restitution 0.5; a disc of radius 0.5 at height
    # 0.45 moving (3, -2): one step of dt = 0.01 moves it to y = 0.43 first, then it is
    # pushed up to 0.5 (the whole overlap) and leaves at vy = +1 (reversed, scaled).
    floor = bounce.Obstacle.segment((-5, 0), (5, 0), restitution=0.5)
    world = bounce.World(bounce.Config(obstacles=[floor]), dt=0.01)
    world.add_discs([[1.0, 0.45]], [[3.0, -2.0]], 0.5)
    world.step()
    assert world.positions[0].tolist() == pytest.approx([1.03, 0.5], abs=1e-12)
    assert world.velocities[0].tolist() == pytest.approx([3.0, 1.0], abs=1e-12)
    # The floor received m (1 + e) |vn| = 0.5 * 1.5 * 2 downwards (mass = radius).
    assert world.obstacle_impulses_last_step[0].tolist() == pytest.approx([0.0, -1.5], abs=1e-12)
    # The total adds up every step: another step off the floor adds nothing.
    world.step()
    assert world.obstacle_impulses_last_step[0].tolist() == [0.0, 0.0]
    assert world.obstacle_impulses_total[0].tolist() == pytest.approx([0.0, -1.5], abs=1e-12)


def test_a_peg_deflects_a_disc_along_the_line_of_centres():
    # Peg of radius 1 at the origin; a disc of radius 0.5 coming in along 45 degrees hits
    # it head on and, at e = 1, leaves along the same line reversed.
    peg = bounce.Obstacle.peg((0, 0), 1.0)
    world = bounce.World(bounce.Config(obstacles=[peg]), dt=0.01)
    d = 3.0 / math.sqrt(2)
    world.add_discs([[d, d]], [[-1.0, -1.0]], 0.5)
    world.step(300)
    vx, vy = world.velocities[0]
    assert vx == pytest.approx(1.0, abs=1e-9) and vy == pytest.approx(1.0, abs=1e-9)
    x, y = world.positions[0]
    assert math.hypot(x, y) > 1.5


def test_obstacles_are_checked_and_described():
    with pytest.raises(ValueError, match="the ends must differ"):
        bounce.Obstacle.segment((1, 1), (1, 1))
    with pytest.raises(ValueError, match="must be finite and > 0"):
        bounce.Obstacle.peg((0, 0), -1.0)
    with pytest.raises(ValueError, match="restitution"):
        bounce.Obstacle.peg((0, 0), 1.0, restitution=2.0)
    with pytest.raises(TypeError, match="force and mass"):
        bounce.Obstacle.segment((0, 0), (1, 0), force=(0, -1))
    with pytest.raises(TypeError, match="bounce.Obstacle"):
        bounce.Config(obstacles=[1, 2])
    box = bounce.rectangle((5, 5), (2, 4), angle=math.pi / 2)
    assert [o.kind for o in box] == ["segment"] * 4
    # Rotated a quarter turn, the 2 × 4 box spans 4 along x.
    xs = [p[0] for o in box for p in o.ends]
    assert max(xs) - min(xs) == pytest.approx(4.0)
    funnel = bounce.polyline([(0, 10), (4, 6), (6, 6), (10, 10)])
    assert len(funnel) == 3 and funnel[1].ends == ((4.0, 6.0), (6.0, 6.0))
    config = bounce.Config(obstacles=funnel)
    assert config.obstacles == funnel
    assert "3 obstacles" in repr(config)
    assert repr(bounce.Obstacle.peg((1, 2), 0.5)) == "Obstacle.peg((1, 2), 0.5)"


def test_a_piston_does_work_equal_to_the_gain_in_kinetic_energy():
    # An elastic gas under a piston moving down at 0.05, well below the thermal speed.
    config = bounce.Config(
        boundary="walls",
        min=(0, 0),
        max=(20, 30),
        obstacles=[bounce.Obstacle.segment((0, 25), (20, 25), velocity=(0, -0.05))],
    )
    world = bounce.World(config, dt=0.02)
    rng = np.random.default_rng(3)
    side = np.arange(10) * 2.0 + 1.0
    positions = np.array([[x, y] for x in side for y in side])
    world.add_discs(positions, rng.normal(size=(100, 2)), 0.5)
    before = world.stats["kinetic_energy"]
    world.step(5000)
    gain = world.stats["kinetic_energy"] - before
    assert gain > 0.2 * before
    assert world.obstacle_work == pytest.approx(gain, rel=0.01)
    (piston,) = world.obstacles
    assert piston.ends[0][1] == pytest.approx(25 - 0.05 * 0.02 * 5000)


def test_drawn_obstacles_join_a_running_world_and_keep_the_pistons_motion():
    config = bounce.Config(
        boundary="walls",
        min=(0, 0),
        max=(20, 20),
        obstacles=[bounce.Obstacle.segment((0, 15), (20, 15), velocity=(0, -0.1))],
    )
    world = bounce.World(config, dt=0.1)
    world.step(10)
    world.add_obstacles([bounce.Obstacle.peg((10, 5), 1.0)])
    assert [o.kind for o in world.obstacles] == ["segment", "peg"]
    assert world.obstacles[0].ends[0][1] == pytest.approx(14.9)
    # A world keeps counting impulses for every obstacle, the new one too.
    world.step(5)
    assert world.obstacle_impulses_last_step.shape == (2, 2)
    assert world.obstacle_impulses_total.shape == (2, 2)


@pytest.mark.parametrize("name, steps", [("galton-board", 200), ("piston", 300)])
def test_obstacle_scenarios_give_the_command_lines_bits(bounce_bin, tmp_path, name, steps):
    scenario = tmp_path / f"{name}.toml"
    run_cli(bounce_bin, "new", name, "--out", scenario)
    out = run_cli(
        bounce_bin, "run", scenario, "--steps", steps, "--out", tmp_path / "run", "-q"
    )
    cli_hash = re.search(r"state hash ([0-9a-f]{16})", out).group(1)
    world = bounce.World.from_scenario(str(scenario), threads=2)
    world.step(steps)
    assert f"{world.state_hash():016x}" == cli_hash
