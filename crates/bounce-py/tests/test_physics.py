"""Conservation laws and determinism, and the same bits as the command line."""

import math
import re

import numpy as np
import pytest

import bounce
from conftest import run_cli


def elastic_gas(threads=1, n=400, seed=2):
    """Equal discs on a square lattice at packing 0.3 in a periodic box, random velocities."""
    rng = np.random.default_rng(seed)
    length = np.sqrt(n * np.pi * 0.25 / 0.3)
    config = bounce.Config(boundary="periodic", min=(0, 0), max=(length, length))
    world = bounce.World(config, dt=0.02, threads=threads)
    side = int(np.ceil(np.sqrt(n)))
    k = np.arange(n)
    spacing = length / side
    positions = (np.stack([k % side, k // side], axis=1) + 0.5) * spacing
    world.add_discs(positions, rng.normal(size=(n, 2)), 0.5)
    return world


def test_an_elastic_gas_of_equal_discs_conserves_energy_and_momentum():
    world = elastic_gas()
    world.step()
    energy, momentum = world.stats["kinetic_energy"], np.array(world.stats["momentum"])
    collisions = 0
    for _ in range(50):
        world.step(10)
        collisions += world.stats["collisions"]
    assert collisions > 100
    assert world.stats["kinetic_energy"] == pytest.approx(energy, rel=1e-10)
    np.testing.assert_allclose(world.stats["momentum"], momentum, atol=1e-9)
    # The kinetic energy the stats report is ½ Σ m v² with m = r.
    v = world.velocities
    assert world.stats["kinetic_energy"] == pytest.approx(
        0.5 * np.sum(world.masses * np.sum(v * v, axis=1)), rel=1e-12
    )


def test_the_same_bits_for_every_thread_count():
    hashes = set()
    for threads in (1, 2, 3):
        world = elastic_gas(threads=threads, n=3000)
        world.step(30)
        hashes.add(world.state_hash())
    assert len(hashes) == 1


@pytest.mark.parametrize("scenario", ["mixing", "pile"])
def test_a_scenario_run_from_python_ends_in_the_state_bounce_run_prints(
    root, bounce_bin, tmp_path, scenario
):
    steps = 40
    out = run_cli(
        bounce_bin,
        "run",
        root / "scenarios" / f"{scenario}.toml",
        "--steps",
        steps,
        "--out",
        tmp_path / "out",
        "--threads",
        2,
        "--quiet",
        "--set",
        "output.gif=false",
    )
    cli_hash = re.search(r"state hash ([0-9a-f]{16})", out).group(1)
    for threads in (1, 2):
        world = bounce.World.from_scenario(root / "scenarios" / f"{scenario}.toml", threads)
        world.step(steps)
        assert f"{world.state_hash():016x}" == cli_hash
    # The run's checkpoint loads in Python as the same state.
    loaded = bounce.World.load(tmp_path / "out" / "checkpoint.bin")
    assert f"{loaded.state_hash():016x}" == cli_hash
    assert loaded.step_count == steps


@pytest.mark.parametrize("support", ["floor", "segment", "peg"])
def test_a_resting_disc_keeps_g_h_under_the_seed_and_is_still_under_rest(support):
    # A disc of radius 0.5 resting on its support under g = 10 at dt = 0.01: the seed's
    # reflection leaves it moving at up to |g| dt; with resting_contacts = "rest" it is still.
    obstacles = {
        "floor": [],
        "segment": [bounce.Obstacle.segment((0, 2), (10, 2))],
        "peg": [bounce.Obstacle.peg((5, 1), 1.0)],
    }[support]
    base = 0.0 if support == "floor" else 2.0
    speeds = {}
    for rest in ("bounce", "rest"):
        config = bounce.Config(
            boundary="walls", min=(0, 0), max=(10, 20), gravity=(0, -10),
            obstacles=obstacles, resting_contacts=rest,
        )
        world = bounce.World(config, dt=0.01)
        world.add_discs([[5, base + 0.5]], [[0, 0]], 0.5)
        top = 0.0
        for _ in range(200):
            world.step()
            top = max(top, float(np.abs(world.velocities[0, 1])))
        speeds[rest] = top
        if rest == "rest":
            assert world.positions[0, 1] == pytest.approx(base + 0.5, abs=1e-12)
    assert speeds["bounce"] == pytest.approx(10 * 0.01, rel=1e-9)
    assert speeds["rest"] == 0.0


def test_a_thermostat_from_python_holds_the_baths_temperature_and_round_trips():
    side = 60.0
    rng = np.random.default_rng(3)
    grid = np.stack(np.meshgrid(np.arange(30) * 2 + 1.0, np.arange(30) * 2 + 1.0), -1)
    positions = grid.reshape(-1, 2)
    bath = {"kind": "rescale", "temperature": 2.0, "rate": 1e3, "seed": 0}
    config = bounce.Config(boundary="periodic", min=(0, 0), max=(side, side), thermostat=bath)
    assert config.thermostat == bath
    assert 'thermostat={"kind": "rescale", "temperature": 2.0' in repr(config)
    world = bounce.World(config, dt=0.01)
    world.add_discs(positions, rng.normal(size=(900, 2)), radii=0.4)
    world.step(5)
    # Rescaled exactly each step: kT (mass = radius) is the bath's.
    v = world.velocities - world.velocities.mean(axis=0)
    kt = 0.5 * 0.4 * (v**2).sum() / len(world)
    assert abs(kt - 2.0) < 1e-9
    assert math.isfinite(world.stats["thermostat_work"])
    with pytest.raises(ValueError, match="thermostat"):
        bounce.Config(thermostat={"kind": "rescale", "temperature": -1.0, "rate": 1.0})
    with pytest.raises(ValueError, match="white_noise"):
        bounce.Config(thermostat={"kind": "nose", "temperature": 1.0, "rate": 1.0})
    with pytest.raises(TypeError, match="unknown key"):
        bounce.Config(thermostat={"kind": "rescale", "temperature": 1.0, "rate": 1.0, "x": 1})
    with pytest.raises(ValueError, match="missing rate"):
        bounce.Config(thermostat={"kind": "rescale", "temperature": 1.0})


def test_a_profile_bins_the_discs_as_profile_csv_does():
    config = bounce.Config(boundary="walls", min=(0, 0), max=(10, 4))
    world = bounce.World(config, dt=0.01)
    world.add_discs([[1, 1], [1.5, 3], [6, 2], [9.5, 2]], [[1, 0], [3, 0], [0, 2], [0, -2]], 0.2)
    p = world.profiles(axis="x", bins=2)
    assert list(p["centre"]) == [2.5, 7.5]
    assert list(p["count"]) == [2, 2]
    assert list(p["density"]) == [2 / 20, 2 / 20]
    # Equal masses: the mean velocity, and ½ m |v − u|² summed over count − 1.
    assert list(p["vx"]) == [2.0, 0.0] and list(p["vy"]) == [0.0, 0.0]
    assert p["temperature"][0] == pytest.approx(0.5 * 0.2 * (1 + 1) / 1)
    assert p["temperature"][1] == pytest.approx(0.5 * 0.2 * (4 + 4) / 1)
    with pytest.raises(ValueError, match="open world"):
        bounce.World(bounce.Config(), dt=0.01).profiles()
    with pytest.raises(ValueError, match="axis"):
        world.profiles(axis="z")


def test_the_pressure_tensor_from_python_has_the_pressure_as_its_trace():
    config = bounce.Config(boundary="periodic", min=(0, 0), max=(40, 40), pressure_tensor=True)
    assert config.pressure_tensor and "pressure_tensor=True" in repr(config)
    world = bounce.World(config, dt=0.01)
    rng = np.random.default_rng(5)
    grid = np.stack(np.meshgrid(np.arange(20) * 2 + 1.0, np.arange(20) * 2 + 1.0), -1)
    world.add_discs(grid.reshape(-1, 2), rng.normal(size=(400, 2)), radii=0.6)
    world.step(50)
    xx, yy, xy = world.pressure_tensor
    assert (xx + yy) / 2 == pytest.approx(world.stats["pressure"], rel=1e-12)
    assert len(world.stats["virial_tensor"]) == 3
    assert bounce.World(bounce.Config(boundary="periodic", min=(0, 0), max=(9, 9)), dt=0.1).pressure_tensor is None


def test_each_disc_counts_its_collisions_and_the_counts_add_up():
    config = bounce.Config(boundary="periodic", min=(0, 0), max=(40, 40), collision_counts=True)
    assert config.collision_counts and "collision_counts=True" in repr(config)
    world = bounce.World(config, dt=0.01)
    rng = np.random.default_rng(6)
    grid = np.stack(np.meshgrid(np.arange(20) * 2 + 1.0, np.arange(20) * 2 + 1.0), -1)
    world.add_discs(grid.reshape(-1, 2), rng.normal(size=(400, 2)), radii=0.6)
    collisions = 0
    for _ in range(100):
        world.step(1)
        collisions += world.stats["collisions"]
    counts = world.collision_counts
    assert counts.dtype == np.uint64 and counts.shape == (400,)
    assert collisions > 100 and counts.sum() == 2 * collisions
    # Without the switch there is nothing to read.
    off = bounce.World(bounce.Config(boundary="periodic", min=(0, 0), max=(9, 9)), dt=0.1)
    assert off.collision_counts is None


def test_the_energy_balance_from_python_is_stats_csvs_dissipated(tmp_path, bounce_bin, root):
    scenario = root / "scenarios" / "driven-granular.toml"
    run_cli(
        bounce_bin, "run", scenario, "--out", tmp_path / "dg", "--steps", "200", "-q",
        "--set", "output.dissipation=true", "--set", "output.stats_every=20",
    )
    lines = (tmp_path / "dg" / "stats.csv").read_text().splitlines()
    column = lines[0].split(",").index("dissipated")
    expected = [float(line.split(",")[column]) for line in lines[2:]]
    world = bounce.World.from_scenario(scenario)
    dissipated = []
    for _ in range(10):
        energy, heat = world.energy, world.thermostat_work + world.obstacle_work
        world.step(20)
        dissipated.append(energy - world.energy + world.thermostat_work + world.obstacle_work - heat)
    # The inelastic gas loses energy; the kicks' work is what the balance adds back.
    assert world.thermostat_work > 0 and min(dissipated) > 0
    assert dissipated == pytest.approx(expected, rel=1e-9)


def test_a_lees_edwards_box_from_python_slides_its_images_and_keeps_the_flow():
    # 20 × 20 at shear rate 0.05: the images above move at 1 along x.
    config = bounce.Config(boundary="lees_edwards", min=(0, 0), max=(20, 20), shear_rate=0.05)
    assert (config.boundary, config.shear_rate) == ("lees_edwards", 0.05)
    assert "shear_rate=0.05" in repr(config)
    world = bounce.World(config, dt=0.25)
    # One disc leaving through the top: back at the bottom, moved back by the offset.
    world.add_discs([[10.0, 19.9]], [[0.0, 1.0]], 0.5)
    world.step()
    assert world.lees_edwards_offset == pytest.approx(0.25)
    (x, y), (vx, vy) = world.positions[0], world.velocities[0]
    assert (x, y) == pytest.approx((9.75, 0.15)) and (vx, vy) == pytest.approx((-1.0, 1.0))
    # Relative to the flow there (0.05 (0.15 − 10) ≈ −0.49) and to itself: no kinetic energy.
    assert world.peculiar_kinetic_energy == pytest.approx(0.0, abs=1e-12)
    assert bounce.World(bounce.Config(), dt=0.1).lees_edwards_offset is None
    with pytest.raises(ValueError, match="shear_rate"):
        bounce.Config(boundary="lees_edwards", min=(0, 0), max=(20, 20))
    with pytest.raises(ValueError, match="shear_rate"):
        bounce.Config(boundary="periodic", min=(0, 0), max=(20, 20), shear_rate=0.1)
    with pytest.raises(ValueError, match="obstacles"):
        bounce.Config(
            boundary="lees_edwards", min=(0, 0), max=(20, 20), shear_rate=0.1,
            obstacles=[bounce.Obstacle.peg((5, 5), 1.0)],
        )
