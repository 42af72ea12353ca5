"""`bounce.rdf`, `psi6` and `msd` (and `bounce analyze`) against freud on the same frames."""

import math

import freud
import gsd.hoomd
import numpy as np
import pytest

import bounce

from conftest import run_cli


@pytest.fixture(scope="module")
def fluid(tmp_path_factory, bounce_bin):
    """Exact hard discs at packing 0.3 (the event-driven engine), 30 frames after melting."""
    out = tmp_path_factory.mktemp("fluid")
    side = math.sqrt(2000 * math.pi * 0.25 / 0.3)
    run_cli(
        bounce_bin, "run", "scenarios/hard-discs.toml", "--out", out, "-q",
        "--set", f"world.max=[{side},{side}]", "--set", "time.steps=400",
        "--set", "output.gif=false", "--set", "output.frame_every=0",
        "--set", "output.gsd_every=10",
    )
    return out / "trajectory.gsd"


def frames(path, first):
    with gsd.hoomd.open(str(path)) as trajectory:
        return [f for f in trajectory][first:]


def exact_rdf(path, first, bins, r_max):
    """g(r) in float64 by brute force over every pair, with freud's "exact" normalisation."""
    pairs, ideal = np.zeros(bins), np.zeros(bins)
    edges = np.linspace(0.0, r_max, bins + 1)
    for f in frames(path, first):
        box = f.configuration.box[:2].astype(np.float64)
        p = f.particles.position[:, :2].astype(np.float64)
        n = len(p)
        for i in range(n - 1):
            d = p[i + 1:] - p[i]
            d -= box * np.round(d / box)
            r = np.hypot(d[:, 0], d[:, 1])
            r = r[r < r_max]
            np.add.at(pairs, np.minimum((r / (r_max / bins)).astype(int), bins - 1), 2)
        ideal += n * n / (box[0] * box[1]) * np.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
    return (edges[1:] + edges[:-1]) / 2, pairs / ideal


def test_rdf_equals_an_exact_count_and_freud_on_the_same_frames(fluid):
    r, g = bounce.rdf(fluid, r_max=5.0, bin=0.05, first=-3)
    r_exact, g_exact = exact_rdf(fluid, -3, 100, 5.0)
    assert np.allclose(r, r_exact, rtol=0, atol=1e-12)
    assert np.abs(g - g_exact).max() < 1e-12
    reference = freud.density.RDF(bins=100, r_max=5.0)
    for f in frames(fluid, -3):
        box = freud.box.Box(Lx=f.configuration.box[0], Ly=f.configuration.box[1], is2D=True)
        reference.compute(system=(box, f.particles.position), reset=False)
    assert np.allclose(r, reference.bin_centers, rtol=0, atol=1e-6)  # freud's are float32
    # freud measures distances in float32 (1e-5 at a box of 72): a pair that close to a bin
    # edge may land in the next bin, so bins differ by a few pairs in ten thousand.
    assert np.abs(g - reference.rdf).max() < 1e-3
    assert np.abs(g - reference.rdf).mean() < 1e-4
    assert g.max() > 1.5  # the contact peak is there to compare


def test_psi6_equals_freuds_hexatic_with_six_neighbours(fluid, tmp_path, bounce_bin):
    steps, order = bounce.psi6(fluid, first=-5)
    expected = []
    for f in frames(fluid, -5):
        box = freud.box.Box(Lx=f.configuration.box[0], Ly=f.configuration.box[1], is2D=True)
        hexatic = freud.order.Hexatic(k=6)
        hexatic.compute(system=(box, f.particles.position), neighbors={"num_neighbors": 6})
        expected.append(abs(np.mean(hexatic.particle_order)))
    assert list(steps) == [f.configuration.step for f in frames(fluid, -5)]
    assert np.abs(order - np.array(expected)).max() < 1e-6
    assert order.max() < 0.1  # a fluid
    # The CLI writes the same numbers.
    run_cli(bounce_bin, "analyze", fluid, "--out", tmp_path, "--first", "-5")
    rows = np.loadtxt(tmp_path / "psi6.csv", delimiter=",", skiprows=1)
    assert np.array_equal(rows[:, 1], order)
    assert (tmp_path / "psi6.png").stat().st_size > 5_000


def test_msd_equals_freuds_window_msd_through_the_periodic_images(fluid):
    lags, values = bounce.msd(fluid)
    trajectory = frames(fluid, 0)
    positions = np.array([f.particles.position for f in trajectory], dtype=np.float64)
    images = np.array([f.particles.image for f in trajectory])
    assert np.abs(images).max() > 0  # discs crossed the box: unwrapping matters
    box = trajectory[0].configuration.box
    reference = freud.msd.MSD(freud.box.Box(Lx=box[0], Ly=box[1], is2D=True), mode="window")
    reference.compute(positions, images=images)
    assert list(lags) == [10 * k for k in range(len(trajectory))]
    # freud's window mode sums by FFT, in float32 positions: its lag 0 is about 1e-4, not 0,
    # and that is its precision. The exact average over origins, in float64, agrees to 1e-12.
    assert np.abs(values - reference.msd).max() < 1e-4 * values.max()
    box = box[:2].astype(np.float64)
    unwrapped = positions[:, :, :2] + images[:, :, :2] * box
    exact = [
        np.mean([np.sum((unwrapped[k + m] - unwrapped[k]) ** 2, axis=1).mean()
                 for k in range(len(trajectory) - m)])
        for m in range(len(trajectory))
    ]
    assert np.allclose(values, exact, rtol=1e-12, atol=1e-12)
    assert values[0] == 0.0


def test_bad_input_names_the_problem(fluid, tmp_path):
    with pytest.raises(FileNotFoundError, match="no trajectory"):
        bounce.rdf(tmp_path / "missing.gsd")
    with pytest.raises(ValueError, match="minimum image"):
        bounce.rdf(fluid, r_max=1e3)
    with pytest.raises(ValueError, match="boundary"):
        bounce.psi6(fluid, boundary="round")
    with pytest.raises(ValueError, match="first frame 99"):
        bounce.msd(fluid, first=99)


def test_a_worlds_structure_now_equals_its_gsd_frames(tmp_path):
    """``rdf`` and ``psi6`` of a World read its state as a GSD frame of it holds it."""
    world = bounce.World.from_scenario(__import__("conftest").ROOT / "scenarios" / "hard-discs.toml")
    world.step(30)
    with bounce.GSDWriter(str(tmp_path / "now.gsd"), every=1) as gsd:
        world.add_writer(gsd)
        world.step(1)
    r, g = bounce.rdf(world, r_max=5.0, bin=0.05)
    r_file, g_file = bounce.rdf(tmp_path / "now.gsd", r_max=5.0, bin=0.05, first=-1)
    # The file holds float32 positions: the same bins within a few pairs' worth.
    assert np.array_equal(r, r_file)
    assert np.abs(g - g_file).max() < 0.05
    steps, order = bounce.psi6(world)
    assert list(steps) == [31] and abs(order[0] - bounce.psi6(tmp_path / "now.gsd", first=-1)[1][0]) < 1e-4
    with pytest.raises(TypeError, match="bounce.World"):
        bounce.psi6(3.5)
