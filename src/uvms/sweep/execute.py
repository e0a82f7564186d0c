"""Running a sweep with Dask, recording each finished run as it completes, and summarising the rows.

The client keeps a sliding window of submitted *batches* of runs (two per worker thread): a kill loses at most
the runs of those in flight, and every run of a finished batch is appended to ``runs.csv``
(:mod:`uvms.sweep.store`) by the client alone, as soon as the batch returns. Workers run :func:`run_batch`, a
module-level function: it prepares each run of the batch (:func:`uvms.sim.scenario.plan_scenario`) and runs the
compilable ones through the batch runner :func:`uvms.sim.batch.run_plans` (compiled loops without the GIL, so
the threads of one worker process run in parallel), and any other one through :func:`run_task` (one run,
``simulate``'s Python loop). Each worker imports uvms once, and the numba kernels come from the on-disk cache
(:mod:`uvms._cache`). Batches are sized from the measured cost of the runs (:class:`BatchSizer`, about
:data:`BATCH_SECONDS` of work each). A run that raises or diverges is a row with ``status = failed`` and its
one-line error; it does not stop the sweep. A run that the *cluster* failed (its worker died, the scheduler was
lost) is not recorded at all, so that resuming runs it again; the sweep then ends with :class:`SweepStopped`,
as it does when no worker is left for :data:`WORKER_WAIT` seconds. The local cluster is private (TLS, no HTTP
port): :mod:`uvms.sweep.cluster`.
"""

from __future__ import annotations

import io
import math
import os
import time
import uuid
from collections.abc import Callable, Iterator
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from uvms.errors import UvmsInputError
from uvms.model.schema import show
from uvms.sweep import cluster
from uvms.sweep.spec import Sweep, SweepRun, load_sweep
from uvms.sweep.store import RunStore, columns, format_line, one_line, parameter_columns, run_cells

QUANTILES = (0.05, 0.5, 0.95)
WORKERS_PER_CPU = 4
"""Most local workers per CPU (``--workers``): more only queue for the same cores."""
CONNECT_TIMEOUT = 20.0
"""Seconds to wait for an external scheduler to answer."""
WORKER_WAIT = 120.0
"""Seconds to wait for a worker: before the first run on an external scheduler, and whenever none is left
during a sweep (then :class:`SweepStopped`)."""
POLL = 1.0
"""Seconds between checks that the cluster still has workers while no run finishes."""
THREADS_PER_PROCESS = 1
"""Worker threads per local worker process: ``--workers N`` starts N single-threaded processes. A process that
dies (a crash in compiled code, the out-of-memory killer) loses only its own batches in flight; one process
with two threads was not faster on the 2-core machine (``docs/sweeps.md``, "Performance")."""
BATCH_THREADS = 1
"""Threads of :func:`uvms.sim.batch.run_plans` in one batch: each worker thread runs its own batch, so that one
batch's Python work (reading scenarios, metrics) overlaps another's compiled loops."""
BATCH_SECONDS = 1.0
"""Wall time of work aimed at by one batch (per thread of the batch)."""
MAX_BATCH = 64
"""Most runs in one batch."""


def run_task(task: dict[str, Any]) -> dict[str, Any]:
    """Simulate one run on a worker: ``task`` holds the scenario ``data``, ``base_dir``, ``source`` and the
    ``metrics`` to compute; returns ``{status, error, metrics, wall_time_s}`` (never raises)."""
    from uvms.sim.scenario import run_scenario

    start = time.perf_counter()
    try:
        outcome = _outcome(run_scenario(_scenario(task)), task["metrics"])
    except Exception as exc:  # noqa: BLE001 - recorded in the row, never fatal to the sweep
        outcome = _failed(exc)
    outcome["wall_time_s"] = time.perf_counter() - start
    return outcome


def run_batch(tasks: list[dict[str, Any]], per_run: Callable[[dict[str, Any]], dict[str, Any]] | None = None,
              threads: int = BATCH_THREADS) -> list[dict[str, Any]]:
    """Run a batch of runs on a worker and return one outcome per task, in order, each what :func:`run_task`
    returns for it (the same numbers: :func:`uvms.sim.batch.run_plans` gives what ``simulate`` gives); never
    raises for a run's own failure.

    Each task is prepared (:func:`uvms.sim.scenario.plan_scenario`; a run whose preparation raises is a
    ``failed`` outcome), then the compilable plans (:func:`uvms.sim.compiled_loop.compilable`) run together in
    ``threads`` threads, and any other run through :func:`run_task`. Should the batch runner raise, every run of
    the batch runs through :func:`run_task`, so that only the run at fault fails. A run's ``wall_time_s`` is
    its own: preparation, loop and metrics.

    Args:
        tasks: as :func:`run_task`'s.
        per_run: a stand-in for :func:`run_task` run on every task in turn (the tests give one that fails the
            cluster); ``None`` or :func:`run_task`: the batch runner.
        threads: threads of the batch runner.
    """
    if per_run is not None and per_run is not run_task:
        return [per_run(task) for task in tasks]
    from uvms.sim.batch import run_plans
    from uvms.sim.compiled_loop import compilable
    from uvms.sim.scenario import plan_scenario

    outcomes: list[dict[str, Any] | None] = [None] * len(tasks)
    plans: dict[int, Any] = {}
    spent: dict[int, float] = {}
    for k, task in enumerate(tasks):
        start = time.perf_counter()
        try:
            plan = plan_scenario(_scenario(task))
            batched = compilable(plan)
        except Exception as exc:  # noqa: BLE001 - recorded in the row, never fatal to the sweep
            outcomes[k] = {**_failed(exc), "wall_time_s": time.perf_counter() - start}
            continue
        if batched:
            plans[k], spent[k] = plan, time.perf_counter() - start
        else:
            outcomes[k] = run_task(task)
    if plans:
        try:
            results = run_plans(list(plans.values()), threads=threads)
        except Exception:  # noqa: BLE001 - each run on its own: the one at fault fails alone
            results = None
        for k, result in zip(plans, results or [None] * len(plans)):
            if result is None:
                outcomes[k] = run_task(tasks[k])
                continue
            start = time.perf_counter()
            try:
                outcome = _outcome(result, tasks[k]["metrics"])
            except Exception as exc:  # noqa: BLE001 - recorded in the row, never fatal to the sweep
                outcome = _failed(exc)
            loop = float(result.metadata.get("wall_time_s", 0.0))
            outcome["wall_time_s"] = spent[k] + loop + time.perf_counter() - start
            outcomes[k] = outcome
    return outcomes


def _scenario(task: dict[str, Any]):
    from uvms.sim.scenario import scenario_from_data

    return scenario_from_data(task["data"], source=task["source"], base_dir=task["base_dir"])


def _outcome(result, metrics: list[str]) -> dict[str, Any]:
    """A finished run's outcome (without its wall time): ``failed`` with the divergence message, else ``ok``
    with its metrics."""
    from uvms.sweep.metrics import compute_metrics

    if not result.complete:
        return {"status": "failed", "error": result.message, "metrics": {}}
    return {"status": "ok", "error": "", "metrics": compute_metrics(result, metrics)}


def _failed(exc: Exception) -> dict[str, Any]:
    return {"status": "failed", "error": _describe(exc), "metrics": {}}


_TASK = run_task
"""The function that runs one task on a worker, passed to :func:`run_batch` (tests replace it to simulate a
cluster failure)."""


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
    """Import uvms and load (or compile) the kernels on a worker: each task shortened to three control periods,
    run as a batch (:func:`run_batch`) under the cache folder's :func:`uvms._cache.compile_lock`, so that the
    workers of one machine pay a compile once, not once each; returns how many ran."""
    short = []
    for task in tasks:
        data = dict(task["data"])
        controller = data.get("controller")
        period = controller.get("period", 0.01) if isinstance(controller, dict) else None
        step = data.get("step", 0.001)
        try:
            data["duration"] = 3 * max(float(period or 0.0), float(step))
        except (TypeError, ValueError):  # the real runs report any problem
            continue
        short.append({**task, "data": data})
    from uvms._cache import compile_lock

    try:
        with compile_lock():            # the workers of one machine compile once, in turn (docs/sweeps.md)
            return len(run_batch(short))
    except Exception:  # noqa: BLE001 - the real runs report any problem
        return 0


class BatchSizer:
    """How many runs the client puts in the next batch: one per batch thread until a run has finished, then
    about :data:`BATCH_SECONDS` of work from the mean wall time of the runs so far, at most :data:`MAX_BATCH`,
    and at most an equal share of the runs left over the ``slots`` batches in flight (so that the last batches
    are small and the workers finish together)."""

    def __init__(self, threads: int = BATCH_THREADS) -> None:
        self.threads = max(1, int(threads))
        self.seconds = 0.0
        self.runs = 0

    def record(self, outcome: dict[str, Any]) -> None:
        """Count a finished run's ``wall_time_s``."""
        wall = outcome.get("wall_time_s")
        if isinstance(wall, (int, float)) and math.isfinite(wall) and wall >= 0:
            self.seconds += float(wall)
            self.runs += 1

    def size(self, left: int, slots: int) -> int:
        """Runs of the next batch, with ``left`` runs not yet submitted and ``slots`` batches in flight at most."""
        if self.runs:
            per_run = max(self.seconds / self.runs, 1e-6) / self.threads  # a batch's runs share its threads
            aim = min(MAX_BATCH, max(1, int(BATCH_SECONDS / per_run)))
        else:
            aim = self.threads
        return max(1, min(aim, math.ceil(left / max(1, slots))))


class SweepStopped(RuntimeError):
    """The sweep stopped, or ended, with runs left unrecorded because its Dask cluster failed: no worker left
    (after :data:`WORKER_WAIT` seconds), the scheduler lost, or runs lost with their worker.
    Nothing of a run's own making raises it: those runs are ``failed`` rows. Rerunning the same sweep into the
    same folder runs what is missing.

    Attributes:
        reason: what happened (one line).
        done: runs recorded (this invocation and earlier ones).
        total: runs in the sweep.
    """

    def __init__(self, reason: str, done: int = 0, total: int = 0) -> None:
        super().__init__(reason, done, total)
        self.reason, self.done, self.total = reason, done, total

    def __str__(self) -> str:
        return f"{self.reason}; {self.done} of {self.total} runs recorded"


def run(sweep_or_path: Sweep | str | os.PathLike[str], *, out_dir: str | os.PathLike[str] | None = None,
        workers: int = 2, scheduler: str | None = None, security: Any = None, insecure: bool = False,
        progress: Callable[[int, int], None] | None = None):
    """Run every run of a sweep in parallel and return one row per run (a pandas DataFrame, in run order).

    Args:
        sweep_or_path: a :class:`Sweep`, or a sweep file path or bundled name.
        out_dir: record into this directory (``runs.csv`` ...; see :mod:`uvms.sweep.store`), skipping the
            runs already recorded there (resume); ``None``: keep the rows in memory only.
        workers: local worker threads, i.e. runs at once, when no ``scheduler`` is given, in processes of
            :data:`THREADS_PER_PROCESS` thread(s) each; the local cluster is private (TLS with credentials made
            for it, no HTTP port: :mod:`uvms.sweep.cluster`).
        scheduler: address of a running Dask scheduler (``tls://host:8786``) to use instead.
        security: ``distributed.security.Security`` for ``scheduler`` (default: the Dask configuration's
            ``distributed.comm.tls.*``); see :func:`uvms.sweep.cluster.security_from_files`.
        insecure: accept a plain ``tcp://`` scheduler on another machine.
        progress: ``progress(done, total)`` after each recorded run (and once at the start).

    Raises:
        UvmsInputError: invalid sweep, output directory or scheduler (one line).
        SweepStopped: the cluster failed (no worker left, scheduler lost, runs lost with their worker): the
            rows recorded so far stay, and the same call resumes.
        OSError: a file of the output directory could not be written (its name in ``filename``).
        KeyboardInterrupt: passed on after the current row is written and the workers are shut down.
    """
    from uvms._cache import announce_compile
    from uvms.sweep.cluster import check_scheduler

    sweep = sweep_or_path if isinstance(sweep_or_path, Sweep) else load_sweep(sweep_or_path)
    most = WORKERS_PER_CPU * (os.cpu_count() or 1)
    if scheduler is None and (isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= most):
        raise UvmsInputError(f"expected 1 to {most} local workers ({WORKERS_PER_CPU} per CPU), found "
                             f"{show(workers)}", path="--workers")
    if scheduler is not None:
        check_scheduler(scheduler, secured=security is not None, insecure=insecure)
    header = columns(sweep)
    store = RunStore.open(out_dir, sweep) if out_dir is not None else None
    try:
        rows: dict[str, list[str]] = dict(store.done) if store is not None else {}
        planned = {run.run_id for run in sweep.runs}
        todo = [run for run in sweep.runs if run.run_id not in rows]
        total = len(sweep.runs)
        done = len(planned & set(rows))
        if todo and scheduler is None:  # the local workers compile into this machine's cache: the CLI says so
            announce_compile()          # once, before a progress bar starts
        if progress is not None:
            progress(done, total)
        lost: dict[str, str] = {}
        if todo:
            try:
                with ExitStack() as connection:
                    try:
                        client = connection.enter_context(_connect(workers, scheduler, security))
                    except UvmsInputError:
                        if store is not None and store.created:  # nothing was run: leave no folder behind
                            store.close()
                            store.remove()
                            store = None
                        raise
                    for run, outcome in _execute(client, sweep, todo, lost):
                        cells = run_cells(sweep, run, outcome)
                        if store is not None:
                            store.append(cells)
                        rows[run.run_id] = cells
                        done += 1
                        if progress is not None:
                            progress(done, total)
            except SweepStopped as exc:
                exc.done, exc.total = done, total
                raise
        if lost:
            run_id, error = next(iter(lost.items()))
            raise SweepStopped(f"{len(lost)} run{'s' if len(lost) > 1 else ''} not recorded: the Dask cluster failed "
                               f"while running {'them' if len(lost) > 1 else 'it'} (e.g. {run_id}: "
                               f"{one_line(error, 200)})", done, total)
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


def _execute(client, sweep: Sweep, runs: list[SweepRun], lost: dict[str, str]
             ) -> Iterator[tuple[SweepRun, dict[str, Any]]]:
    """Submit the runs in batches (:func:`run_batch`, sized by :class:`BatchSizer`) in a sliding window of two
    per worker thread, and yield ``(run, outcome)`` for every run of a batch as soon as it returns.

    An outcome is what :func:`run_task` returns: the run's own result, ``ok`` or ``failed``, and final. A
    future that raises instead (``KilledWorker``, a lost connection, cancelled) says nothing about its runs:
    they go into ``lost`` (run_id -> error), are not yielded, and run again on resume.

    Raises:
        SweepStopped: no worker for :data:`WORKER_WAIT` seconds, or the scheduler lost.
    """
    from distributed import wait

    threads = _threads(client)
    first = {}
    for run, task in _tasks(sweep, runs):
        first.setdefault(run.controller, task)
    try:
        client.run(warm_up, list(first.values()))
    except Exception:  # noqa: BLE001 - a worker that cannot warm up reports through its runs
        pass
    token = uuid.uuid4().hex[:8]
    pending = _tasks(sweep, runs)
    left = [len(runs)]
    sizer = BatchSizer(BATCH_THREADS)
    by_future: dict[Any, list[SweepRun]] = {}

    def fill() -> None:
        slots = 2 * max(1, threads)
        while len(by_future) < slots and left[0]:
            batch = [next(pending) for _ in range(sizer.size(left[0], slots))]
            left[0] -= len(batch)
            key = f"uvms-sweep-{token}-{batch[0][0].run_id}" + (f"+{len(batch) - 1}" if len(batch) > 1 else "")
            try:
                future = client.submit(run_batch, [task for _, task in batch], _TASK, BATCH_THREADS, key=key,
                                       pure=False, retries=0)
            except Exception as exc:  # noqa: BLE001 - a client that lost its scheduler
                raise SweepStopped(_lost_scheduler(exc)) from None
            by_future[future] = [run for run, _ in batch]

    fill()
    idle_since: float | None = None
    try:
        while by_future:
            try:
                with client.as_current():
                    finished, _ = wait(list(by_future), timeout=POLL, return_when="FIRST_COMPLETED")
            except TimeoutError:
                threads = _threads(client)
                if threads:
                    idle_since = None
                    fill()
                elif idle_since is None:
                    idle_since = time.monotonic()
                elif time.monotonic() - idle_since > WORKER_WAIT:
                    raise SweepStopped(f"no Dask worker left (waited {WORKER_WAIT:g} s)") from None
                continue
            except Exception as exc:  # noqa: BLE001 - the client lost its scheduler
                raise SweepStopped(_lost_scheduler(exc)) from None
            idle_since = None
            for future in finished:
                batch = by_future.pop(future)
                try:
                    outcomes = future.result()
                except Exception as exc:  # noqa: BLE001 - the cluster failed, not the runs: not final
                    lost.update((run.run_id, f"{type(exc).__name__}: {exc}") for run in batch)
                    outcomes = []
                future.release()
                for run, outcome in zip(batch, outcomes):
                    sizer.record(outcome)
                    yield run, outcome
            if client.status != "running":
                raise SweepStopped(_lost_scheduler(None))
            fill()
    finally:
        if by_future:
            try:
                client.cancel(list(by_future), force=True)
            except Exception:  # noqa: BLE001 - shutting down anyway
                pass


def _threads(client) -> int:
    """Worker threads the scheduler has now."""
    try:
        return sum(client.nthreads().values())
    except Exception as exc:  # noqa: BLE001 - the client lost its scheduler
        raise SweepStopped(_lost_scheduler(exc)) from None


def _lost_scheduler(exc: BaseException | None) -> str:
    why = f": {one_line(f'{type(exc).__name__}: {exc}', 200)}" if exc is not None else ""
    return f"lost the connection to the Dask scheduler{why}"


def _connect(workers: int, scheduler: str | None, security: Any = None):
    """A Dask client (a context manager): on a new private local cluster of ``workers`` threads (in processes
    of :data:`THREADS_PER_PROCESS` threads), or on the scheduler at ``scheduler``."""
    if scheduler is not None:
        return cluster.external_client(scheduler, security, connect_timeout=CONNECT_TIMEOUT,
                                       worker_wait=WORKER_WAIT)
    return cluster.local_cluster(workers, threads=THREADS_PER_PROCESS, preload=[__name__])


def runs_table(out_dir: str | os.PathLike[str]):
    """A sweep directory's ``runs.csv`` as a DataFrame (a partial last line, from a kill, is left out)."""
    import csv

    text = (Path(out_dir) / "runs.csv").read_text(encoding="utf-8")
    rows = list(csv.reader(io.StringIO(text[: text.rfind("\n") + 1], newline="")))
    if not rows:
        raise UvmsInputError("empty file (no header)", str(Path(out_dir) / "runs.csv"))
    return _frame(rows[0], rows[1:])
