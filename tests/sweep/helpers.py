"""Helpers of the sweep tests: a short sweep on disk, snapshots of folders, process-group hygiene, and the
task functions that stand in for :func:`uvms.sweep.run_task` on the workers to simulate a failing cluster
(importable by name there: the workers get the test process's ``sys.path``)."""

from __future__ import annotations

import copy
import os
import signal
import subprocess
import sys
import time
from importlib.resources import files
from pathlib import Path
from typing import Any

import yaml

CASE3 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case3_controlled.yaml").read_text())
BIN = Path(sys.executable).parent
ROOT = str(Path(__file__).resolve().parents[2])
SRC = str(Path(ROOT) / "src")


def write_sweep(folder: Path, *, duration: float = 0.05, parameters: dict | None = None, runs: int = 1,
                controllers: list[str] | None = None, name: str = "tiny", **extra: Any) -> Path:
    """A shortened paper case 3 (``base.yaml``) and a sweep over it (``sweep.yaml``) in ``folder``."""
    base = copy.deepcopy(CASE3)
    base.update(name="short", duration=duration)
    (folder / "base.yaml").write_text(yaml.safe_dump(base, sort_keys=False))
    sweep = {"name": name, "base": "base.yaml", "runs": runs, "controllers": controllers or ["smc-ab"],
             "metrics": ["peak_body_error_xy_m"],
             "parameters": parameters if parameters is not None else {
                 "controller.parameters.hydro_scale": [0.5, 1.0, 1.5]}, **extra}
    path = folder / "sweep.yaml"
    path.write_text(yaml.safe_dump(sweep, sort_keys=False))
    return path


def warm_kernels() -> None:
    """Compile (or load) the kernels of a short smc-ab run here, before any worker process starts."""
    from uvms.sim.scenario import run_scenario, scenario_from_data

    data = copy.deepcopy(CASE3)
    data.update(duration=0.03)
    assert run_scenario(scenario_from_data(data)).complete


def snapshot(folder: Path) -> dict[str, tuple[str, bytes | str, int]]:
    """Every entry under ``folder`` (hidden ones included): kind, content or link target, mode."""
    state = {}
    for path in sorted(folder.rglob("*")):
        st = path.lstat()
        if path.is_symlink():
            state[str(path.relative_to(folder))] = ("link", os.readlink(path), st.st_mode)
        elif path.is_dir():
            state[str(path.relative_to(folder))] = ("dir", b"", st.st_mode)
        else:
            state[str(path.relative_to(folder))] = ("file", path.read_bytes(), st.st_mode)
    return state


def start(args: list[str], cwd: Path, **kwargs: Any) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([SRC, ROOT, os.environ.get("PYTHONPATH", "")]))
    return subprocess.Popen(args, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, env=env, **kwargs)


def alive_in_group(pgid: int) -> list[str]:
    ps = subprocess.run(["ps", "-o", "pid=,stat=,args=", "-g", str(pgid)], capture_output=True, text=True)
    return [line for line in ps.stdout.splitlines() if line.split()[1][0] != "Z"]


def stop_group(proc: subprocess.Popen) -> None:
    """Kill whatever is left of ``proc``'s session (its process group) and reap ``proc``."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    try:
        proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:  # pragma: no cover
        pass


def wait_for(predicate, timeout: float, what: str) -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.02)
    raise AssertionError(f"{what} within {timeout} s")


def scheduler_address(scheduler_file: Path, scheduler, timeout: float = 60) -> str:
    """The address a ``dask scheduler --scheduler-file`` process writes, once the file is complete (it exists
    before its JSON is written)."""
    import json

    found: dict = {}

    def ready() -> bool:
        if scheduler.poll() is not None:
            raise AssertionError(f"the scheduler exited with {scheduler.returncode}")
        try:
            found.update(json.loads(scheduler_file.read_text()))
        except (OSError, ValueError):
            return False
        return "address" in found

    wait_for(ready, timeout, "the scheduler file")
    return found["address"]


def rows_in(out: Path) -> int:
    try:
        return max(0, (out / "runs.csv").read_bytes().count(b"\n") - 1)
    except FileNotFoundError:
        return 0


# ---------------------------------------------------------------------------------------------- worker tasks


def die_on_marked_run(task: dict[str, Any]) -> dict[str, Any]:
    """Kill the worker process on a run whose scenario ``description`` is ``"die"`` (a worker lost mid-run:
    the scheduler reports ``KilledWorker``), else run it normally."""
    from uvms.sweep import run_task

    if task["data"].get("description") == "die":
        os._exit(1)
    return run_task(task)


def slow_run(task: dict[str, Any]) -> dict[str, Any]:
    """A run that takes a few seconds (so that a test can pull the cluster from under it)."""
    from uvms.sweep import run_task

    time.sleep(3.0)
    return run_task(task)
