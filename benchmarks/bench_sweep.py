"""Wall time of the bundled Monte-Carlo sweep: 200 paper-scenario runs (10 s each, 1 ms RK4), ``smc-ab`` and
``smc-vehicle`` on the same 100 draws of the controller's model error (0.3-1.7) and a random current.

Run ``python benchmarks/bench_sweep.py [--workers 2] [--draws 100] [--duration 10] [--json FILE]``;
``--draws 500`` is issue #14's figure (1000 runs). ``--draws`` and ``--duration`` shorten the sweep for a quick
look; ``--threads-per-process T`` runs the ``--workers`` threads in processes of T threads each (to compare
layouts; default: uvms's). The kernels are compiled (or loaded from the disk cache) in this process first, so the
figure is the sweep itself: cluster start-up, worker import and cache loading included, first-time compilation
excluded (reported separately as ``warm_up_s``). Workers run batches of runs through the batch runner
(:func:`uvms.sweep.execute.run_batch`). Prints the total wall time, the per-run wall times (mean, max), runs per
second and the load average before and after.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import platform
import sys
import tempfile
import time


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    parser.add_argument("--draws", type=int, default=None, help="random draws (default: the file's 100)")
    parser.add_argument("--duration", type=float, default=None, help="simulated seconds per run (default 10)")
    parser.add_argument("--threads-per-process", type=int, default=None,
                        help="worker threads per local process (default: uvms's THREADS_PER_PROCESS)")
    parser.add_argument("--json", metavar="FILE", default=None, help="also write the figures as JSON")
    args = parser.parse_args(argv)

    import yaml

    from uvms.model.load import read_yaml
    from uvms.sweep import execute
    from uvms.sim.scenario import run_scenario, scenario_from_data
    from uvms.sweep import run, summarize, sweep_from_data
    from uvms.sweep.spec import resolve_sweep_path

    path = resolve_sweep_path("paper_model_error")
    data = read_yaml(path)
    if args.draws is not None:
        data["runs"] = args.draws
    if args.duration is not None:
        data.setdefault("parameters", {})["duration"] = {"value": args.duration}
    sweep = sweep_from_data(data, source=str(path), base_dir=path.parent, text=yaml.safe_dump(data))

    start = time.perf_counter()
    for run_ in sweep.runs[:2]:  # compile or load the kernels of both controllers here, once
        warm = copy.deepcopy(sweep.scenario_data(run_))
        warm["duration"] = 0.03
        run_scenario(scenario_from_data(warm, base_dir=sweep.base_dir))
    warm_up = time.perf_counter() - start

    if args.threads_per_process is not None:
        execute.THREADS_PER_PROCESS = args.threads_per_process
    threads_per_process = getattr(execute, "THREADS_PER_PROCESS", 1)
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory(prefix="bench_sweep.") as out:
        start = time.perf_counter()
        rows = run(sweep, out_dir=os.path.join(out, "sweep"), workers=args.workers)
        wall = time.perf_counter() - start
    ok = rows[rows["status"] == "ok"]
    figures = {
        "runs": len(rows), "ok": len(ok), "workers": args.workers, "threads_per_process": threads_per_process,
        "cpus": os.cpu_count(),
        "simulated_s_per_run": sweep.base.spec.duration if args.duration is None else args.duration,
        "wall_time_s": wall, "runs_per_s": len(rows) / wall, "warm_up_s": warm_up,
        "run_wall_mean_s": float(rows["wall_time_s"].mean()), "run_wall_max_s": float(rows["wall_time_s"].max()),
        "python": sys.version.split()[0], "machine": platform.machine(), "load_average_before": load_before,
        "load_average": os.getloadavg(),
    }
    print(f"{len(rows)} runs ({len(ok)} ok) with {args.workers} workers ({threads_per_process} per process): "
          f"{wall:.1f} s wall "
          f"({figures['runs_per_s']:.2f} runs/s; per run {figures['run_wall_mean_s']:.2f} s mean, "
          f"{figures['run_wall_max_s']:.2f} s max; kernel warm-up here {warm_up:.1f} s; "
          f"load average {load_before[0]:.2f} before, {figures['load_average'][0]:.2f} after)")
    print(summarize(rows).to_string(index=False, float_format=lambda x: f"{x:.4g}"))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(figures, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
