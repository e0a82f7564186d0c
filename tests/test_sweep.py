"""Sweeps: file validation (one-line errors), deterministic draws, metrics against Result, runs.csv repair,
and end to end with Dask: a tiny sweep, SIGKILL and Ctrl-C then resume, and an external scheduler.

Every subprocess starts in its own session and is killed with its whole process group on the way out, within
bounded timeouts. The numba kernels are compiled (or loaded from the disk cache) once in this process before any
worker starts, so the workers only load them.
"""

from __future__ import annotations

import copy
import json
import os
import signal
import subprocess
import sys
import time
from importlib.resources import files
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.sweep import load_sweep, run, summarize, sweep_from_data
from uvms.sweep.spec import parameter_sets, set_path
from uvms.sweep.store import RunStore, columns

from .sweep.helpers import scheduler_address
from .sweep.helpers import stop_group as _stop_group

CASE3 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case3_controlled.yaml").read_text())
BIN = Path(sys.executable).parent
DURATION = 0.3


def write_files(tmp_path: Path, *, runs: int = 6, duration: float = DURATION, seed: int = 1, **extra) -> Path:
    """A shortened paper case 3 (``base.yaml``) and a sweep over it (``sweep.yaml``) in ``tmp_path``."""
    base = copy.deepcopy(CASE3)
    base.update(name="short", duration=duration)
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(base, sort_keys=False))
    sweep = {"name": "tiny", "base": "base.yaml", "runs": runs, "seed": seed, "controllers": ["smc-ab", "smc-vehicle"],
             "parameters": {"controller.parameters.hydro_scale": {"uniform": [0.3, 1.7]},
                            "inputs.current.constant": {"uniform_vector": {"low": [-0.2, -0.2, 0.0],
                                                                           "high": [0.2, 0.2, 0.0]}}},
             **extra}
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(sweep, sort_keys=False))
    return path


@pytest.fixture(scope="module")
def warm_kernels():
    """Compile (or load) the kernels both controllers use, here, before any worker process starts."""
    from uvms.sim.scenario import run_scenario, scenario_from_data

    for name in ("smc-ab", "smc-vehicle"):
        for current in (None, [0.1, 0.0, 0.0]):  # with a current, the kernels get another specialisation
            data = copy.deepcopy(CASE3)
            data.update(duration=0.03)
            data["controller"]["name"] = name
            if current is not None:
                data["inputs"]["current"] = {"constant": current}
            assert run_scenario(scenario_from_data(data)).complete


def read_runs(out: Path) -> tuple[bytes, pd.DataFrame]:
    raw = (out / "runs.csv").read_bytes()
    return raw, pd.read_csv(out / "runs.csv")


def assert_one_row_per_run(out: Path, sweep_path: Path) -> pd.DataFrame:
    raw, df = read_runs(out)
    assert raw.endswith(b"\n")
    expected = {r.run_id for r in load_sweep(sweep_path).runs}
    assert df["run_id"].is_unique
    assert set(df["run_id"]) == expected
    assert set(df["status"]) <= {"ok", "failed"}
    return df


# ---------------------------------------------------------------------------------------------- files


def test_draws_are_deterministic_and_paired(tmp_path):
    path = write_files(tmp_path)
    a, b = load_sweep(path), load_sweep(path)
    assert [r.run_id for r in a.runs] == [r.run_id for r in b.runs]
    assert [r.parameters for r in a.runs] == [r.parameters for r in b.runs]
    assert len(a.runs) == 12 and a.sha256 == b.sha256
    for k in range(0, 12, 2):  # each draw once per controller, same values
        assert a.runs[k].parameters == a.runs[k + 1].parameters
        assert (a.runs[k].controller, a.runs[k + 1].controller) == ("smc-ab", "smc-vehicle")
    scales = [r.parameters["controller.parameters.hydro_scale"] for r in a.runs[::2]]
    assert len(set(scales)) == 6 and all(0.3 <= s <= 1.7 for s in scales)
    currents = np.array([r.parameters["inputs.current.constant"] for r in a.runs])
    assert np.all(np.abs(currents[:, :2]) <= 0.2) and np.all(currents[:, 2] == 0.0)
    other = load_sweep(write_files(tmp_path, seed=2))
    assert other.sha256 != a.sha256 and other.runs[0].parameters != a.runs[0].parameters


def test_grid_crossed_with_draws_shares_random_values_and_adding_a_parameter_keeps_the_others():
    spec = sweep_from_data({"base": "paper_case3_controlled", "runs": 3, "seed": 5, "parameters": {
        "controller.parameters.eta": [0.3, 0.5],
        "controller.parameters.hydro_scale": {"normal": [1.0, 0.1]}}}).spec
    sets = parameter_sets(spec)
    assert [s["controller.parameters.eta"] for s in sets] == [0.3] * 3 + [0.5] * 3
    draws = [s["controller.parameters.hydro_scale"] for s in sets]
    assert draws[:3] == draws[3:]  # common random numbers across grid points
    more = sweep_from_data({"base": "paper_case3_controlled", "runs": 3, "seed": 5, "parameters": {
        "controller.parameters.hydro_scale": {"normal": [1.0, 0.1]},
        "controller.parameters.bandwidth": {"choice": [2.0, 3.14]}}}).spec
    assert [s["controller.parameters.hydro_scale"] for s in parameter_sets(more)] == draws[:3]


def test_set_path_creates_mappings_and_indexes_lists():
    data = copy.deepcopy(CASE3)
    set_path(data, "inputs.current.constant", [0.1, 0.0, 0.0])
    set_path(data, "inputs.joint_torques[1].torques", [0.0, 0.0, 0.0])
    assert data["inputs"]["current"] == {"constant": [0.1, 0.0, 0.0]}
    assert data["inputs"]["joint_torques"][1]["torques"] == [0.0, 0.0, 0.0]
    with pytest.raises(UvmsInputError, match=r"index \[5\] out of range"):
        set_path(data, "inputs.joint_torques[5].torques", [0, 0, 0])


BAD = {  # change to the sweep data -> text of the one error line
    "unknown_key": (lambda d: d.update(rnus=3), "sweep.yaml: rnus: unknown key; expected one of: base, controllers"),
    "bad_distribution": (lambda d: d["parameters"].update({"duration": {"uniform": [2.0, 1.0]}}),
                         "sweep.yaml: parameters.duration.uniform: expected [low, high] with low <= high"),
    "unknown_form": (lambda d: d["parameters"].update({"duration": {"gauss": [1, 2]}}),
                     "sweep.yaml: parameters.duration: expected a number or string (a fixed value), a list (a grid)"),
    "unknown_path": (lambda d: d["parameters"].update({"inputs.curent.constant": {"value": [0, 0, 0]}}),
                     "sweep.yaml: parameters.inputs.curent.constant: inputs.curent: unknown key"),
    "unknown_controller_parameter": (
        lambda d: d["parameters"].update({"controller.parameters.model_error": {"uniform": [0.3, 1.7]}}),
        "sweep.yaml: parameters.controller.parameters.model_error: unknown parameter; expected one of:"),
    "bad_value_for_scenario": (lambda d: d["parameters"].update({"step": {"value": "fast"}}),
                               "sweep.yaml: parameters.step: expected a finite number, found 'fast'"),
    "unknown_controller": (lambda d: d.update(controllers=["smc-ab", "smc"]),
                           "sweep.yaml: controllers[1]: unknown controller 'smc'"),
    "unknown_metric": (lambda d: d.update(metrics=["peak_error"]), "sweep.yaml: metrics[0]: unknown metric"),
    "missing_base": (lambda d: d.update(base="nowhere.yaml"), "sweep.yaml: base: no such file or bundled scenario"),
    "runs_without_random": (lambda d: d.update(parameters={"duration": [0.1, 0.2]}),
                            "sweep.yaml: runs: expected runs: 1 when no parameter is random"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_sweep_file_exits_2_with_one_line(tmp_path, capsys, case):
    path = write_files(tmp_path)
    data = yaml.safe_load(path.read_text())
    mutate, expected = BAD[case]
    mutate(data)
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    code = main(["sweep", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("uvms: error: ") and str(path) in err
    assert expected.replace("sweep.yaml", "") in err.replace(str(path), ""), err
    assert not (tmp_path / "out").exists()


def test_bundled_sweep_loads():
    sweep = load_sweep("paper_model_error")
    assert len(sweep.runs) == 200 and sweep.spec.controllers == ("smc-ab", "smc-vehicle")


# ---------------------------------------------------------------------------------------------- store


def test_store_cuts_a_partial_last_line_and_refuses_another_sweep(tmp_path):
    path = write_files(tmp_path)
    sweep = load_sweep(path)
    out = tmp_path / "out"
    with RunStore.open(out, sweep) as store:
        cells = ["x"] * len(store.columns)
        cells[0] = sweep.runs[0].run_id
        store.append(cells)
        with pytest.raises(UvmsInputError, match="another uvms sweep is writing"):
            RunStore.open(out, sweep)
    with open(out / "runs.csv", "ab") as fh:
        fh.write(b"0001-smc-ab-0000,1,smc-ab,0.5")  # killed mid-write
    with RunStore.open(out, sweep) as store:
        assert list(store.done) == [sweep.runs[0].run_id]
    assert (out / "runs.csv").read_bytes().count(b"\n") == 2 and (out / "runs.csv").read_bytes().endswith(b"\n")
    assert json.loads((out / "sweep.json").read_text())["columns"] == columns(sweep)
    other = load_sweep(write_files(tmp_path, seed=9))
    with pytest.raises(UvmsInputError, match="not the current sweep file"):
        RunStore.open(out, other)


# ---------------------------------------------------------------------------------------------- metrics


def test_metrics_agree_with_result(warm_kernels):
    from uvms.sim.scenario import run_scenario, scenario_from_data
    from uvms.sweep import compute_metrics

    data = copy.deepcopy(CASE3)
    data.update(duration=0.5)
    data["inputs"]["current"] = {"constant": [0.1, -0.1, 0.0]}
    result = run_scenario(scenario_from_data(data))
    m = compute_metrics(result, ["peak_body_error_xy_m", "peak_abs_yaw_rad", "max_abs_s_surge", "rms_command_X",
                                 "final_q_joint1_rad", "final_q1_rad", "max_abs_yaw_rad", "max_abs_no_such_signal"])
    summary = result.summary()
    assert m["peak_body_error_xy_m"] == pytest.approx(summary["peak_body_error_xy_m"], rel=1e-12)
    assert m["peak_abs_yaw_rad"] == pytest.approx(summary["peak_abs_euler_rad"][2], rel=1e-12)
    assert m["max_abs_yaw_rad"] == pytest.approx(np.abs(result.euler[:, 2]).max(), rel=1e-12)
    assert m["max_abs_s_surge"] == pytest.approx(summary["peak_abs_signal"]["s_surge"], rel=1e-12)
    assert m["rms_command_X"] == pytest.approx(np.sqrt(np.mean(result.signals["command_X"] ** 2)), rel=1e-12)
    assert m["final_q_joint1_rad"] == result.q[-1, 0] and m["final_q1_rad"] == result.q[-1, 0]  # older name too
    assert np.isnan(m["max_abs_no_such_signal"])


# ---------------------------------------------------------------------------------------------- with Dask


def test_tiny_sweep_rows_summary_and_resume_in_process(tmp_path, warm_kernels):
    path = write_files(tmp_path)
    out = tmp_path / "out"
    seen = []
    df = run(path, out_dir=out, workers=2, progress=lambda done, total: seen.append((done, total)))
    assert len(df) == 12 and (df["status"] == "ok").all(), df[["run_id", "error"]]
    assert list(df["run_id"]) == [r.run_id for r in load_sweep(path).runs]  # run order, not completion order
    assert seen[0] == (0, 12) and seen[-1] == (12, 12)
    assert df.groupby("controller")["draw"].apply(list).to_dict() == {c: list(range(6)) for c in
                                                                      ("smc-ab", "smc-vehicle")}
    assert (df["wall_time_s"] > 0).all() and df["peak_body_error_xy_m"].notna().all()
    assert_one_row_per_run(out, path)

    summary = pd.read_csv(out / "summary.csv")
    assert set(summary["controller"]) == {"smc-ab", "smc-vehicle"}
    row = summary[(summary["controller"] == "smc-ab") & (summary["metric"] == "peak_body_error_xy_m")].iloc[0]
    values = df.loc[df["controller"] == "smc-ab", "peak_body_error_xy_m"]
    assert row["q50"] == pytest.approx(values.median()) and row["q05"] <= row["q50"] <= row["q95"]
    assert row["ok"] == 6 and row["failed"] == 0
    pd.testing.assert_frame_equal(summarize(df), summary, check_dtype=False)

    again = run(path, out_dir=out, workers=2)  # everything recorded: no cluster, same rows
    pd.testing.assert_frame_equal(again, df)
    assert (out / "runs.csv").read_bytes().count(b"\n") == 13


def test_failing_run_is_a_row_not_fatal(tmp_path, warm_kernels):
    path = write_files(tmp_path, runs=1, metrics=["peak_body_error_xy_m"])
    data = yaml.safe_load(path.read_text())
    data["parameters"] = {"controller.parameters.hydro_scale": [0.4, -1.0]}  # the second is invalid
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    df = run(path, workers=1)
    assert list(df["status"]) == ["ok", "ok", "failed", "failed"]
    assert "controller.parameters.hydro_scale: expected a number >= 0" in df["error"].iloc[2]
    assert df["peak_body_error_xy_m"].iloc[2:].isna().all()


def _start(args: list[str], cwd: Path) -> subprocess.Popen:
    return subprocess.Popen(args, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)


def _alive_in_group(pgid: int) -> list[str]:
    ps = subprocess.run(["ps", "-o", "pid=,stat=,args=", "-g", str(pgid)], capture_output=True, text=True)
    return [line for line in ps.stdout.splitlines() if line.split()[1][0] != "Z"]


def _wait_rows(out: Path, count: int, proc: subprocess.Popen, timeout: float = 120.0) -> int:
    end = time.monotonic() + timeout
    while time.monotonic() < end and proc.poll() is None:
        try:
            rows = (out / "runs.csv").read_bytes().count(b"\n") - 1
        except FileNotFoundError:
            rows = 0
        if rows >= count:
            return rows
        time.sleep(0.02)
    raise AssertionError(f"no {count} rows within {timeout} s; exit code {proc.poll()}")


@pytest.mark.slow
@pytest.mark.parametrize("how", ["SIGKILL", "Ctrl-C"])
def test_kill_and_resume(tmp_path, warm_kernels, how):
    path = write_files(tmp_path, runs=10, duration=2.0, metrics=["peak_body_error_xy_m", "rms_command_X"])
    out = tmp_path / "out"
    command = [str(BIN / "uvms"), "sweep", str(path), "-o", str(out), "--workers", "2"]
    proc = _start(command, tmp_path)
    try:
        _wait_rows(out, 3, proc)
        if how == "SIGKILL":
            proc.send_signal(signal.SIGKILL)
            proc.communicate(timeout=30)
        else:  # a terminal's Ctrl-C: SIGINT to the whole foreground process group (client and workers)
            os.killpg(proc.pid, signal.SIGINT)
            _, err = proc.communicate(timeout=60)
            assert proc.returncode == 130, err
            assert "Traceback" not in err and err.count("\n") == 1 and "interrupted:" in err, err
            assert not (out / "summary.csv").exists()
            deadline = time.monotonic() + 20
            while _alive_in_group(proc.pid) and time.monotonic() < deadline:
                time.sleep(0.2)
            assert not _alive_in_group(proc.pid)  # the workers were shut down with the client
    finally:
        _stop_group(proc)
    raw, first = read_runs(out)
    assert raw.endswith(b"\n") and first["run_id"].is_unique
    assert 3 <= len(first) < 20, "the sweep finished before the signal: nothing left to resume"
    if how == "SIGKILL":
        with open(out / "runs.csv", "ab") as fh:  # as if killed in the middle of writing a row
            fh.write(b"0009-smc-ab-deadbeef,9,smc-ab,0.7")

    again = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, timeout=300,
                           start_new_session=True)
    assert again.returncode == 0, again.stderr
    assert f"{20 - len(first)} new" in again.stdout and f"{len(first)} from before" in again.stdout
    df = assert_one_row_per_run(out, path)
    assert (df["status"] == "ok").all()
    kept = df.set_index("run_id").loc[first["run_id"]]  # rows of the first invocation untouched
    np.testing.assert_array_equal(kept["peak_body_error_xy_m"].to_numpy(), first["peak_body_error_xy_m"].to_numpy())
    assert (out / "summary.csv").exists()


def test_resume_refuses_a_changed_sweep(tmp_path, warm_kernels, capsys):
    path = write_files(tmp_path, runs=1, duration=0.05, metrics=["peak_body_error_xy_m"])
    out = tmp_path / "out"
    assert main(["sweep", str(path), "-o", str(out), "--workers", "1"]) == 0
    capsys.readouterr()
    write_files(tmp_path, runs=1, duration=0.05, seed=7, metrics=["peak_body_error_xy_m"])
    assert main(["sweep", str(path), "-o", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "sweep.json: this directory holds sweep 'tiny'" in err


@pytest.mark.slow
def test_external_scheduler_and_worker(tmp_path, warm_kernels, capsys):
    scheduler_file = tmp_path / "scheduler.json"
    scheduler = _start([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                        "--scheduler-file", str(scheduler_file)], tmp_path)
    worker = None
    try:
        address = scheduler_address(scheduler_file, scheduler)
        assert address.startswith("tcp://127.0.0.1:")
        worker = _start([str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1", "--host",
                         "127.0.0.1", "--no-dashboard", "--death-timeout", "60"], tmp_path)
        path = write_files(tmp_path, runs=2)
        out = tmp_path / "out"
        assert main(["sweep", str(path), "-o", str(out), "--scheduler", address]) == 0
        df = assert_one_row_per_run(out, path)
        assert len(df) == 4 and (df["status"] == "ok").all()
        assert "4 new" in capsys.readouterr().out
    finally:
        for proc in (worker, scheduler):
            if proc is not None:
                try:
                    os.killpg(proc.pid, signal.SIGTERM)
                except ProcessLookupError:
                    pass
        for proc in (worker, scheduler):
            if proc is not None:
                try:
                    proc.communicate(timeout=20)
                except subprocess.TimeoutExpired:
                    pass
                _stop_group(proc)
                deadline = time.monotonic() + 20      # a killed process is gone once the kernel has torn it down
                while _alive_in_group(proc.pid) and time.monotonic() < deadline:
                    time.sleep(0.2)
                assert not _alive_in_group(proc.pid)


def test_unreachable_scheduler_is_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("uvms.sweep.execute.CONNECT_TIMEOUT", 2.0)
    path = write_files(tmp_path, runs=1, duration=0.05)
    code = main(["sweep", str(path), "-o", str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:9"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "--scheduler: cannot connect to the Dask scheduler" in err
    assert not (tmp_path / "out").exists()          # nothing ran: no folder left behind


@pytest.mark.parametrize("extra, message", [
    (["--scheduler", "notanaddress"], "notanaddress: --scheduler: expected a Dask scheduler address such as"),
    (["--workers", "100000"], "--workers: expected 1 to"),
])
def test_malformed_scheduler_or_too_many_workers_is_one_line_and_leaves_nothing(tmp_path, capsys, extra, message):
    path = write_files(tmp_path, runs=1, duration=0.05)
    assert main(["sweep", str(path), "-o", str(tmp_path / "out"), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "out").exists()


def test_a_base_that_is_a_folder_names_the_sweep_file_and_field(tmp_path, capsys):
    path = write_files(tmp_path, runs=1, duration=0.05)
    data = yaml.safe_load(path.read_text())
    data["base"] = "."
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    assert main(["sweep", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"uvms: error: {path}: base: ") and err.endswith("expected a YAML file, found a directory\n")
    assert err.count("\n") == 1 and not (tmp_path / "out").exists()


@pytest.mark.parametrize("field, value, expected", [("runs", "true", "runs: expected a whole number, found True"),
                                                    ("runs", "2.5", "runs: expected a whole number, found 2.5"),
                                                    ("seed", "false", "seed: expected a whole number, found False")])
def test_counts_are_whole_numbers_not_booleans(tmp_path, field, value, expected):
    from uvms.sweep.spec import load_sweep

    path = tmp_path / "sweep.yaml"
    path.write_text(f"base: paper_case3_controlled\n{field}: {value}\n")
    with pytest.raises(UvmsInputError, match=expected):
        load_sweep(path)
