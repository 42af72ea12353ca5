"""A Galton board from Python: obstacles, a scenario file, and the bell curve.

Balls fall through a funnel onto staggered rows of pegs and pile up in bins. Each peg sends
a ball left or right, so the bin counts approach a normal distribution centred under the
funnel. This script builds the shipped ``galton-board`` scenario's board in Python with
``bounce.Obstacle`` (funnel, pegs, bin walls) and an ``Emitter`` for the balls, counts the
balls per bin, and draws the histogram over the fitted normal (``OUT/galton.png``; the
counts go to ``OUT/galton.json``). ``--quick`` drops 300 balls instead of 500.

    python examples/python/galton.py --out galton-out [--quick]
"""

# %% Setup
import argparse
import json
import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import bounce  # noqa: E402

parser = argparse.ArgumentParser(description="A Galton board")
parser.add_argument("--out", default="galton-out")
parser.add_argument("--quick", action="store_true", help="300 balls instead of 500")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

# %% The board: the shipped scenario's geometry, built from Python
# A funnel whose mouth (6 wide) is over the axis, 15 staggered rows of 25 pegs, bin walls every
# 3 units; the balls come from an emitter above the funnel instead of a [[gas]] table.
width, bin_width = 60.0, 3.0
pegs = [
    bounce.Obstacle.peg((1.2 + 2.4 * j + (1.2 if row % 2 else 0.0), 32.0 + 2.4 * row), 0.3)
    for row in range(15)
    for j in range(25)
]
bin_walls = [bounce.Obstacle.segment((x, 0.0), (x, 26.0)) for x in np.arange(3.0, 60.0, 3.0)]
config = bounce.Config(
    boundary="walls",
    min=(0, 0),
    max=(width, 110),
    gravity=(0, -9.81),
    coefficient_of_restitution=0.5,
    restitution_model="relative_normal_velocity",
    velocity_update="approaching_only",
    substeps=4,
    obstacles=[
        bounce.Obstacle.segment((0, 100), (27, 75)),
        bounce.Obstacle.segment((60, 100), (33, 75)),
        *pegs,
        *bin_walls,
    ],
    emitters=[
        bounce.Emitter(
            (10, 96), (50, 109), rate=250, radius=0.4, limit=300 if args.quick else 500, seed=1
        )
    ],
)
world = bounce.World(config, dt=1 / 60)
steps = 2400 if args.quick else 3000

# %% Run it
world.step(steps)
x = world.positions[:, 0]
bins = np.minimum((x / bin_width).astype(int), int(width / bin_width) - 1)
counts = np.bincount(bins, minlength=int(width / bin_width))
print("balls per bin:", counts.tolist())

# %% Against the normal distribution with the sample's mean and spread
centres = (np.arange(len(counts)) + 0.5) * bin_width
n = counts.sum()
mean = float((centres * counts).sum() / n)
sd = float(math.sqrt(((centres - mean) ** 2 * counts).sum() / (n - 1)))
expected = n * bin_width / (sd * math.sqrt(2 * math.pi)) * np.exp(-0.5 * ((centres - mean) / sd) ** 2)
print(f"mean {mean:.2f} (axis {width / 2}), sd {sd:.2f}")

fig, ax = plt.subplots(figsize=(7, 4))
ax.bar(centres, counts, width=bin_width * 0.9, color="#f2c14e", label=f"{n} balls")
ax.plot(centres, expected, "k-", label="normal, fitted")
ax.axvline(width / 2, color="grey", lw=0.8)
ax.set_xlabel("x")
ax.set_ylabel("balls per bin")
ax.legend()
fig.tight_layout()
fig.savefig(out / "galton.png", dpi=120)
landed = int((world.positions[:, 1] < 26.0).sum())
(out / "galton.json").write_text(
    json.dumps(
        {"counts": counts.tolist(), "mean": mean, "sd": sd, "axis": width / 2, "landed": landed}
    )
)
