"""The seed's formulas through the Python API, against values computed by hand."""

import numpy as np
import pytest

import bounce


def two_disc_world(**config):
    return bounce.World(bounce.Config(**config), dt=0.1)


def test_equal_discs_head_on_exchange_velocities_and_are_pushed_apart_half_each():
    world = two_disc_world()
    world.add_discs([[0.0, 0.0], [2.1, 0.0]], [[1.0, 0.0], [-1.0, 0.0]], 1.0)
    world.step()
    # Moved to 0.1 and 2.0: distance 1.9 < 2, overlap 0.1, pushed 0.05 each; e = 1 and
    # equal masses (radii) swap the normal velocities.
    np.testing.assert_allclose(world.positions, [[0.05, 0.0], [2.05, 0.0]], atol=1e-12)
    np.testing.assert_allclose(world.velocities, [[-1.0, 0.0], [1.0, 0.0]], atol=1e-12)
    assert world.stats["collisions"] == 1


def test_radii_are_the_masses_and_each_normal_velocity_is_scaled_by_e():
    world = two_disc_world(coefficient_of_restitution=0.8)
    world.add_discs([[0.0, 0.0], [3.05, 0.0]], [[2.0, 0.0], [0.0, 0.0]], [1.0, 2.0])
    world.step()
    # A moves to 0.2; distance 2.85 < 3: overlap 0.15, 0.075 each. Normal n = (-1, 0),
    # v1n = -2, v2n = 0, m1 = 1, m2 = 2:
    # v1n' = (v1n (m1 - m2) + 2 m2 v2n) / (m1 + m2) e = (2 / 3) 0.8
    # v2n' = (v2n (m2 - m1) + 2 m1 v1n) / (m1 + m2) e = (-4 / 3) 0.8
    np.testing.assert_allclose(world.positions, [[0.125, 0.0], [3.125, 0.0]], atol=1e-12)
    v1 = -(2.0 / 3.0) * 0.8
    v2 = (4.0 / 3.0) * 0.8
    np.testing.assert_allclose(world.velocities, [[v1, 0.0], [v2, 0.0]], atol=1e-12)
    # The seed's restitution scales the momentum too: 2 before, 0.8 × 2 after.
    assert world.stats["momentum"][0] == pytest.approx(1.6, abs=1e-12)
    np.testing.assert_allclose(world.masses, [1.0, 2.0])


def test_the_tangential_velocity_is_kept():
    world = two_disc_world()
    world.add_discs([[0.0, 0.0], [1.9, 0.0]], [[1.0, 3.0], [-1.0, 3.0]], 1.0)
    world.step()
    # Both rise by 0.3, so the normal stays along x: moved to 0.1 and 1.8, overlap 0.3,
    # pushed 0.15 each; the normal velocities swap, the tangential ones (3) stay.
    np.testing.assert_allclose(world.positions, [[-0.05, 0.3], [1.95, 0.3]], atol=1e-12)
    np.testing.assert_allclose(world.velocities, [[-1.0, 3.0], [1.0, 3.0]], atol=1e-12)


def test_the_momentum_conserving_model_is_an_option():
    world = two_disc_world(
        coefficient_of_restitution=0.5, restitution_model="relative_normal_velocity"
    )
    world.add_discs([[0.0, 0.0], [3.05, 0.0]], [[2.0, 0.0], [0.0, 0.0]], [1.0, 2.0])
    world.step()
    # Momentum 2 kept; the relative normal velocity reversed and halved: v2 - v1 = 1.
    v1, v2 = world.velocities[:, 0]
    assert v1 + 2.0 * v2 == pytest.approx(2.0, abs=1e-12)
    assert v2 - v1 == pytest.approx(1.0, abs=1e-12)
