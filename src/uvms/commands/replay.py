"""``uvms replay MODEL LOG [-o DIR] [--animate]``: simulate a logged trial and compare it with the log.

The vehicle starts from the log's pose and velocities and moves freely; the joints follow the logged angles
exactly (prescribed motion). Writes ``DIR/result.csv`` and ``DIR/result.json`` (the run, as ``uvms run``
writes it, in the log's frame convention), ``DIR/comparison.json`` (RMSE of roll, pitch, yaw change and depth
change against the log, beside the no-skill score of the start held), ``DIR/comparison.png`` (log and
simulation per signal) and, with ``--animate``, ``DIR/animation.html``: the simulated robot and the logged
motion (faint grey) in one 3-D scene on one time slider. Nothing is written before the model and the log are
valid; the folder is written whole or not at all (``docs/logs.md``, "Replaying").
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

NAME = "replay"
HELP = ("simulate a logged trial (vehicle free from the log's start, joints following the log) and compare it with "
        "the log: result files, comparison.json, comparison.png")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms replay``."""
    parser.add_argument("model", metavar="MODEL", help="model YAML/URDF file or bundled model name "
                        "(e.g. hinsdale_bluerov2_alpha5)")
    parser.add_argument("log", metavar="LOG", help="log description YAML (docs/logs.md) or a bundled log "
                        "(e.g. hinsdale_2023/traj_alt_001-0)")
    parser.add_argument("-o", "--output", metavar="DIR", default=None,
                        help="output folder (default: replays/<trial>); an earlier replay there is replaced, a "
                             "folder holding files uvms did not write is refused")
    parser.add_argument("--step", type=float, default=None, metavar="SECONDS",
                        help="RK4 step (default 0.002 s)")
    parser.add_argument("--grid", type=float, default=None, metavar="SECONDS",
                        help="spacing of the comparison (default 0.04 s)")
    parser.add_argument("--animate", action="store_true",
                        help="also write animation.html: the simulation and the logged motion (faint) in one 3-D page")
    parser.add_argument("--force", action="store_true",
                        help="replace an earlier replay folder even if files were added to it or changed since")


def run(args: argparse.Namespace) -> int:
    """Read, simulate, compare, write atomically; 0 on success, 3 when the simulation diverged."""
    import sys

    from uvms.errors import UvmsInputError
    from uvms.logs import Log
    from uvms.logs.bundled import resolve_logs
    from uvms.model.load import load_model
    from uvms.output import check_output_folder, default_file_name

    from uvms import checks

    for flag, value in (("--step", args.step), ("--grid", args.grid)):
        if value is not None:
            checks.number(value, flag, positive=True, unit="s")
    paths = resolve_logs(args.log)
    if len(paths) != 1:
        raise UvmsInputError(f"names {len(paths)} logs; replay takes one (uvms identify takes several)", args.log)
    if args.output == "":
        raise UvmsInputError("expected a folder name, found an empty string", None, "--output")
    out = Path(args.output) if args.output is not None else Path("replays") / default_file_name([paths[0].stem], "",
                                                                                                 "replay")
    check_output_folder(out, "--output", kind="replaced folder", force=args.force)
    model = load_model(args.model)
    log = Log.load(paths[0])
    if args.grid is not None and args.grid > log.duration:
        raise UvmsInputError(f"expected at most the log's duration, {log.duration:.9g} s, got {args.grid!r}", None,
                             "--grid")
    from uvms.replays import replay

    options = {k: v for k, v in (("step", args.step), ("grid", args.grid)) if v is not None}
    rp = replay(model, log, **options)
    write_replay(rp, out, force=args.force, animate=args.animate)
    _print_scores(rp, out)
    if not rp.result.complete:
        print(f"uvms: error: {rp.result.message}", file=sys.stderr)
        return 3
    return 0


def write_replay(rp, out: Path, *, force: bool = False, animate: bool = False) -> None:
    """The replay folder (module docstring), staged and published whole."""
    from uvms.output import atomic_write_text, staged_directory
    from uvms.plots import save_figure

    with staged_directory(out, kind="replay", force=force) as tmp:
        rp.result.metadata["log"] = rp.log.source
        rp.result.save(tmp)
        atomic_write_text(tmp / "comparison.json", json.dumps(rp.comparison(), indent=2) + "\n")
        save_figure(rp.figure(), tmp / "comparison.png")
        if animate:
            from uvms.replays import log_result
            from uvms.view.animate import drawable_samples, replay as frames, write_replay_html

            title = f"{rp.name}: simulation (solid) and log (faint grey)"
            logged = log_result(rp.log, rp.model, times=rp.result.time[:drawable_samples(rp.result)])
            write_replay_html(frames(rp.result, rp.model, title=title), tmp / "animation.html",
                              ghost=frames(logged, rp.model), ghost_name="log")


def _print_scores(rp, out: Path) -> None:
    from rich.console import Console
    from rich.table import Table

    s = rp.scores
    table = Table(title=f"{rp.name}: {rp.model.name} against the log ({rp.log.frame}, {rp.log.duration:g} s)")
    for column in ("quantity", "RMSE", "held at start", "unit"):
        table.add_column(column, justify="left" if column == "quantity" else "right")
    for label, a, b, unit in (("roll", s.roll_rmse_deg, s.roll_no_skill_rmse_deg, "deg"),
                              ("pitch", s.pitch_rmse_deg, s.pitch_no_skill_rmse_deg, "deg"),
                              ("yaw change", s.yaw_change_rmse_deg, s.yaw_change_no_skill_rmse_deg, "deg"),
                              ("depth change", s.depth_change_rmse_m, s.depth_change_no_skill_rmse_m, "m")):
        table.add_row(label, f"{a:.3g}", f"{b:.3g}", unit)
    console = Console()
    console.print(table)
    console.print(f"replay saved to {out}/ (result.csv, result.json, comparison.json, comparison.png)",
                  highlight=False, soft_wrap=True)
