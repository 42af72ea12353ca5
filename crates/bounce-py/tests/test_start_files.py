"""Starting from a file: `World.add_file` reads a GSD frame (as HOOMD-blue and the `gsd`
package write it) or a CSV table, with the CLI's validation and errors."""

import numpy as np
import pytest

import bounce


def walled(width=20.0, height=10.0):
    config = bounce.Config(boundary="walls", min=(0, 0), max=(width, height))
    return bounce.World(config, dt=0.01)


def test_a_frame_written_by_the_gsd_package_starts_a_world(tmp_path):
    import gsd.hoomd as gsd_hoomd  # scripts/test installs it

    # A HOOMD-style file: box centred on the origin, 3D positions, types and typeids; the
    # first frame has everything, the second only moves the discs (the schema takes the rest
    # from frame 0).
    path = tmp_path / "hoomd.gsd"
    with gsd_hoomd.open(path, mode="w") as f:
        first = gsd_hoomd.Frame()
        first.configuration.step = 0
        first.configuration.box = [20, 10, 0, 0, 0, 0]
        first.configuration.dimensions = 2
        first.particles.N = 3
        first.particles.position = [[-5, 0, 0], [0, 1, 0], [5, -2, 0]]
        first.particles.velocity = [[1, 0, 0], [0, -1, 0], [0.5, 0.5, 0]]
        first.particles.diameter = [1.0, 2.0, 1.0]
        first.particles.types = ["small", "big"]
        first.particles.typeid = [0, 1, 0]
        f.append(first)
        second = gsd_hoomd.Frame()
        second.configuration.step = 100
        second.particles.N = 3
        second.particles.position = [[-4, 0, 0], [0, 2, 0], [6, -2, 0]]
        f.append(second)
    world = walled()
    ids = world.add_file(path)
    assert list(ids) == [0, 1, 2]
    # Around the world's box centre (10, 5); the rest from frame 0.
    np.testing.assert_array_equal(world.positions, [[6, 5], [10, 7], [16, 3]])
    np.testing.assert_array_equal(world.velocities, [[1, 0], [0, -1], [0.5, 0.5]])
    np.testing.assert_array_equal(world.radii, [0.5, 1.0, 0.5])
    first_frame = walled()
    first_frame.add_file(path, frame=0)
    np.testing.assert_array_equal(first_frame.positions[0], [5, 5])
    # The types reach the GSD files the world writes.
    out = tmp_path / "out.gsd"
    world.write_gsd(out)
    with gsd_hoomd.open(out) as trajectory:
        frame = trajectory[0]
        assert [frame.particles.types[t] for t in frame.particles.typeid] == [
            "small",
            "big",
            "small",
        ]
    # A world of another size is refused, and nothing is added.
    other = walled(30.0, 10.0)
    with pytest.raises(ValueError, match=r"hoomd.gsd: its box is 20 × 10, the world's is 30 × 10"):
        other.add_file(path)
    assert len(other) == 0


def test_a_csv_table_and_its_errors(tmp_path):
    good = tmp_path / "discs.csv"
    good.write_text("x,y,vx,vy,radius\n2,2,1,0,0.5\n8,2,-1,0,0.5\n")
    world = walled()
    world.add_file(good)
    np.testing.assert_array_equal(world.velocities, [[1, 0], [-1, 0]])
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y,radius\n2,2,0.5\n3,x,0.5\n")
    with pytest.raises(ValueError, match=r'bad.csv: line 3: y = "x" is not a number'):
        world.add_file(bad)
    outside = tmp_path / "outside.csv"
    outside.write_text("x,y,radius\n2,2,0.5\n50,2,0.5\n")
    with pytest.raises(ValueError, match=r"outside.csv: particle 1: centre \[50.0, 2.0\]"):
        world.add_file(outside)
    assert len(world) == 2
