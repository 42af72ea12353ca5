"""NumPy in and out: dtypes, shapes, strides, id order, setters, the storage view."""

import gc

import numpy as np
import pytest

import bounce


def walled(n=0, dt=0.01):
    world = bounce.World(bounce.Config(boundary="walls", min=(0, 0), max=(100, 100)), dt=dt)
    if n:
        k = np.arange(n)
        positions = np.stack([5.0 + 3.0 * (k % 30), 5.0 + 3.0 * (k // 30)], axis=1)
        world.add_discs(positions, np.zeros((n, 2)), 1.0)
    return world


def test_any_real_dtype_and_any_strides_are_accepted():
    world = walled()
    big = np.arange(40, dtype=np.int64).reshape(10, 4) + 10  # strided columns
    positions = big[::2, ::2]  # (5, 2), not contiguous
    assert not positions.flags.c_contiguous
    velocities = np.asfortranarray(np.ones((5, 2), dtype=np.float32))
    ids = world.add_discs(positions, velocities, np.full(5, 0.5, dtype=np.float32))
    assert ids.dtype == np.uint32 and list(ids) == [0, 1, 2, 3, 4]
    out = world.positions
    assert out.dtype == np.float64 and out.shape == (5, 2) and out.flags.c_contiguous
    np.testing.assert_array_equal(out, positions.astype(np.float64))
    np.testing.assert_array_equal(world.velocities, np.ones((5, 2)))
    np.testing.assert_array_equal(world.radii, np.full(5, 0.5))
    # Lists work too, and a scalar radius applies to every disc.
    world.add_discs([[50, 50]], [[0, 0]], 2)
    assert len(world) == 6 and world.radii[-1] == 2.0


def test_arrays_come_out_in_id_order_whatever_the_storage_order():
    world = walled(300)
    rng = np.random.default_rng(1)
    world.velocities = rng.normal(size=(300, 2)) * 20
    world.step(50)  # rebuilds reorder the storage
    with world.storage_view() as view:
        ids = view.ids.copy()
        x = view.x.copy()
    assert list(ids) != sorted(ids), "storage should have been reordered"
    np.testing.assert_array_equal(world.positions[ids, 0], x)
    np.testing.assert_array_equal(world.ids, np.arange(300))


def test_setters_replace_every_row_or_nothing():
    world = walled(10)
    before = world.positions
    new = before + 1.0
    world.positions = new
    np.testing.assert_array_equal(world.positions, new)
    bad = new.copy()
    bad[7] = [500.0, 5.0]
    with pytest.raises(ValueError, match="disc 7"):
        world.positions = bad
    np.testing.assert_array_equal(world.positions, new)
    with pytest.raises(ValueError, match=r"disc 3: .*velocity"):
        world.velocities = np.where(np.arange(10)[:, None] == 3, np.nan, 0.0) * np.ones((10, 2))
    np.testing.assert_array_equal(world.velocities, np.zeros((10, 2)))
    with pytest.raises(ValueError, match="has 9 rows; expected 10"):
        world.velocities = np.zeros((9, 2))


def test_the_storage_view_is_zero_copy_read_only_and_holds_the_world():
    world = walled(20)
    view = world.storage_view()
    x = view.x
    assert not x.flags.writeable and not x.flags.owndata
    with pytest.raises(ValueError):
        x[0] = 1.0
    # The arrays see the engine's memory: a setter is refused while they live...
    with pytest.raises(RuntimeError, match="storage view"):
        world.step()
    with pytest.raises(RuntimeError, match="storage view"):
        world.positions = world.positions
    view.close()
    with pytest.raises(RuntimeError, match="storage view"):
        world.step()  # `x` still lives
    del x, view
    gc.collect()
    world.step()
    # ...and a with-block whose arrays are not kept frees it at its end.
    with world.storage_view() as v:
        total = float(v.x.sum())
    assert total == pytest.approx(world.positions[:, 0].sum())
    world.step()
