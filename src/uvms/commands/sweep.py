"""``uvms sweep SWEEP [-o DIR] [--workers N | --scheduler ADDRESS [--tls-ca-file F --tls-cert F --tls-key F]]``:
run a parameter sweep in parallel.

Each finished run is appended to ``DIR/runs.csv`` as it completes; rerunning the same command resumes (runs
already recorded are skipped, runs lost with a worker or the scheduler are run again). At the end
``DIR/summary.csv`` is written and the 5/50/95 % quantiles of each metric are printed per controller. Ctrl-C
stops cleanly (exit 130), also while the cluster starts: the rows written so far stay, the workers are shut
down, and the same command resumes. A cluster that fails (no worker left, scheduler lost) stops the sweep with
one line and exit code 1. ``docs/sweeps.md`` documents the sweep file and the cluster's security.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

NAME = "sweep"
HELP = "run a parameter sweep (a sweep YAML file or bundled name) in parallel with Dask; resumable"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms sweep``."""
    parser.add_argument("sweep", metavar="SWEEP", help="sweep YAML file, or a bundled sweep name (paper_model_error)")
    parser.add_argument("-o", "--output", metavar="DIR", default=None,
                        help="output directory (default: sweeps/<sweep name>); an earlier run of the same sweep "
                             "there is resumed")
    parser.add_argument("--workers", metavar="N", type=int, default=None,
                        help="local worker processes, one thread each (default: the number of CPUs; at most 4 per CPU)")
    parser.add_argument("--scheduler", metavar="ADDRESS", default=None,
                        help="use the Dask scheduler at ADDRESS (e.g. tls://10.0.0.5:8786) and its workers "
                             "instead of a private local cluster")
    parser.add_argument("--tls-ca-file", metavar="FILE", default=None,
                        help="with --scheduler: CA certificate (PEM) that signed the scheduler's certificate "
                             "(default: the Dask configuration, distributed.comm.tls)")
    parser.add_argument("--tls-cert", metavar="FILE", default=None,
                        help="with --scheduler: this client's certificate (PEM)")
    parser.add_argument("--tls-key", metavar="FILE", default=None,
                        help="with --scheduler: this client's private key (PEM)")
    parser.add_argument("--insecure", action="store_true",
                        help="with --scheduler: accept plain tcp:// to another machine (no authentication, no "
                             "encryption: anyone who reaches that scheduler runs code on its workers)")


def run(args: argparse.Namespace) -> int:
    """Validate, run (resuming), summarise; 0 when every run is recorded, 130 on Ctrl-C."""
    from rich.console import Console

    from uvms.errors import UvmsInputError
    from uvms.output import check_output_folder
    from uvms.sweep.store import one_line
    from uvms.sweep import SweepStopped, load_sweep, summarize
    from uvms.sweep import run as run_sweep
    from uvms.sweep.cluster import check_scheduler, security_from_files

    if args.scheduler is not None and args.workers is not None:
        raise UvmsInputError("has no effect with --scheduler (the scheduler's workers run the sweep)",
                             path="--workers")
    security, warning = None, None
    if args.scheduler is None:
        for option, value in (("--tls-ca-file", args.tls_ca_file), ("--tls-cert", args.tls_cert),
                              ("--tls-key", args.tls_key), ("--insecure", args.insecure or None)):
            if value is not None:
                raise UvmsInputError("only applies with --scheduler (the local cluster makes its own credentials)",
                                     path=option)
    else:
        security = security_from_files(args.tls_ca_file, args.tls_cert, args.tls_key)
        warning = check_scheduler(args.scheduler, secured=security is not None, insecure=args.insecure)
    workers = args.workers if args.workers is not None else _cpu_count()
    sweep = load_sweep(args.sweep)
    out = Path(args.output) if args.output else Path("sweeps") / sweep.name
    check_output_folder(out, "--output", kind="folder")

    if warning is not None:
        print(f"uvms: warning: {warning}", file=sys.stderr)
    bar = _Progress(sweep.name, "scheduler " + args.scheduler if args.scheduler else f"{workers} local workers")
    start = time.perf_counter()
    try:
        rows = run_sweep(sweep, out_dir=out, workers=workers, scheduler=args.scheduler, security=security,
                         insecure=args.insecure, progress=bar)
    except KeyboardInterrupt:
        bar.close()
        print(f"uvms: interrupted: {bar.done} of {bar.total} runs recorded in {out / 'runs.csv'}; run the same "
              "command again to resume", file=sys.stderr)
        return 130
    except SweepStopped as exc:
        bar.close()
        print(f"uvms: error: {exc.reason}; {exc.done} of {exc.total} runs recorded in {out / 'runs.csv'}; run the "
              "same command again to resume", file=sys.stderr)
        return 1
    finally:
        bar.close()
    wall = time.perf_counter() - start

    console = Console()
    if not console.is_terminal:
        console = Console(width=120)
    summary = summarize(rows, metrics=sweep.metrics)
    console.print(_quantile_table(summary, sweep.name))
    failed = int((rows["status"] != "ok").sum())
    new = bar.total - bar.skipped
    console.print(f"{len(rows)} runs recorded in {out / 'runs.csv'} ({new} new in {wall:.1f} s, {bar.skipped} from "
                  f"before, {failed} failed); summary in {out / 'summary.csv'}", highlight=False, soft_wrap=True)
    if failed:
        example = rows.loc[rows["status"] != "ok"].iloc[0]
        print(f"uvms: warning: {failed} of {len(rows)} runs failed (status=failed in runs.csv), e.g. "
              f"{example['run_id']}: {one_line(example['error'], 300)}", file=sys.stderr)
    ok = rows[rows["status"] == "ok"]
    if "healthy" in sweep.metrics and len(ok):
        unhealthy = ok[ok["healthy"] == 0]
        if len(unhealthy):                          # complete runs that lost control (uvms.sim.health)
            print(f"uvms: warning: {len(unhealthy)} of {len(ok)} runs are unhealthy (healthy=0 in runs.csv: "
                  f"tumbled, saturated, off station or short of thrust), e.g. {unhealthy.iloc[0]['run_id']}",
                  file=sys.stderr)
    for metric in sweep.metrics:
        if len(ok) and ok[metric].isna().all():
            print(f"uvms: warning: metric {metric} is empty in every run: these runs record no such series",
                  file=sys.stderr)
    return 0


def _cpu_count() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


class _Progress:
    """A rich progress bar on stderr (on a terminal only); remembers the counts for the final message."""

    def __init__(self, label: str, where: str) -> None:
        from rich.console import Console

        self.label, self.where = label, where
        self.console = Console(stderr=True)
        self.bar = None
        self.task = None
        self.done = self.total = self.skipped = 0
        self._first = True

    def __call__(self, done: int, total: int) -> None:
        if self._first:
            self._first = False
            self.skipped = done
        self.done, self.total = done, total
        if not self.console.is_terminal:
            return
        if self.bar is None:
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            self.bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                TimeElapsedColumn(), TimeRemainingColumn(), console=self.console, transient=True)
            self.bar.start()
            self.task = self.bar.add_task(f"{self.label} ({self.where})", total=total, completed=done)
        self.bar.update(self.task, completed=done)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
            self.bar = None


def _quantile_table(summary, name: str):
    """Metric quantiles (5/50/95 %) per controller as a rich table."""
    from rich import box
    from rich.table import Table

    table = Table(title=f"{name}: quantiles over the ok runs", box=box.SIMPLE, pad_edge=False)
    for column, justify in (("metric", "left"), ("controller", "left"), ("ok/runs", "right"), ("5 %", "right"),
                            ("50 %", "right"), ("95 %", "right")):
        table.add_column(column, justify=justify, no_wrap=True)
    for metric, group in summary.groupby("metric", sort=False):
        for k, (_, row) in enumerate(group.iterrows()):
            table.add_row(metric if k == 0 else "", str(row["controller"]), f"{row['ok']}/{row['runs']}",
                          *(f"{row[q]:.3g}" for q in ("q05", "q50", "q95")), end_section=k == len(group) - 1)
    return table
