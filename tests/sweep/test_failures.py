"""A cluster that fails under a sweep: a run lost with its worker is not recorded (it runs again on resume), no
worker left stops the sweep with one line and exit code 1 after a bounded wait, and so does a lost scheduler."""

from __future__ import annotations

import os
import signal
import threading
from pathlib import Path

import dask
import distributed  # noqa: F401 - its configuration defaults must exist before dask.config.set changes one
import pandas as pd
import pytest

from tests.sweep.helpers import (BIN, die_on_marked_run, rows_in, scheduler_address, slow_run, start, stop_group,
                                 wait_for, warm_kernels, write_sweep)
from uvms.cli import main
from uvms.sweep import SweepStopped, load_sweep, run


@pytest.fixture(scope="module")
def warm():
    warm_kernels()


def test_a_run_lost_with_its_worker_is_not_recorded_and_runs_on_resume(tmp_path, monkeypatch, warm):
    path = write_sweep(tmp_path, parameters={"description": ["first", "die", "third", "fourth"]})
    out = tmp_path / "out"
    monkeypatch.setattr("uvms.sweep.execute._TASK", die_on_marked_run)
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), pytest.raises(SweepStopped) as caught:
        run(path, out_dir=out, workers=2)
    stopped = caught.value  # the run that killed its worker, and any queued on that worker with it
    assert " not recorded: the Dask cluster failed" in stopped.reason and "KilledWorker" in stopped.reason
    assert 1 <= stopped.done <= 3 and stopped.total == 4
    sweep = load_sweep(path)
    lost = next(r.run_id for r in sweep.runs if r.parameters["description"] == "die")
    recorded = pd.read_csv(out / "runs.csv")
    assert lost not in set(recorded["run_id"]) and len(recorded) == stopped.done
    assert (recorded["status"] == "ok").all()
    assert not (out / "summary.csv").exists()

    monkeypatch.undo()  # the real task again: the lost run is run on resume
    rows = run(path, out_dir=out, workers=1)
    assert len(rows) == 4 and (rows["status"] == "ok").all() and lost in set(rows["run_id"])
    assert pd.read_csv(out / "runs.csv")["run_id"].is_unique and (out / "summary.csv").exists()


def test_cli_reports_a_lost_run_in_one_line_with_exit_1(tmp_path, capsys, monkeypatch, warm):
    path = write_sweep(tmp_path, parameters={"description": ["die", "second"]})
    monkeypatch.setattr("uvms.sweep.execute._TASK", die_on_marked_run)
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        code = main(["sweep", str(path), "-o", str(tmp_path / "out"), "--workers", "1"])
    err = capsys.readouterr().err
    assert code == 1 and err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith("uvms: error: ") and " not recorded: the Dask cluster failed" in err
    assert " of 2 runs recorded in" in err
    assert "run the same command again to resume" in err


def _external_cluster(tmp_path: Path):
    scheduler_file = tmp_path / "scheduler.json"
    scheduler = start([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                       "--scheduler-file", str(scheduler_file)], tmp_path)
    address = scheduler_address(scheduler_file, scheduler)
    worker = start([str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1", "--host",
                    "127.0.0.1", "--no-dashboard", "--death-timeout", "60"], tmp_path)
    return scheduler, worker, address


@pytest.mark.slow
@pytest.mark.parametrize("pull", ["worker", "scheduler"])
def test_a_cluster_pulled_away_stops_the_sweep_in_one_line(tmp_path, capsys, monkeypatch, warm, pull):
    """All workers gone, or the scheduler gone, in the middle of a sweep: one line, exit code 1, and the rows
    recorded so far stay; the same command on a working cluster completes the sweep."""
    monkeypatch.setattr("uvms.sweep.execute.WORKER_WAIT", 5.0)
    monkeypatch.setattr("uvms.sweep.execute._TASK", slow_run)
    path = write_sweep(tmp_path, parameters={"controller.parameters.hydro_scale": [0.4, 0.6, 0.8, 1.0, 1.2, 1.4]})
    out = tmp_path / "out"
    scheduler, worker, address = _external_cluster(tmp_path)
    result: dict[str, int] = {}
    try:
        thread = threading.Thread(target=lambda: result.update(code=main(
            ["sweep", str(path), "-o", str(out), "--scheduler", address])), daemon=True)
        thread.start()
        wait_for(lambda: rows_in(out) >= 1 or not thread.is_alive(), 180, "a first row")
        os.killpg((worker if pull == "worker" else scheduler).pid, signal.SIGKILL)
        thread.join(timeout=120)  # the bound: WORKER_WAIT, or the client's reconnection timeout
        assert not thread.is_alive(), "the sweep still waits"
    finally:
        stop_group(worker)
        stop_group(scheduler)
    err = capsys.readouterr().err
    assert result["code"] == 1 and err.count("\n") == 1 and "Traceback" not in err, err
    reason = "no Dask worker left (waited 5 s)" if pull == "worker" else "lost the connection to the Dask scheduler"
    assert err.startswith(f"uvms: error: {reason}") and "run the same command again to resume" in err, err
    recorded = pd.read_csv(out / "runs.csv")
    assert 1 <= len(recorded) < 6 and (recorded["status"] == "ok").all()

    monkeypatch.undo()
    assert main(["sweep", str(path), "-o", str(out), "--workers", "1"]) == 0
    final = pd.read_csv(out / "runs.csv")
    assert len(final) == 6 and final["run_id"].is_unique and (final["status"] == "ok").all()
