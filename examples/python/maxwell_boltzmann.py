"""Teaching example: a gas relaxes to the Maxwell–Boltzmann distribution.

Every disc starts with the same speed in a random direction: a distribution as far from
equilibrium as it gets. Collisions (the default model, e = 1, equal discs) share the energy out,
and within a few collision times the speeds follow the 2D Maxwell–Boltzmann law,

    f(v) = (m v / kT) exp(-m v² / 2kT),     kT = KE / N,

whatever the start. The script prints the Kolmogorov–Smirnov distance between the measured
speeds and that law as time goes on, and draws the histograms over the curve
(``OUT/maxwell_boltzmann.png``). Each cell is meant to be read and run in order, as in a
notebook.

    python examples/python/maxwell_boltzmann.py --out mb-out [--quick]
"""

# %% Setup
import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import bounce  # noqa: E402

parser = argparse.ArgumentParser(description="A gas relaxing to Maxwell–Boltzmann")
parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("mb-out"))
parser.add_argument("--quick", action="store_true", help="fewer discs (for tests)")
args = parser.parse_args()
args.out.mkdir(parents=True, exist_ok=True)
n = 2000 if args.quick else 20000

# %% A box of discs, all at speed 1
length = np.sqrt(n * np.pi * 0.25 / 0.2)  # packing 0.2
world = bounce.World(
    bounce.Config(boundary="walls", min=(0, 0), max=(length, length)), dt=0.02
)
side = int(np.ceil(np.sqrt(n)))
k = np.arange(n)
positions = (np.stack([k % side, k // side], axis=1) + 0.5) * (length / side)
angle = np.random.default_rng(7).uniform(0, 2 * np.pi, n)
world.add_discs(positions, np.stack([np.cos(angle), np.sin(angle)], axis=1), 0.5)
mass = world.masses[0]  # the default mass is the radius: 0.5


# %% The law and the distance to it
def mb_cdf(v, kT):
    """Cumulative 2D Maxwell–Boltzmann distribution of the speed."""
    return 1 - np.exp(-mass * v**2 / (2 * kT))


def ks_distance(speeds, kT):
    """Largest gap between the measured and the theoretical cumulative distributions."""
    v = np.sort(speeds)
    theory = mb_cdf(v, kT)
    upper = np.arange(1, len(v) + 1) / len(v)
    return float(max(np.max(upper - theory), np.max(theory - upper + 1 / len(v))))


# %% Watch it relax
kT = world.stats["kinetic_energy"] / n if world.stats["kinetic_energy"] else 0.5 * mass
snapshots = {}
history = []
for t in [0, 1, 2, 5, 10, 20, 40]:
    world.step(max(0, int(round(t / world.dt)) - world.step_count))
    speeds = np.linalg.norm(world.velocities, axis=1)
    kT = world.stats["kinetic_energy"] / n if world.step_count else 0.5 * mass
    distance = ks_distance(speeds, kT)
    history.append({"time": world.time, "ks": distance})
    snapshots[t] = speeds
    print(f"t = {world.time:5.1f}: KS distance to Maxwell–Boltzmann {distance:.4f}")

# %% Draw
fig, ax = plt.subplots(figsize=(7, 4))
v = np.linspace(0, 3.5, 200)
ax.plot(v, mass * v / kT * np.exp(-mass * v**2 / (2 * kT)), "k", label="Maxwell–Boltzmann")
for t in [1, 5, 40]:
    ax.hist(snapshots[t], bins=60, range=(0, 3.5), density=True, histtype="step", label=f"t = {t}")
ax.set(xlabel="speed", ylabel="probability density", title=f"{n} discs relaxing")
ax.legend()
fig.tight_layout()
fig.savefig(args.out / "maxwell_boltzmann.png", dpi=100)
(args.out / "maxwell_boltzmann.json").write_text(json.dumps(history, indent=1))
print(f"figure in {args.out / 'maxwell_boltzmann.png'}")
