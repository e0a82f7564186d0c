"""Parameter sweeps: many runs of one scenario with parameters gridded or drawn at random, run in parallel
with Dask, recorded row by row (resumable), summarised per controller.

    sweep = load_sweep("paper_model_error")           # or a path; validated, every run listed
    rows = run(sweep, out_dir="sweeps/demo", workers=2)   # -> pandas DataFrame, one row per run
    table = summarize(rows)                           # 5/50/95 % quantiles per controller and metric

``docs/sweeps.md`` documents the sweep file, the output directory and resuming.
"""

from __future__ import annotations

from uvms.sweep.execute import SweepStopped, run, run_batch, run_task, runs_table, summarize
from uvms.sweep.metrics import check_metric, compute_metrics, default_metrics
from uvms.sweep.spec import Sweep, SweepRun, SweepSpec, bundled_sweeps, load_sweep, sweep_from_data

__all__ = ["Sweep", "SweepRun", "SweepSpec", "SweepStopped", "bundled_sweeps", "check_metric", "compute_metrics", "default_metrics",
           "load_sweep", "run", "run_batch", "run_task", "runs_table", "summarize", "sweep_from_data"]
