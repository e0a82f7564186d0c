"""``uvms compare``: the station-keeping controllers side by side on the paper's scenario.

Runs :data:`uvms.control.compare.DEFAULT_CASES` (``smc-ab``, ``smc-ne`` with a perfect and a noisy IMU,
``smc-vehicle``, ``pid``) on the paper's case 3 (the bundled scenario ``paper_case3_controlled``, with ideal
actuation) and prints
peak body-frame errors, peak ``|s|`` per axis, RMS commands and a chatter count; ``--json FILE`` saves them.
"""

from __future__ import annotations

import argparse

NAME = "compare"
HELP = "compare the station-keeping controllers on the paper's scenario (table; --json to save it)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms compare``."""
    parser.add_argument("--model", default="paper", metavar="FILE_OR_NAME",
                        help="model YAML file or bundled model name (default: paper)")
    parser.add_argument("--duration", type=float, default=None, metavar="S",
                        help="simulated time [s] (default: the scenario file's, 10)")
    parser.add_argument("--step", type=float, default=None, metavar="S",
                        help="RK4 step [s] (default: the scenario file's, 0.001)")
    parser.add_argument("--period", type=float, default=None, metavar="S",
                        help="controller update period [s] (default: the scenario file's, 0.01)")
    parser.add_argument("--hydro-scale", type=float, default=None, metavar="FACTOR",
                        help="controller model's added mass and drag / the plant's (default: 0.4, the paper's 60 %% error)")
    parser.add_argument("--json", metavar="FILE", default=None, help="also save the table and the settings as JSON")


def _defaults(args: argparse.Namespace) -> None:
    """Fill the options left out from the paper scenario file and the sliding-mode controllers' defaults."""
    from uvms.control.compare import PAPER_SCENARIO
    from uvms.control.smc import SlidingModeParameters
    from uvms.sim.scenario import load_scenario

    spec = load_scenario(PAPER_SCENARIO).spec
    for name, value in (("duration", spec.duration), ("step", spec.step), ("period", spec.controller.period),
                        ("hydro_scale", SlidingModeParameters().hydro_scale)):
        if getattr(args, name) is None:
            setattr(args, name, value)


def _check(args: argparse.Namespace) -> None:
    import math

    from uvms.errors import UvmsInputError

    _defaults(args)

    for name in ("duration", "step", "period"):
        value = getattr(args, name)
        if not (math.isfinite(value) and value > 0):
            raise UvmsInputError(f"expected a positive number of seconds, found {value!r}", path=f"--{name}")
    if args.step > args.duration:
        raise UvmsInputError(f"expected a step <= duration ({args.duration:g} s), found {args.step:g} s", path="--step")
    from uvms.sim.run import MAX_STEPS

    if args.duration / args.step > MAX_STEPS:
        raise UvmsInputError(f"expected at most {MAX_STEPS:.0e} steps in --duration, found {args.duration / args.step:.3g}",
                             path="--step")
    if args.period < args.step:
        raise UvmsInputError(f"expected a period >= step ({args.step:g} s), found {args.period:g} s", path="--period")
    if not (math.isfinite(args.hydro_scale) and args.hydro_scale >= 0):
        raise UvmsInputError(f"expected a factor >= 0, found {args.hydro_scale!r}", path="--hydro-scale")
    if args.json:
        from uvms.output import check_destination

        check_destination(args.json, "--json", kind="file")


def run(args: argparse.Namespace) -> int:
    """Run the comparison, print the table, optionally save JSON; 0 on success, 3 if a run diverged."""
    import json
    from pathlib import Path

    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    from uvms.control.compare import compare_controllers, scenario_torques
    from uvms.control.smc import SlidingModeParameters
    from uvms.errors import UvmsInputError
    from uvms.model import load_model
    from uvms.sim.result import atomic_write_text

    _check(args)
    model = load_model(args.model)
    try:
        scenario_torques(model)                     # the scenario needs an arm: say so about --model
    except UvmsInputError as exc:
        raise UvmsInputError(exc.message, path="--model") from None
    console = Console(stderr=True)
    with console.status("running") as status:
        table = compare_controllers(model, duration=args.duration, step=args.step, period=args.period,
                                    hydro_scale=args.hydro_scale,
                                    progress=lambda label: status.update(f"running {label}"))

    view = Table(title=f"Station keeping: model {model.name}, paper torques, {args.duration:g} s, ideal actuation, "
                       f"controller model hydrodynamics x{args.hydro_scale:g}")
    rows = [("xy error [mm]", "peak_xy_error_mm", "{:.3g}"), ("yaw error [deg]", "peak_yaw_error_deg", "{:.3g}"),
            ("|s| surge", "max_abs_s_surge", "{:.2g}"), ("|s| sway", "max_abs_s_sway", "{:.2g}"),
            ("|s| yaw", "max_abs_s_yaw", "{:.2g}"), ("RMS X [N]", "rms_command_X_N", "{:.3g}"),
            ("RMS Y [N]", "rms_command_Y_N", "{:.3g}"), ("RMS N [N m]", "rms_command_N_Nm", "{:.3g}"),
            ("chatter X/Y/N", None, None)]
    records = table.to_dict("records")
    view.add_column("", no_wrap=True)
    for record in records:
        state = "" if record["complete"] and record["healthy"] else " (diverged)" if not record["complete"] else \
            " (unhealthy)"
        view.add_column(escape(record["case"]) + state, justify="right")
    for label, key, fmt in rows:
        view.add_row(escape(label), *[f"{r['chatter_X']}/{r['chatter_Y']}/{r['chatter_N']}" if key is None or fmt is None
                                      else fmt.format(r[key]) for r in records])
    out = Console()
    out.print(view)
    paper = SlidingModeParameters()
    lam, phi = paper.bandwidth[0], paper.boundary_layer[0]          # the same on every paper axis
    out.print(escape(f"Peak body-frame errors (Phi/lambda = {phi / lam * 1e3:.1f} mm with "
                     f"the paper's values); peak |s| [m/s, rad/s] from the states with lambda = {lam:g}; "
                     "RMS commands; chatter: sign changes of the command increments."))

    if args.json:
        settings = {"model": model.name, "duration_s": args.duration, "step_s": args.step, "period_s": args.period,
                    "hydro_scale": args.hydro_scale, "actuation": "ideal", "joint_torques": "paper"}
        text = json.dumps({"settings": settings, "rows": table.to_dict("records")}, indent=2)
        atomic_write_text(Path(args.json), text + "\n")
        out.print(escape(f"saved {args.json}"))
    return 0 if bool(table["complete"].all()) else 3
