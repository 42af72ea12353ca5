"""The event-driven method from Python: Config(method="event_driven"), exact hard discs."""

import numpy as np
import pytest

import bounce


def hard_discs(n=900, packing=0.3, seed=4):
    """Equal discs (radius 0.5) on a square lattice in a periodic box, thermal velocities."""
    rng = np.random.default_rng(seed)
    length = np.sqrt(n * np.pi * 0.25 / packing)
    config = bounce.Config(
        boundary="periodic", min=(0, 0), max=(length, length), method="event_driven"
    )
    world = bounce.World(config, dt=0.5)
    side = int(np.ceil(np.sqrt(n)))
    k = np.arange(n)
    positions = (np.stack([k % side, k // side], axis=1) + 0.5) * (length / side)
    velocities = rng.normal(size=(n, 2))
    velocities -= velocities.mean(axis=0)
    world.add_discs(positions, velocities, 0.5)
    return world, length


def test_exact_hard_discs_keep_energy_and_give_the_monte_carlo_pressure():
    world, length = hard_discs()
    assert world.config.method == "event_driven"
    world.step(20)
    energy = world.stats["kinetic_energy"]
    z, collisions = [], 0
    for _ in range(100):
        world.step()
        stats = world.stats
        collisions += stats["collisions"]
        kt = stats["kinetic_energy"] / 900
        z.append(stats["pressure"] * length**2 / (900 * kt))
    assert abs(world.stats["kinetic_energy"] / energy - 1) < 1e-12
    # Monte Carlo: Z = 2.0631 at packing 0.3 (900 discs, 50 time units: within 1.5 %).
    assert abs(np.mean(z) / 2.0631 - 1) < 0.015, np.mean(z)
    assert collisions > 10_000


def test_the_method_is_checked_and_what_it_cannot_do_is_refused():
    with pytest.raises(ValueError, match="method"):
        bounce.Config(method="events")
    with pytest.raises(ValueError, match="substeps"):
        bounce.Config(method="event_driven", substeps=4)
    config = bounce.Config(method="event_driven", contact_duration=1e-4)
    assert config.contact_duration == 1e-4
    assert "event_driven" in repr(config)
    with pytest.raises(ValueError, match="contact_duration"):
        bounce.Config(contact_duration=-1.0)


def test_overlapping_discs_are_named_when_the_step_starts():
    world = bounce.World(bounce.Config(method="event_driven"), dt=0.1)
    world.add_discs(np.array([[0.0, 0.0], [1.0, 0.0]]), np.zeros((2, 2)), 1.0)
    with pytest.raises(RuntimeError, match="discs 0 and 1 overlap"):
        world.step()
