"""`bounce sweep` writes a workspace that signac itself reads: every job, its state point,
the id signac computes for it, and the job's outputs."""

import pytest
import signac
from signac.job import calc_id

import bounce

from conftest import run_cli


def test_signac_reads_the_sweeps_jobs_with_their_state_points_and_outputs(
    tmp_path, bounce_bin, root
):
    scenario = tmp_path / "gas.toml"
    run_cli(bounce_bin, "new", "gas", "--out", scenario)
    text = scenario.read_text().replace("frame_every = 30", "frame_every = 0")
    scenario.write_text(text.replace("gif = true", "gif = false"))
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(
        'scenario = "gas.toml"\nsteps = 40\nseeds = 2\n[parameters]\n'
        '"world.coefficient_of_restitution" = [0.8, 1.0]\n'
    )
    run_cli(bounce_bin, "sweep", sweep, "--out", tmp_path / "ws", "--jobs", "2")
    project = signac.get_project(str(tmp_path / "ws"))
    jobs = list(project)
    assert len(jobs) == 4
    points = sorted(
        (job.sp["world"]["coefficient_of_restitution"], job.sp["seed"]) for job in jobs
    )
    assert points == [(0.8, 0), (0.8, 1), (1.0, 0), (1.0, 1)]
    for job in jobs:
        assert calc_id(job.statepoint()) == job.id  # signac's own id for the state point
        assert job.isfile("stats.csv") and job.isfile("bounce_done")
    # signac's queries work on them.
    elastic = project.find_jobs({"world.coefficient_of_restitution": 1.0})
    assert len(elastic) == 2
    summary = (tmp_path / "ws" / "summary.csv").read_text().splitlines()
    assert summary[0].startswith("job_id,world.coefficient_of_restitution,seed,step,")
    assert sorted(row.split(",")[0] for row in summary[1:]) == sorted(job.id for job in jobs)


def test_bounce_sweep_from_python_returns_the_signac_project(tmp_path, bounce_bin):
    scenario = tmp_path / "gas.toml"
    run_cli(bounce_bin, "new", "gas", "--out", scenario)
    text = scenario.read_text().replace("frame_every = 30", "frame_every = 0")
    scenario.write_text(text.replace("gif = true", "gif = false"))
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('scenario = "gas.toml"\nsteps = 20\n[parameters]\n"gas.1.count" = [100, 200]\n')
    project = bounce.sweep(sweep, tmp_path / "ws", jobs=2, command=bounce_bin)
    assert sorted(job.sp["gas"]["1"]["count"] for job in project) == [100, 200]
    bad = tmp_path / "bad.toml"
    bad.write_text("[parameters]\n")
    with pytest.raises(RuntimeError, match="scenario"):
        bounce.sweep(bad, tmp_path / "bad", command=bounce_bin)
