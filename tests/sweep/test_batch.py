"""Batches of runs on a worker (:func:`uvms.sweep.execute.run_batch`): the same rows as one task per run (the
compiled batch runner against ``simulate``'s chunked loop, number for number), failures inside a batch are rows
of their own, batch sizes, the local cluster's layout, and a sweep killed between batches resumes to the rows
of an uninterrupted one."""

from __future__ import annotations

import copy
import math
import os
import signal
import subprocess

import numpy as np
import pandas as pd
import pytest
import yaml

from tests.sweep.helpers import (BIN, CASE3, ROOT, SRC, rows_in, start, stop_group, wait_for, warm_kernels,
                                 write_sweep)
from uvms.sweep import load_sweep, run
from uvms.sweep import execute
from uvms.sweep.cluster import process_threads
from uvms.sweep.execute import BatchSizer, run_batch, run_task
from uvms.sweep.spec import set_path
from uvms.sweep.store import run_cells

METRICS = ["peak_body_error_xy_m", "final_body_error_xy_m", "rms_command_X", "max_abs_s_yaw"]


@pytest.fixture(scope="module")
def warm():
    warm_kernels()


def _task(duration: float = 0.3, **changes) -> dict:
    """A task of a shortened paper case 3 with ``changes`` at dotted paths."""
    data = copy.deepcopy(CASE3)
    data.update(name="short", duration=duration)
    for path, value in changes.items():
        set_path(data, path, value)
    return {"data": data, "base_dir": ".", "source": None, "metrics": METRICS}


def _same(batch: dict, alone: dict) -> None:
    """Same status, error and metrics, to the last bit (NaN where NaN)."""
    assert (batch["status"], batch["error"]) == (alone["status"], alone["error"])
    assert batch["metrics"].keys() == alone["metrics"].keys()
    for name, value in alone["metrics"].items():
        assert batch["metrics"][name] == value or (math.isnan(value) and math.isnan(batch["metrics"][name])), name
    assert batch["wall_time_s"] > 0


@pytest.mark.parametrize("threads", [1, 2])
def test_a_batch_gives_the_rows_of_one_task_per_run(tmp_path, warm, threads):
    """A sweep's tasks (both controllers, random model error and current) through one batch and through
    run_task one by one: the same rows (runs.csv cells) but for the wall time."""
    path = write_sweep(tmp_path, duration=0.5, runs=3, controllers=["smc-ab", "smc-vehicle"],
                       parameters={"controller.parameters.hydro_scale": {"uniform": [0.3, 1.7]},
                                   "inputs.current.constant": {"uniform_vector": {"low": [-0.2, -0.2, 0.0],
                                                                                  "high": [0.2, 0.2, 0.0]}}},
                       metrics=METRICS)
    sweep = load_sweep(path)
    tasks = [task for _, task in execute._tasks(sweep, sweep.runs)]
    assert len(tasks) == 6
    alone = [run_task(task) for task in tasks]
    batch = run_batch(tasks, threads=threads)
    assert [o["status"] for o in alone] == ["ok"] * 6
    assert len({o["metrics"]["peak_body_error_xy_m"] for o in alone}) == 6  # six different runs
    for run_, b, a in zip(sweep.runs, batch, alone):
        _same(b, a)
        keep = [k for k, name in enumerate(execute.columns(sweep)) if name != "wall_time_s"]
        cells_b, cells_a = run_cells(sweep, run_, b), run_cells(sweep, run_, a)
        assert [cells_b[k] for k in keep] == [cells_a[k] for k in keep]


def test_failing_runs_inside_a_batch_are_rows_of_their_own(warm, monkeypatch):
    """A batch of: a good run, a run that diverges, a run whose scenario is invalid, a run that is not
    compilable (adaptive integrator: run_task's simulate), another good run. Each outcome is run_task's; only
    the run that is not compilable leaves the batch runner."""
    tasks = [_task(), _task(**{"inputs.body_wrench": [0, 0, 0, 1e12, 0, 0]}),
             _task(**{"controller.parameters.hydro_scale": -1.0}), _task(integrator="DOP853"),
             _task(**{"controller.parameters.hydro_scale": 1.5})]
    alone = [run_task(task) for task in tasks]
    assert [o["status"] for o in alone] == ["ok", "failed", "failed", "ok", "ok"]
    assert alone[1]["error"].startswith("simulation diverged at t = ")
    assert alone[2]["error"] == "controller.parameters.hydro_scale: expected a number >= 0, found -1.0"

    left_the_batch = []

    def recorded(task):
        left_the_batch.append(task)
        return run_task(task)

    monkeypatch.setattr(execute, "run_task", recorded)
    batch = run_batch(tasks)
    for b, a in zip(batch, alone):
        _same(b, a)
    assert left_the_batch == [tasks[3]]


def test_a_batch_runner_that_raises_runs_each_run_on_its_own(warm, monkeypatch):
    """Should run_plans raise, every run of the batch gets run_task's outcome (the one at fault alone fails)."""
    tasks = [_task(), _task(**{"controller.parameters.hydro_scale": 0.5})]
    alone = [run_task(task) for task in tasks]

    def broken(plans, *, threads, progress=None):
        raise RuntimeError("the batch runner failed")

    monkeypatch.setattr("uvms.sim.batch.run_plans", broken)
    for b, a in zip(run_batch(tasks), alone):
        _same(b, a)


def test_a_stand_in_for_run_task_runs_every_task_in_turn():
    seen = []
    outcomes = run_batch([{"n": 1}, {"n": 2}], lambda task: seen.append(task["n"]) or {"n": task["n"]})
    assert seen == [1, 2] and outcomes == [{"n": 1}, {"n": 2}]


def test_batch_sizes():
    sizer = BatchSizer(threads=1)
    assert sizer.size(left=1000, slots=4) == 1                    # nothing measured: one run per thread
    assert BatchSizer(threads=2).size(left=1000, slots=4) == 2
    for _ in range(4):
        sizer.record({"wall_time_s": 0.125})
    assert sizer.size(left=1000, slots=4) == round(execute.BATCH_SECONDS / 0.125)
    assert sizer.size(left=10, slots=4) == 3                      # an equal share of the last runs
    assert sizer.size(left=1, slots=4) == 1
    sizer.record({"wall_time_s": float("nan")})                   # not counted
    sizer.record({})
    assert sizer.runs == 4
    fast = BatchSizer()
    fast.record({"wall_time_s": 1e-9})
    assert fast.size(left=10**6, slots=2) == execute.MAX_BATCH
    slow = BatchSizer()
    slow.record({"wall_time_s": 30.0})
    assert slow.size(left=10**6, slots=2) == 1


@pytest.mark.parametrize("workers, threads, layout", [(1, 1, [1]), (2, 1, [1, 1]), (2, 2, [2]), (5, 2, [2, 2, 1]),
                                                      (3, 4, [3]), (7, 3, [3, 2, 2])])
def test_local_process_layout(workers, threads, layout):
    assert process_threads(workers, threads) == layout


def test_a_local_cluster_of_threads_in_fewer_processes(tmp_path, warm, monkeypatch):
    """--workers 2 in one process of two threads: both threads run batches; the rows are those of the default
    layout."""
    path = write_sweep(tmp_path, duration=0.2, runs=3, parameters={
        "controller.parameters.hydro_scale": {"uniform": [0.3, 1.7]}}, metrics=METRICS)
    monkeypatch.setattr(execute, "THREADS_PER_PROCESS", 2)
    rows = run(path, workers=2)
    monkeypatch.undo()
    expected = pd.DataFrame([[run_task(task)["metrics"][m] for m in METRICS]
                             for _, task in execute._tasks(load_sweep(path), load_sweep(path).runs)], columns=METRICS)
    assert (rows["status"] == "ok").all() and len(rows) == 3
    np.testing.assert_array_equal(rows[METRICS].to_numpy(), expected.to_numpy())


@pytest.mark.slow
def test_a_sweep_killed_between_batches_resumes_to_the_uninterrupted_rows(tmp_path, warm):
    """SIGKILL of `uvms sweep` once some batches are recorded: the rows kept are whole rows, the resumed sweep
    runs exactly the runs missing, and every row (old and new) is the row of an uninterrupted sweep."""
    path = write_sweep(tmp_path, duration=1.0, runs=20, controllers=["smc-ab", "smc-vehicle"], parameters={
        "controller.parameters.hydro_scale": {"uniform": [0.3, 1.7]},
        "inputs.current.constant": {"uniform_vector": {"low": [-0.2, -0.2, 0.0], "high": [0.2, 0.2, 0.0]}}},
        metrics=METRICS)
    out = tmp_path / "out"
    command = [str(BIN / "uvms"), "sweep", str(path), "-o", str(out), "--workers", "1"]
    proc = start(command, tmp_path)
    try:
        wait_for(lambda: rows_in(out) >= 3 or proc.poll() is not None, 180, "three rows")
        proc.send_signal(signal.SIGKILL)
        proc.communicate(timeout=30)
    finally:
        stop_group(proc)
    first = pd.read_csv(out / "runs.csv")
    assert first["run_id"].is_unique and 3 <= len(first) < 40, "the sweep finished before the kill"

    env = dict(os.environ, PYTHONPATH=os.pathsep.join([SRC, ROOT, os.environ.get("PYTHONPATH", "")]))
    again = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, timeout=300,
                           start_new_session=True, env=env)
    assert again.returncode == 0, again.stderr
    assert f"{40 - len(first)} new" in again.stdout and f"{len(first)} from before" in again.stdout
    resumed = pd.read_csv(out / "runs.csv")
    assert len(resumed) == 40 and resumed["run_id"].is_unique and (resumed["status"] == "ok").all()

    whole = run(path, workers=1).set_index("run_id")
    resumed = resumed.set_index("run_id").loc[whole.index]
    np.testing.assert_array_equal(resumed[METRICS].to_numpy(), whole[METRICS].to_numpy())
