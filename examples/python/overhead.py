"""What calling bounce from Python costs: a Python `step()` against the engine's own time
for that step, and reading positions, at 1k, 100k and 1M discs (gas at packing 0.3, walls).

    python examples/python/overhead.py [--threads 2] [--steps 200]

For each size it prints, in µs per step, the mean and median of: the wall time of `world.step()`
seen from Python, the time the engine measured inside the step (`world.profile["total"]`),
their difference (the Python overhead), and `world.positions` (an id-ordered copy) and a
storage view (zero-copy).
"""

import argparse
import os
import platform
import time

import numpy as np

import bounce


def gas(n, threads):
    length = np.sqrt(n * np.pi * 0.25 / 0.3)
    world = bounce.World(
        bounce.Config(boundary="walls", min=(0, 0), max=(length, length)),
        dt=1 / 60,
        threads=threads,
    )
    side = int(np.ceil(np.sqrt(n)))
    k = np.arange(n)
    positions = (np.stack([k % side, k // side], axis=1) + 0.5) * (length / side)
    world.add_discs(positions, np.random.default_rng(1).uniform(-2, 2, (n, 2)), 0.5)
    return world


def summary(values):
    values = np.asarray(values) * 1e6
    return f"{values.mean():8.1f} / {np.median(values):8.1f}"


def main():
    parser = argparse.ArgumentParser(description="Python overhead of bounce")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--sizes", default="1000,100000,1000000")
    args = parser.parse_args()
    cpu = next(
        (line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if "model name" in line),
        platform.processor(),
    )
    print(f"{cpu}, {os.cpu_count()} CPUs, {args.threads} threads, {args.steps} steps")
    print("µs per step, mean / median (means include the steps that rebuild)")
    print(f"{'discs':>9} | {'Python step()':>17} | {'engine step':>17} | {'overhead':>17} "
          f"| {'positions copy':>17} | {'storage view':>17}")
    for n in map(int, args.sizes.split(",")):
        world = gas(n, args.threads)
        world.step(10)
        outer, inner, copy, view = [], [], [], []
        for _ in range(args.steps):
            t0 = time.perf_counter()
            world.step()
            t1 = time.perf_counter()
            outer.append(t1 - t0)
            inner.append(world.profile["total"])
            t2 = time.perf_counter()
            world.positions
            t3 = time.perf_counter()
            with world.storage_view() as v:
                v.x, v.y
            t4 = time.perf_counter()
            copy.append(t3 - t2)
            view.append(t4 - t3)
        overhead = np.subtract(outer, inner)
        print(f"{n:>9} | {summary(outer)} | {summary(inner)} | {summary(overhead)} "
              f"| {summary(copy)} | {summary(view)}")


if __name__ == "__main__":
    main()
