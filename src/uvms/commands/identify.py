"""``uvms identify MODEL LOG... --fit P,P... [--held-out LOG...] [-o FILE]``: fit model parameters to logs.

Each log is replayed as ``uvms replay`` does (vehicle free from the log's start, joints following the log);
the chosen parameters (``docs/logs.md``, "Identification": ``buoyancy``, ``cob.x``, ``damping.linear.pitch``
...) are fitted by least squares on the simulation error of the chosen signals, all trials simulated in
parallel. Held-out logs are scored before and after, never fitted. Writes the fitted model as a model file
(default ``<model>_fit.yaml``) whose ``identified:`` block holds the values and the record of the fit
(uncertainties, correlations, bounds reached, scores per log); nothing is written when a log or an option is
bad.
"""

from __future__ import annotations

import argparse
from pathlib import Path

NAME = "identify"
HELP = ("fit model parameters (buoyancy, its centre, damping, added mass) to logged trials by least squares on the "
        "simulation error; writes the fitted model file")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms identify``."""
    parser.add_argument("model", metavar="MODEL", help="model YAML file or bundled model name")
    parser.add_argument("logs", metavar="LOG", nargs="+",
                        help="log description files or bundled logs/patterns (e.g. 'hinsdale_2023/traj0*')")
    parser.add_argument("--fit", required=True, metavar="P,P,...",
                        help="parameters to fit, comma-separated, each NAME or NAME=LOWER:UPPER (e.g. "
                             "buoyancy,cob.x,cob.z=-0.05:0.05,damping.linear.pitch,point_load:foam.fluid_mass,"
                             "disturbance.surge=-5:5; docs/logs.md, Identification)")
    parser.add_argument("--held-out", nargs="+", default=[], metavar="LOG",
                        help="logs scored before and after, never fitted")
    parser.add_argument("--exclude", nargs="+", default=[], metavar="LOG",
                        help="logs (names or patterns) to leave out of the LOG list (e.g. trials whose motion capture "
                             "lost track)")
    parser.add_argument("--signals", default="roll,pitch", metavar="S,S",
                        help="compared signals: roll, pitch, yaw, depth, x, y (default roll,pitch)")
    parser.add_argument("--max-evaluations", type=int, default=30, metavar="N",
                        help="most residual evaluations, each simulating every fitted log (default 30)")
    parser.add_argument("--step", type=float, default=None, metavar="SECONDS", help="RK4 step (default 0.002 s)")
    parser.add_argument("--threads", type=int, default=None, help="simulation threads (default: the cores)")
    parser.add_argument("-o", "--output", metavar="FILE", default=None,
                        help="the fitted model file (default <model>_fit.yaml in the working folder)")
    parser.add_argument("--force", action="store_true",
                        help="let the default output replace a file that uvms did not write")


def _logs(names) -> list[Path]:
    from uvms.logs.bundled import resolve_logs

    out: list[Path] = []
    for name in names:
        out += resolve_logs(name)
    return out


def run(args: argparse.Namespace) -> int:
    """Check everything, build the experiments, fit, write the model file, print the tables."""
    from uvms.errors import UvmsInputError
    from uvms.identify import identify
    from uvms.identify.fit import parse_parameter
    from uvms.identify.write import write_fitted_model
    from uvms.logs import Log
    from uvms.logs.bundled import log_name
    from uvms.model.load import load_model
    from uvms.model.parameters import parameter
    from uvms.output import check_file_output, default_file_name
    from uvms.replays import plan

    from uvms import checks

    for flag, value in (("--max-evaluations", args.max_evaluations), ("--threads", args.threads)):
        if value is not None and value < 1:
            raise UvmsInputError(f"expected a whole number >= 1, got {value}", None, flag)
    if args.step is not None:
        checks.number(args.step, "--step", positive=True, unit="s")
    model = load_model(args.model)
    fit_names = [p for p in (s.strip() for s in args.fit.split(",")) if p]
    for text in fit_names:
        parameter(model, parse_parameter(text)[0], "--fit")
    signals = tuple(s.strip() for s in args.signals.split(",") if s.strip())
    if args.output == "":
        raise UvmsInputError("expected a file name, found an empty string", None, "--output")
    output = Path(args.output) if args.output else Path(default_file_name([f"{model.name}_fit"], ".yaml"))
    check_file_output(output, "--output", named=args.output is not None, force=args.force)
    excluded = {p.resolve() for p in _logs(args.exclude)}
    fitted_paths = [p for p in _logs(args.logs) if p.resolve() not in excluded]
    held_paths = _logs(args.held_out)
    if not fitted_paths:
        raise UvmsInputError("no log left to fit after --exclude", None, "LOG")
    both = {p.resolve() for p in fitted_paths} & {p.resolve() for p in held_paths}
    if both:
        raise UvmsInputError("is both fitted and held out", str(sorted(both)[0]), "--held-out")
    step = {"step": args.step} if args.step is not None else {}
    logs = [Log.load(p) for p in fitted_paths + held_paths]
    experiments = [plan(model, log, **step) for log in logs[:len(fitted_paths)]]
    held_out = [plan(model, log, **step) for log in logs[len(fitted_paths):]]
    with _Progress(args.max_evaluations) as progress:           # fitted in the logs' frame, reported in the model's
        result = identify(model, experiments, fit_names, held_out=held_out, signals=signals,
                          max_evaluations=args.max_evaluations, threads=args.threads, progress=progress)
    write_fitted_model(result, model.source, output,
                       logs=[log_name(p) for p in fitted_paths + held_paths], named=args.output is not None,
                       force=args.force)
    _print(result, output)
    return 0


class _Progress:
    """A rich progress bar of the fit's evaluations on stderr (a terminal only)."""

    def __init__(self, total: int) -> None:
        from rich.console import Console

        self.total, self.console, self.bar, self.task = total, Console(stderr=True), None, None

    def __enter__(self):
        if self.console.is_terminal:
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

            self.bar = Progress(TextColumn("fitting"), BarColumn(), TextColumn("{task.completed}/{task.total} "
                                "evaluations, cost {task.fields[cost]}"), TimeElapsedColumn(),
                                console=self.console, transient=True)
            self.bar.start()
            self.task = self.bar.add_task("fit", total=self.total, cost="-")
        return self

    def __call__(self, evaluations: int, cost: float) -> None:
        if self.bar is not None:
            self.bar.update(self.task, completed=min(evaluations, self.total), cost=f"{cost:.4g}")

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.stop()


def _print(result, output: Path) -> None:
    import sys

    from rich.console import Console
    from rich.table import Table

    console = Console()
    if not console.is_terminal:                 # a log file: wide enough for parameter names and bounds
        console = Console(width=140)
    table = Table(title=f"identified ({result.evaluations} evaluations, {result.wall_time_s:.0f} s): "
                        f"{'converged' if result.converged else 'NOT CONVERGED, best point kept'}")
    for column in ("parameter", "initial", "fitted", "std", "unit", "bounds"):
        table.add_column(column, justify="left" if column in ("parameter", "unit") else "right")
    for row in result.table().itertuples():
        table.add_row(row.parameter + (" (at bound)" if row.at_bound else ""), f"{row.initial:.5g}",
                      f"{row.value:.5g}", f"{row.std:.2g}", row.unit, f"[{row.lower:.4g}, {row.upper:.4g}]")
    console.print(table)
    scores = Table(title="RMSE per log, before -> after")
    scores.add_column("log")
    scores.add_column("role")
    for s in result.signals:
        scores.add_column(s, justify="right")
    for row in result.scores:
        cells = []
        for s in result.signals:
            unit = "deg" if s in ("roll", "pitch", "yaw") else "m"
            cells.append(f"{row[f'{s}_rmse_{unit}_before']:.3g} -> {row[f'{s}_rmse_{unit}_after']:.3g} {unit}")
        scores.add_row(row["name"], row["role"], *cells)
    console.print(scores)
    console.print(f"fitted model written to {output}", highlight=False, soft_wrap=True)
    if not result.converged:
        print(f"uvms: warning: the fit did not converge ({result.message}); the best point found was kept",
              file=sys.stderr)
    if result.at_bound:
        print(f"uvms: warning: stopped at a bound: {', '.join(result.at_bound)} (widen it with NAME=LOWER:UPPER)",
              file=sys.stderr)
