"""The step without the GIL, Ctrl-C, memory, checkpoints and GSD files."""

import _thread
import resource
import signal
import threading
import time

import numpy as np
import pytest

import bounce


def gas(n, side=None, threads=1):
    side = side or np.sqrt(n / 0.3)
    world = bounce.World(
        bounce.Config(boundary="walls", min=(0, 0), max=(side, side)), dt=0.01, threads=threads
    )
    per_row = int(side // 1.6)
    k = np.arange(n)
    positions = np.stack([1.0 + 1.6 * (k % per_row), 1.0 + 1.6 * (k // per_row)], axis=1)
    rng = np.random.default_rng(4)
    world.add_discs(positions, rng.uniform(-2, 2, size=(n, 2)), 0.5)
    return world


def test_other_python_threads_run_during_a_long_step():
    world = gas(100_000)
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    try:
        start = len(ticks)
        begin = time.perf_counter()
        # Long enough to count ticks in on a fast machine (100 steps took 0.1 s here).
        world.step(400)
        elapsed = time.perf_counter() - begin
        during = len(ticks) - start
    finally:
        done.set()
        counter.join()
    # Holding the GIL through the call would leave the counter (a tick per millisecond)
    # almost nothing; released, it ticks all along.
    assert elapsed > 0.1
    assert during > 0.25 * elapsed / 0.001, (during, elapsed)


def test_ctrl_c_interrupts_between_steps():
    world = gas(20_000)
    # Python's own Ctrl-C handler, as in a terminal: a process started in the background of
    # a non-interactive shell (`nohup ... &`, some CI runners) begins with SIGINT ignored,
    # and then `interrupt_main` does nothing.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            world.step(1_000_000)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    steps = world.step_count
    assert 0 < steps < 1_000_000
    # The world is whole: it steps on, and time agrees with the steps.
    world.step(2)
    assert world.step_count == steps + 2
    assert world.time == pytest.approx((steps + 2) * 0.01)


def test_no_memory_growth_over_ten_thousand_steps():
    world = gas(2_000)
    world.step(500)
    for _ in range(200):
        world.positions, world.stats  # noqa: B018 (reading is the point)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    for _ in range(100):
        world.step(100)
        _ = world.positions
        _ = world.velocities
        _ = world.stats
        with world.storage_view() as v:
            _ = v.x.sum()
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    assert world.step_count == 10_500
    # ru_maxrss is in KiB on Linux: under 2 MiB of growth for 10,000 steps.
    assert after - before < 2048, (before, after)


def test_a_checkpoint_round_trip_continues_bit_for_bit(tmp_path):
    world = gas(3_000)
    world.step(25)
    path = tmp_path / "state.bin"
    world.save(path)
    loaded = bounce.World.load(path, dt=0.01, threads=2)
    assert loaded.state_hash() == world.state_hash()
    assert loaded.step_count == 25 and loaded.time == world.time
    world.step(40)
    loaded.step(40)
    assert loaded.state_hash() == world.state_hash()


def test_gsd_files_read_back_with_the_gsd_package(tmp_path):
    import gsd.hoomd as gsd_hoomd  # scripts/test installs it
    world = gas(500)
    path = tmp_path / "traj.gsd"
    with bounce.GSDWriter(path, every=10) as writer:
        world.add_writer(writer)  # frame at step 0
        world.step(35)  # frames at 10, 20, 30
        final = world.positions
    world.step()  # the closed writer is left alone
    with gsd_hoomd.open(path) as trajectory:
        assert len(trajectory) == 4
        assert [int(f.configuration.step) for f in trajectory] == [0, 10, 20, 30]
        last = trajectory[3]
        assert last.particles.N == 500 and last.configuration.dimensions == 2
        side = np.sqrt(500 / 0.3)
        np.testing.assert_allclose(last.configuration.box[:2], [side, side], rtol=1e-6)
    # Positions are relative to the box centre, in id order (frame 30 is `final` minus
    # the five more steps: compare a fresh one-frame file instead).
    one = tmp_path / "one.gsd"
    world.write_gsd(one)
    with gsd_hoomd.open(one) as trajectory:
        frame = trajectory[0]
        np.testing.assert_allclose(
            frame.particles.position[:, :2], world.positions - side / 2, atol=1e-4
        )
        np.testing.assert_allclose(frame.particles.diameter, 1.0)
    assert final.shape == (500, 2)


def test_the_plain_step_gives_the_fast_steps_bits():
    fast, plain = gas(3000, threads=2), gas(3000)
    for _ in range(30):
        fast.step()
        plain.step(plain=True)
        assert fast.state_hash() == plain.state_hash()
        assert fast.stats["collisions"] == plain.stats["collisions"]
    assert fast.stats["collisions"] > 0
    # A dilute gas sorts its one detection a step; nothing was presorted.
    assert (fast.profile["sorted_detections"], fast.profile["out_of_place"]) == (1, 0)
