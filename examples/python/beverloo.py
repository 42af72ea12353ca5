"""The Beverloo discharge law, measured with a sensor under an hourglass's neck.

Grains run out of a flat-bottomed bulb (a silo) through a neck of width D in its floor. A
sensor below the floor counts every grain that has come through; the steady part of that
count over time is the discharge rate W (grains per unit time). In two dimensions Beverloo's
law reads

    W = C (D − k d)^(3/2)

(the grains fall freely from an arch of size ∝ D, so at speed ∝ √(g D), through a width
D − k d that the grains' own size d narrows). This script measures W for several neck widths,
fits C, k and the exponent n all three (``scipy``'s ``curve_fit``), and draws the classic plot W^(2/3) against D,
a straight line that meets zero at k d (``OUT/beverloo.png``; the rates and the fit go to
``OUT/beverloo.json``).

The grains are rough (friction 0.5, against each other and the walls), their contacts are
solved eight times a substep, and resting contacts do not bounce (``resting_contacts =
"rest"``): the packing is then stiff enough to carry its weight to the walls (the Janssen
effect), and the rate does not depend on how full the bulb is, as in a real silo (the script
prints the rate over the first and the second half of the measured part: they agree within
a few percent). Smooth discs (the default) with one solver pass flow more like a liquid, their
rate falling as the bulb empties (Torricelli), and the law does not hold for them; with four
passes and bouncing resting contacts the fitted exponent moves with the bulb's width.

``--quick`` runs a smaller bulb and fewer necks (about a minute); the full run takes a few
minutes on two cores.

    python examples/python/beverloo.py --out beverloo-out [--quick]
"""

# %% Setup
import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import curve_fit  # noqa: E402

import bounce  # noqa: E402

parser = argparse.ArgumentParser(description="The Beverloo discharge law")
parser.add_argument("--out", default="beverloo-out")
parser.add_argument("--quick", action="store_true", help="a smaller bulb, four necks")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

# Grains of diameter 0.9 to 1 (mean d = 0.95), so the neck widths are about D grains wide.
if args.quick:
    grains, width, necks = 900, 24.0, [4.0, 5.0, 6.5, 8.0]
else:
    grains, width, necks = 2000, 40.0, [4.0, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0]
d_mean = 0.95
floor, dt = 6.0, 0.005


# %% One discharge
def discharge(neck):
    """Fills the bulb over a floor with a centred neck of width `neck`, lets it run, and
    returns the times and the sensor's counts of grains through the neck."""
    centre = width / 2
    height = floor + 2 + grains / (width * 0.8) * 1.2 + 10
    config = bounce.Config(
        boundary="walls",
        min=(0, 0),
        max=(width, height),
        gravity=(0, -9.81),
        coefficient_of_restitution=0.5,
        restitution_model="relative_normal_velocity",
        velocity_update="approaching_only",
        mass_model="area",
        friction=0.5,
        substeps=8,
        solver_iterations=8,
        resting_contacts="rest",
        obstacles=[
            bounce.Obstacle.segment((0.0, floor), (centre - neck / 2, floor)),
            bounce.Obstacle.segment((centre + neck / 2, floor), (width, floor)),
        ],
        # Grains that came through fall into a sink at the bottom, out of the way.
        sinks=[bounce.Sink((0, 0), (width, 2.0))],
        # The sensor: the space under the floor; every grain in it came through the neck.
        sensors=[bounce.Sensor("neck", min=(0.0, 0.0), max=(width, floor - 1.0))],
    )
    world = bounce.World(config, dt=dt)
    # A loose lattice of grains, at rest, that settles before much has run out.
    rng = np.random.default_rng(1)
    columns = int((width - 1) / 1.05)
    rows = -(-grains // columns)
    xs, ys = 0.6 + np.arange(columns) * 1.05, floor + 1.0 + np.arange(rows) * 1.05
    positions = np.stack(np.meshgrid(xs, ys), -1).reshape(-1, 2)[:grains]
    positions[:, 0] += rng.uniform(-0.02, 0.02, grains)
    world.add_discs(positions, np.zeros((grains, 2)), rng.uniform(0.45, 0.5, grains))
    times, counts = [0.0], [0]
    while counts[-1] < 0.6 * grains and times[-1] < 120:
        world.step(20)
        times.append(times[-1] + 20 * dt)
        counts.append(world.sensors["neck"]["entered"])
    return np.array(times), np.array(counts)


def steady_rate(times, counts):
    """The slope of the count while 15 % to 55 % of the grains have run out (after the start,
    before the bulb runs low), and the two halves' slopes, whose gap says how steady it was."""
    n = grains
    part = (counts > 0.15 * n) & (counts < 0.55 * n)
    early = part & (counts < 0.35 * n)
    late = part & (counts >= 0.35 * n)
    return [float(np.polyfit(times[s], counts[s], 1)[0]) for s in (part, early, late)]


# %% Run every neck
rates, runs = [], []
for neck in necks:
    times, counts = discharge(neck)
    rate, early, late = steady_rate(times, counts)
    rates.append(rate)
    runs.append({"neck": neck, "rate": rate, "early": early, "late": late})
    print(f"D = {neck:5.2f}: W = {rate:7.2f} grains/time (first half {early:.2f}, second {late:.2f})")
D, W = np.array(necks), np.array(rates)


# %% Fit W = C (D − k d)^n with C, k and n free (least squares in W)
def law(D, C, kd, n):
    return C * np.clip(D - kd, 1e-9, None) ** n


(C, kd, n), covariance = curve_fit(law, D, W, p0=(3.0, 1.5, 1.5))
n_err = float(np.sqrt(covariance[2, 2]))
print(f"fit: W = {C:.3f} (D - {kd / d_mean:.2f} d)^{n:.3f} ± {n_err:.3f}  (Beverloo: n = 3/2)")
# With the exponent held at 3/2, W^(2/3) is a line in D.
slope, intercept = np.polyfit(D, W ** (2 / 3), 1)

# %% The figure
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
grid = np.linspace(0, D.max() * 1.05, 200)
left.plot(D, W ** (2 / 3), "o", color="#c8963e", label="measured")
left.plot(grid, slope * grid + intercept, "k-", lw=1, label="a line: n = 3/2")
left.axhline(0, color="grey", lw=0.6)
left.set(xlabel="neck width D", ylabel="W^(2/3)", title="Beverloo: W^(2/3) is linear in D")
left.legend()
span = np.linspace(D.min() - kd, D.max() - kd, 100)
right.loglog(D - kd, W, "o", color="#c8963e", label="measured")
right.loglog(span, C * span**n, "k-", lw=1, label=f"fit: n = {n:.2f} ± {n_err:.2f}")
right.set(xlabel=f"D − k d  (k = {kd / d_mean:.2f})", ylabel="W (grains per unit time)")
right.legend()
fig.tight_layout()
fig.savefig(out / "beverloo.png", dpi=120)
(out / "beverloo.json").write_text(
    json.dumps(
        {"runs": runs, "exponent": n, "exponent_err": n_err, "k": kd / d_mean, "C": C},
        indent=1,
    )
)
