"""``uvms run SCENARIO [-o DIR]``: simulate a scenario file and save its results.

Writes ``DIR/result.csv`` (time series), ``DIR/result.json`` (summary and metadata), ``DIR/result.<sensor>.csv``
for each simulated sensor (``docs/sensors.md``) and ``DIR/scenario.yaml`` (the scenario file, verbatim); the
closing line names every file written. Nothing is written before the scenario is valid; the results go to a hidden
temporary sibling of ``DIR`` that is renamed into place at the end, so an interrupted run never leaves a
half-written ``DIR``. A diverging run still saves what it computed (``"complete": false``) and exits 3; a
complete but unhealthy run (tumbled, thrusters saturated: :mod:`uvms.sim.health`) exits 0 with one warning line.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

NAME = "run"
HELP = ("simulate a scenario file (or a bundled scenario name) and save result.csv, result.json, each sensor's "
        "result.<sensor>.csv and scenario.yaml")

PROGRESS_AFTER = 1.0
"""Wall time [s] after which a progress bar appears (on a terminal only)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms run``."""
    parser.add_argument("scenario", metavar="SCENARIO",
                        help="scenario YAML file, or a bundled scenario name (e.g. paper_case2_released)")
    parser.add_argument("-o", "--output", metavar="DIR", default=None,
                        help="output directory (default: runs/<scenario name>); a previous run there is replaced, "
                             "a folder holding files uvms did not write is refused")
    parser.add_argument("--force", action="store_true",
                        help="replace an earlier run's directory (one with a .uvms-output.json) even if files "
                             "were added to it or changed since (they are deleted); a folder uvms never wrote is "
                             "refused even then")


def run(args: argparse.Namespace) -> int:
    """Validate, simulate, save atomically, summarise; 0 on success, 3 when the simulation diverged."""
    from rich.console import Console

    from uvms.output import atomic_write_text, check_output_folder, staged_directory
    from uvms.sim.scenario import load_scenario, run_scenario

    scenario = load_scenario(args.scenario)
    if args.output == "":
        from uvms.errors import UvmsInputError

        raise UvmsInputError("expected a folder name, found an empty string", None, "--output")
    out = Path(args.output) if args.output is not None else Path("runs") / scenario.name
    check_output_folder(out, "--output", kind="replaced folder", force=args.force)
    from uvms.control.smc import warn_controller_b_bounds

    warn_controller_b_bounds(scenario.next_controller())   # b bounds that miss the plant: one warning line
    progress = _Progress(scenario.name)
    try:
        result = run_scenario(scenario, progress=progress)
    finally:
        progress.close()

    if scenario.source:           # where a relative model path resolves ('uvms animate' reads it back)
        result.metadata["scenario_folder"] = str(Path(scenario.source).resolve().parent)
    with staged_directory(out, kind="run", force=args.force) as tmp:
        result.save(tmp)
        atomic_write_text(tmp / "scenario.yaml", scenario.text)

    console = Console()
    console.print(_summary_table(result, scenario.name))
    state = "saved" if result.complete else "saved (incomplete run)"
    files = ["result.csv", "result.json", *(f"result.{name}.csv" for name in result.sensors), "scenario.yaml"]
    console.print(f"results {state} to {out}/ ({', '.join(files)})", highlight=False, soft_wrap=True)
    if not result.complete:
        print(f"uvms: error: {result.message}", file=sys.stderr)
        return 3
    health = result.summary()["health"]
    if health and not health["healthy"]:          # still a complete run: say it once, exit 0
        print(f"uvms: warning: {health['warning']}", file=sys.stderr)
    return 0


class _Progress:
    """A rich progress bar on stderr that appears once a run has taken :data:`PROGRESS_AFTER` seconds."""

    def __init__(self, label: str) -> None:
        from rich.console import Console

        self.label = label
        self.console = Console(stderr=True)
        self.start = time.perf_counter()
        self.bar: Any = None
        self.task: Any = None

    def __call__(self, t: float, duration: float) -> None:
        if self.bar is None:
            if not self.console.is_terminal or time.perf_counter() - self.start < PROGRESS_AFTER:
                return
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

            self.bar = Progress(TextColumn("{task.description}"), BarColumn(),
                                TextColumn("{task.completed:.2f} / {task.total:g} s"), TimeElapsedColumn(),
                                TimeRemainingColumn(), console=self.console, transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.label, total=duration)
        self.bar.update(self.task, completed=t)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


def _summary_table(result, name: str):
    """Peaks, final state and wall time of a run as a rich table."""
    import numpy as np
    from rich.table import Table

    s = result.summary()
    fin = s["final"]
    meta = s["metadata"]

    def vec(values, scale=1.0, fmt="{:+.4f}"):
        return "[" + ", ".join(fmt.format(v * scale) for v in values) + "]" if len(values) else "-"

    deg = 180.0 / np.pi
    table = Table(title=f"{name}: {'complete' if result.complete else 'INCOMPLETE'}", show_header=True)
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_column("unit")
    rows = [
        ("simulated time", f"{fin['time_s']:.4g} / {meta.get('duration_s', float('nan')):.4g}", "s"),
        ("integrator, step", f"{meta.get('integrator')}, {meta.get('step_s', float('nan')):g}", "s"),
        ("wall time", f"{meta.get('wall_time_s', float('nan')):.3g}", "s"),
        ("samples", f"{len(result.time)}", ""),
        ("peak |vehicle displacement| x, y, z", vec(s["peak_abs_position_m"]), "m"),
        ("peak |Euler change| roll, pitch, yaw", vec(s["peak_abs_euler_rad"], deg, "{:.3f}"), "deg"),
        ("peak body-frame XY error", f"{s['peak_body_error_xy_m']:.4g}", "m"),
        ("final vehicle position", vec(fin["position_m"]), "m"),
        ("final Euler angles", vec(fin["euler_rad"], deg, "{:+.3f}"), "deg"),
        ("final joint angles", vec(fin["q_rad"]), "rad"),
        ("final end effector", vec(fin["end_effector_m"]), "m"),
    ]
    health = s.get("health")
    if health:
        rows.append(("largest |roll|, |pitch|", vec([health["max_abs_roll_rad"], health["max_abs_pitch_rad"]], deg,
                                                     "{:.3f}"), "deg"))
        if health["saturated_fraction"]:
            worst = max(health["saturated_fraction"].items(), key=lambda item: item[1])
            rows.append((f"most saturated thruster ({worst[0]})", f"{worst[1] * 100:.1f}", "% of time"))
            rows.append(("peak wrench not produced (force, moment)",
                         f"{health['peak_unachieved_force_N']:.3g}, {health['peak_unachieved_moment_Nm']:.3g}",
                         "N, N m"))
        rows.append(("run health", "healthy" if health["healthy"] else "UNHEALTHY", ""))
    for key, value in sorted(s["peak_abs_signal"].items()):
        if key in ("command_X", "command_Y", "command_Z", "command_K", "command_M", "command_N"):
            rows.append((f"peak |{key}|", f"{value:.4g}", "N m" if key[-1] in "KMN" else "N"))
    for row in rows:
        table.add_row(*row)
    return table
