"""Running a sweep with Dask, recording each finished run as it completes, and summarising the rows.

The client keeps a sliding window of submitted runs (two per worker thread): a kill loses at most those in
flight, and every finished run is appended to ``runs.csv`` (:mod:`uvms.sweep.store`) by the client alone.
Workers run :func:`run_task`, a module-level function: each worker imports uvms once, and the numba kernels
come from the on-disk cache (:mod:`uvms._cache`). A run that raises or diverges is a row with
``status = failed`` and its one-line error; it does not stop the sweep.
"""

from __future__ import annotations

import io
import logging
import os
import re
import shutil
import time
import uuid
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Any

from uvms.errors import UvmsInputError
from uvms.sweep.spec import Sweep, SweepRun, load_sweep
from uvms.sweep.store import RunStore, columns, format_line, parameter_columns, run_cells

QUANTILES = (0.05, 0.5, 0.95)
CONNECT_TIMEOUT = 20.0
"""Seconds to wait for a scheduler to answer, and for it to have at least one worker."""
WORKER_WAIT = 120.0
WORKERS_PER_CPU = 4
"""Most local workers per CPU (``--workers``): more only queue for the same cores."""
_ADDRESS = re.compile(r"(?:[a-z]+://)?(?:\[[0-9a-fA-F:.]+\]|[^\s/:\[\]]+):\d{1,5}")
"""A Dask scheduler address: ``[protocol://]host:port``, an IPv6 host in brackets."""


def run_task(task: dict[str, Any]) -> dict[str, Any]:
    """Simulate one run on a worker: ``task`` holds the scenario ``data``, ``base_dir``, ``source`` and the
    ``metrics`` to compute; returns ``{status, error, metrics, wall_time_s}`` (never raises)."""
    from uvms.sim.scenario import run_scenario, scenario_from_data
    from uvms.sweep.metrics import compute_metrics

    start = time.perf_counter()
    try:
        scenario = scenario_from_data(task["data"], source=task["source"], base_dir=task["base_dir"])
        result = run_scenario(scenario)
        if not result.complete:
            outcome = {"status": "failed", "error": result.message, "metrics": {}}
        else:
            outcome = {"status": "ok", "error": "", "metrics": compute_metrics(result, task["metrics"])}
    except Exception as exc:  # noqa: BLE001 - recorded in the row, never fatal to the sweep
        outcome = {"status": "failed", "error": _describe(exc), "metrics": {}}
    outcome["wall_time_s"] = time.perf_counter() - start
    return outcome


def _describe(exc: Exception) -> str:
    """One line for a failed run: an input error as ``field.path: message`` (the base file is in sweep.json)."""
    from uvms.errors import SimulationDiverged

    if isinstance(exc, UvmsInputError):
        text = f"{exc.path}: {exc.message}" if exc.path else exc.message
    elif isinstance(exc, SimulationDiverged):
        text = str(exc)
    else:
        text = f"{type(exc).__name__}: {exc}"
    return " ".join(text.split()) or type(exc).__name__


def dask_setup(worker=None) -> None:
    """Preload of the local cluster's workers (``LocalCluster(preload=[__name__])``): import uvms at start-up
    and ignore SIGINT, so that a Ctrl-C at the terminal (sent to every process of the foreground group) stops
    only the client, which then shuts the workers down cleanly."""
    import signal
    import threading

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


def warm_up(tasks: list[dict[str, Any]]) -> int:
    """Import uvms and load (or compile) the kernels on a worker: each task shortened to three control periods."""
    count = 0
    for task in tasks:
        data = dict(task["data"])
        controller = data.get("controller")
        period = controller.get("period", 0.01) if isinstance(controller, dict) else None
        step = data.get("step", 0.001)
        try:
            data["duration"] = 3 * max(float(period or 0.0), float(step))
            run_task({**task, "data": data})
            count += 1
        except Exception:  # noqa: BLE001 - the real runs report any problem
            pass
    return count


def run(sweep_or_path: Sweep | str | os.PathLike[str], *, out_dir: str | os.PathLike[str] | None = None,
        workers: int = 2, scheduler: str | None = None,
        progress: Callable[[int, int], None] | None = None):
    """Run every run of a sweep in parallel and return one row per run (a pandas DataFrame, in run order).

    Args:
        sweep_or_path: a :class:`Sweep`, or a sweep file path or bundled name.
        out_dir: record into this directory (``runs.csv`` ...; see :mod:`uvms.sweep.store`), skipping the
            runs already recorded there (resume); ``None``: keep the rows in memory only.
        workers: local worker processes (one thread each) when no ``scheduler`` is given.
        scheduler: address of a running Dask scheduler (``tcp://host:8786``) to use instead.
        progress: ``progress(done, total)`` after each recorded run (and once at the start).

    Raises:
        UvmsInputError: invalid sweep, output directory or scheduler (one line).
        KeyboardInterrupt: passed on after the current row is written and the workers are shut down.
    """
    sweep = sweep_or_path if isinstance(sweep_or_path, Sweep) else load_sweep(sweep_or_path)
    most = WORKERS_PER_CPU * (os.cpu_count() or 1)
    if scheduler is None and (isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= most):
        raise UvmsInputError(f"expected 1 to {most} local workers ({WORKERS_PER_CPU} per CPU), found {workers!r}",
                             path="--workers")
    if scheduler is not None and not _ADDRESS.fullmatch(scheduler):
        raise UvmsInputError("expected a Dask scheduler address such as tcp://10.0.0.5:8786", scheduler, "--scheduler")
    header = columns(sweep)
    fresh = out_dir is not None and not Path(out_dir).exists()
    store = RunStore.open(out_dir, sweep) if out_dir is not None else None
    try:
        rows: dict[str, list[str]] = dict(store.done) if store is not None else {}
        planned = {run.run_id for run in sweep.runs}
        todo = [run for run in sweep.runs if run.run_id not in rows]
        total = len(sweep.runs)
        done = len(planned & set(rows))
        if progress is not None:
            progress(done, total)
        if todo:
            with ExitStack() as connection:
                try:
                    client = connection.enter_context(_connect(workers, scheduler))
                except UvmsInputError:
                    if store is not None and fresh:         # nothing was run: leave no folder behind
                        store.close()
                        store = None
                        shutil.rmtree(out_dir, ignore_errors=True)
                    raise
                for run, outcome in _execute(client, sweep, todo):
                    cells = run_cells(sweep, run, outcome)
                    if store is not None:
                        store.append(cells)
                    rows[run.run_id] = cells
                    done += 1
                    if progress is not None:
                        progress(done, total)
        frame = _frame(header, [rows[run.run_id] for run in sweep.runs if run.run_id in rows])
        frame.attrs.update(metrics=list(sweep.metrics), parameter_columns=[c for c, _, _ in parameter_columns(sweep)])
        if store is not None:
            store.write_summary(summarize(frame, metrics=sweep.metrics))
        return frame
    finally:
        if store is not None:
            store.close()


def summarize(df, *, metrics: tuple[str, ...] | list[str] | None = None):
    """Per controller and metric: runs, ok and failed counts, mean, std and the 5/50/95 % quantiles (over the
    ``ok`` runs). ``metrics`` defaults to ``df.attrs["metrics"]`` (set by :func:`run`), else to every numeric
    column that is not an identity, parameter or bookkeeping column."""
    import pandas as pd

    if metrics is None:
        metrics = df.attrs.get("metrics") or _metric_columns(df)
    records = []
    for controller, group in df.groupby("controller", sort=False):
        ok = group[group["status"] == "ok"]
        for metric in metrics:
            values = pd.to_numeric(ok[metric], errors="coerce").dropna()
            quantiles = values.quantile(list(QUANTILES)) if len(values) else pd.Series([float("nan")] * 3,
                                                                                          index=list(QUANTILES))
            records.append({"controller": controller, "metric": metric, "runs": len(group), "ok": len(ok),
                            "failed": int((group["status"] != "ok").sum()), "count": len(values),
                            "mean": values.mean() if len(values) else float("nan"),
                            "std": values.std() if len(values) > 1 else float("nan"),
                            **{f"q{round(q * 100):02d}": float(quantiles[q]) for q in QUANTILES}})
    columns = ["controller", "metric", "runs", "ok", "failed", "count", "mean", "std",
               *(f"q{round(q * 100):02d}" for q in QUANTILES)]
    return pd.DataFrame.from_records(records, columns=columns)


def _metric_columns(df) -> list[str]:
    """Numeric columns other than ``draw``, ``wall_time_s`` and the parameters (``df.attrs["parameters"]``)."""
    skip = {"draw", "wall_time_s", *df.attrs.get("parameter_columns", [])}
    return [c for c in df.select_dtypes("number").columns if c not in skip]


def _frame(header: list[str], rows: list[list[str]]):
    """The rows as a DataFrame, parsed exactly like ``runs.csv`` (same dtypes from memory or from the file)."""
    import pandas as pd

    text = format_line(header) + "".join(format_line(r) for r in rows)
    frame = pd.read_csv(io.StringIO(text), dtype={"run_id": str, "controller": str, "status": str, "error": str},
                        keep_default_na=False, na_values=[""])
    frame["error"] = frame["error"].fillna("")
    return frame


def _tasks(sweep: Sweep, runs: list[SweepRun]) -> Iterator[tuple[SweepRun, dict[str, Any]]]:
    source = sweep.base.source or sweep.source
    for run in runs:
        yield run, {"data": sweep.scenario_data(run), "base_dir": sweep.base_dir, "source": source,
                    "metrics": list(sweep.metrics)}


def _execute(client, sweep: Sweep, runs: list[SweepRun]) -> Iterator[tuple[SweepRun, dict[str, Any]]]:
    """Submit the runs in a sliding window and yield ``(run, outcome)`` as they finish."""
    from distributed import as_completed

    threads = max(1, sum(client.nthreads().values()))
    window = 2 * threads
    first = {}
    for run, task in _tasks(sweep, runs):
        first.setdefault(run.controller, task)
    try:
        client.run(warm_up, list(first.values()))
    except Exception:  # noqa: BLE001 - a worker that cannot warm up reports through its runs
        pass
    token = uuid.uuid4().hex[:8]
    pending = _tasks(sweep, runs)
    by_future: dict[Any, SweepRun] = {}

    def submit() -> Any | None:
        item = next(pending, None)
        if item is None:
            return None
        run, task = item
        future = client.submit(run_task, task, key=f"uvms-sweep-{token}-{run.run_id}", pure=False, retries=0)
        by_future[future] = run
        return future

    futures = [f for f in (submit() for _ in range(window)) if f is not None]
    completed = as_completed(futures, loop=client.loop)
    try:
        for future in completed:
            run = by_future.pop(future)
            try:
                outcome = future.result()
            except Exception as exc:  # noqa: BLE001 - a worker died or the task could not run
                outcome = {"status": "failed", "error": f"worker failure: {type(exc).__name__}: {exc}",
                           "metrics": {}, "wall_time_s": 0.0}
            future.release()
            nxt = submit()
            if nxt is not None:
                completed.add(nxt)
            yield run, outcome
    finally:
        if by_future:
            try:
                client.cancel(list(by_future), force=True)
            except Exception:  # noqa: BLE001 - shutting down anyway
                pass


@contextmanager
def _connect(workers: int, scheduler: str | None):
    """A Dask client: on a new local cluster of ``workers`` processes, or on the scheduler at ``scheduler``."""
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT, set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            raise UvmsInputError(f"cannot connect to the Dask scheduler: {' '.join(str(exc).split())}", scheduler,
                                 "--scheduler") from None
        try:
            try:
                client.wait_for_workers(1, timeout=WORKER_WAIT)
            except (TimeoutError, OSError):
                raise UvmsInputError(f"the Dask scheduler has no workers (waited {WORKER_WAIT:g} s)", scheduler,
                                     "--scheduler") from None
            yield client
        finally:
            _quietly(client.close, timeout=10)
        return

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=logging.CRITICAL, scheduler_port=0, preload=[__name__])
    client = Client(cluster, set_as_default=False)
    try:
        yield client
    finally:
        _quietly(client.close, timeout=10)
        _quietly(cluster.close, timeout=20)


def _quietly(close: Callable[..., Any], **kwargs: Any) -> None:
    """Shut something down, ignoring errors and the logging noise of a cluster going away."""
    level = logging.getLogger("distributed").level
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    try:
        close(**kwargs)
    except BaseException:  # noqa: BLE001 - a second Ctrl-C or a dead worker must not hide the first cause
        pass
    finally:
        logging.getLogger("distributed").setLevel(level)


def runs_table(out_dir: str | os.PathLike[str]):
    """A sweep directory's ``runs.csv`` as a DataFrame (a partial last line, from a kill, is left out)."""
    import csv

    text = (Path(out_dir) / "runs.csv").read_text(encoding="utf-8")
    rows = list(csv.reader(io.StringIO(text[: text.rfind("\n") + 1], newline="")))
    if not rows:
        raise UvmsInputError("empty file (no header)", str(Path(out_dir) / "runs.csv"))
    return _frame(rows[0], rows[1:])
