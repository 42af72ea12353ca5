"""Shared fixtures: the repository root, the `bounce` command, a scratch directory."""

import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def bounce_bin():
    """The `bounce` command built from this checkout (BOUNCE_BIN, else target/release)."""
    candidates = [os.environ.get("BOUNCE_BIN")]
    target = os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target"))
    candidates.append(os.path.join(target, "release", "bounce"))
    for path in candidates:
        if path and os.path.exists(path):
            return path
    # Build it: the tests compare against the real command, never skip.
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "bounce-cli"], cwd=ROOT, check=True
    )
    return os.path.join(target, "release", "bounce")


def run_cli(bounce_bin, *args):
    """Runs `bounce`, returns its combined output; fails the test on a non-zero exit."""
    done = subprocess.run(
        [bounce_bin, *map(str, args)], capture_output=True, text=True, cwd=ROOT
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout + done.stderr
