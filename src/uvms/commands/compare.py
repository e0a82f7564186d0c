"""``uvms compare``: the station-keeping controllers side by side on a scenario (default: the paper's).

Without ``--scenario`` it runs :data:`uvms.control.compare.DEFAULT_CASES` (``smc-ab``, ``smc-ne`` with a perfect
and a noisy IMU, ``smc-vehicle``, ``pid``; ``--lqr`` adds the ``lqr`` baseline) on the paper's case 3 (the bundled scenario
``paper_case3_controlled``, with ideal actuation) and prints peak body-frame errors, peak ``|s|`` per axis, RMS
commands and a chatter count. ``--scenario NAME_OR_FILE`` runs
:data:`~uvms.control.compare.SIX_AXIS_CASES` on any scenario (plus ``smc-ab`` with wave feed-forward,
:data:`~uvms.control.compare.WAVE_FEED_FORWARD_CASE`, on a scenario with an ``environment:`` section), each
controller holding the axes the scenario's controller holds, with the scenario's actuators, and prints the metrics
of those axes (:func:`uvms.control.compare.metrics`). ``--json FILE`` saves the table.
"""

from __future__ import annotations

import argparse

NAME = "compare"
HELP = "compare the station-keeping controllers on a scenario (default: the paper's; table; --json to save it)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms compare``."""
    parser.add_argument("--scenario", default=None, metavar="FILE_OR_NAME",
                        help="scenario YAML file or bundled scenario name (default: paper_case3_controlled)")
    parser.add_argument("--model", default=None, metavar="FILE_OR_NAME",
                        help="model YAML file or bundled model name (default: the scenario's; paper)")
    parser.add_argument("--actuators", choices=("ideal", "scenario"), default=None,
                        help="ideal actuation or the scenario's actuators (default: ideal on the paper's scenario, "
                             "the scenario's on any other)")
    parser.add_argument("--duration", type=float, default=None, metavar="S",
                        help="simulated time [s] (default: the scenario file's; 10 for the paper's)")
    parser.add_argument("--step", type=float, default=None, metavar="S",
                        help="RK4 step [s] (default: the scenario file's, 0.001)")
    parser.add_argument("--period", type=float, default=None, metavar="S",
                        help="controller update period [s] (default: the scenario file's, 0.01)")
    parser.add_argument("--hydro-scale", type=float, default=None, metavar="FACTOR",
                        help="controller model's added mass and drag / the plant's (default: 0.4, the paper's 60 %% error)")
    parser.add_argument("--lqr", action="store_true",
                        help="add the lqr baseline to the paper's comparison (every other scenario has it)")
    parser.add_argument("--json", metavar="FILE", default=None, help="also save the table and the settings as JSON")


def _load(args: argparse.Namespace):
    """The scenario (``--scenario``, default the paper's); a missing or invalid file fails in one line."""
    from uvms.control.compare import PAPER_SCENARIO
    from uvms.sim.scenario import load_scenario

    return load_scenario(PAPER_SCENARIO if args.scenario is None else args.scenario)


def _defaults(args: argparse.Namespace, scenario) -> None:
    """Fill the options left out from the scenario file and the sliding-mode controllers' defaults."""
    from uvms.control.compare import is_paper
    from uvms.control.smc import SlidingModeParameters

    spec = scenario.spec
    period = spec.controller.period if spec.controller is not None else 0.01
    for name, value in (("duration", spec.duration), ("step", spec.step), ("period", period),
                        ("hydro_scale", SlidingModeParameters().hydro_scale),
                        ("actuators", "ideal" if is_paper(scenario) else "scenario")):
        if getattr(args, name) is None:
            setattr(args, name, value)


def _check(args: argparse.Namespace, scenario) -> None:
    import math

    from uvms.errors import UvmsInputError

    _defaults(args, scenario)

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


def _model(args: argparse.Namespace, scenario):
    """The model compared (``--model``, default the scenario's), checked against the scenario's inputs."""
    from uvms.control.compare import is_paper, scenario_torques
    from uvms.errors import UvmsInputError
    from uvms.model import load_model

    if args.model is None:
        return scenario.model
    model = load_model(args.model)
    if is_paper(scenario):
        try:
            scenario_torques(model)                 # the scenario needs an arm: say so about --model
        except UvmsInputError as exc:
            raise UvmsInputError(exc.message, path="--model") from None
    elif model.n_joints != scenario.model.n_joints:
        raise UvmsInputError(f"expected a model with {scenario.model.n_joints} joints (the scenario's inputs are for "
                             f"{scenario.model.name!r}), found {model.name!r} with {model.n_joints}", path="--model")
    return model


ROWS_PAPER = (("xy error [mm]", "peak_xy_error_mm", "{:.3g}"), ("yaw error [deg]", "peak_yaw_error_deg", "{:.3g}"),
              ("|s| surge", "max_abs_s_surge", "{:.2g}"), ("|s| sway", "max_abs_s_sway", "{:.2g}"),
              ("|s| yaw", "max_abs_s_yaw", "{:.2g}"))
"""The error rows of the paper's comparison: label, metric, format."""

ROWS_SIX = (("world xy error [mm]", "peak_world_xy_error_mm", "{:.3g}"),
            ("depth error [mm]", "peak_depth_error_mm", "{:.3g}"),
            ("roll error [deg]", "peak_roll_error_deg", "{:.3g}"), ("pitch error [deg]", "peak_pitch_error_deg", "{:.3g}"),
            ("yaw error [deg]", "peak_yaw_error_deg", "{:.3g}"))
"""The error rows of a comparison on other axes (those of the held axes are shown)."""


def replaced_controller(scenario) -> dict | None:
    """The scenario file's own controller, which every case of the comparison replaces (``None``: the file has
    none): its ``name``, ``period_s`` and ``parameters`` (the cases keep only its ``axes`` and period)."""
    spec = scenario.spec.controller
    if spec is None:
        return None
    return {"name": spec.name, "period_s": spec.period, "parameters": dict(spec.parameters)}


def _replaced_note(scenario, args: argparse.Namespace) -> str:
    """One sentence saying that the file's controller settings are replaced (``docs/controllers.md``)."""
    replaced = replaced_controller(scenario)
    if replaced is None:
        return f"Scenario {scenario.name} has no controller of its own: each column runs its controller on it."
    given = ", ".join(f"{k}: {v}" for k, v in replaced["parameters"].items()) or "defaults"
    return (f"Each column's controller replaces the scenario's own ({replaced['name']}, {given}): only its axes and "
            f"period are kept (period {args.period:g} s); every other setting is the column controller's default.")


def print_table(table, args: argparse.Namespace, *, scenario, model):
    """Print the comparison (``table``: :func:`uvms.control.compare.compare_controllers`'s) on stdout, every cell
    whole: the console is as wide as the table needs, whatever the terminal (rich cuts cells to fit 80 columns
    when stdout is not a terminal). Returns the console."""
    from rich.console import Console
    from rich.markup import escape
    from rich.measure import Measurement
    from rich.table import Table

    from uvms.control.compare import AXIS_COMMAND, PAPER_AXES, is_paper, scenario_axes
    from uvms.control.smc import SlidingModeParameters

    axes, paper = scenario_axes(scenario), is_paper(scenario)
    three = set(axes) <= set(PAPER_AXES)
    inputs = "paper torques" if paper else f"scenario {scenario.name}"
    actuators = "ideal actuation" if args.actuators == "ideal" else f"actuators {scenario.spec.actuators}"
    view = Table(title=f"Station keeping ({', '.join(axes)}): model {model.name}, {inputs}, {args.duration:g} s, "
                       f"{actuators}, controller model hydrodynamics x{args.hydro_scale:g}")
    commands = [c for a, c in AXIS_COMMAND.items() if a in axes] if not three else \
        [AXIS_COMMAND[a] for a in PAPER_AXES]
    rows = [row for row in (ROWS_PAPER if three else ROWS_SIX) if row[1] in table.columns]
    rows += [(f"RMS {c} [{u.replace('Nm', 'N m')}]", f"rms_command_{c}_{u}", "{:.3g}") for c, u in commands]
    chatter = [c for c, _ in commands]
    rows.append((f"chatter {'/'.join(chatter)}", None, None))
    records = table.to_dict("records")
    view.add_column("", no_wrap=True)
    for record in records:
        state = "" if record["complete"] and record["healthy"] else " (diverged)" if not record["complete"] else \
            " (unhealthy)"
        view.add_column(escape(record["case"]) + state, justify="right", no_wrap=True)
    for label, key, fmt in rows:
        view.add_row(escape(label), *["/".join(str(r[f"chatter_{c}"]) for c in chatter) if key is None
                                      else fmt.format(r[key]) for r in records])
    probe = Console(width=10_000)
    terminal = Console()
    out = Console(width=max(Measurement.get(probe, probe.options, view).maximum,
                            terminal.width if terminal.is_terminal else 80))
    out.print(view)
    if three:
        par = SlidingModeParameters()
        lam, phi = par.bandwidth[0], par.boundary_layer[0]          # the same on every paper axis
        note = (f"Peak body-frame errors (Phi/lambda = {phi / lam * 1e3:.1f} mm with "
                f"the paper's values); peak |s| [m/s, rad/s] from the states with lambda = {lam:g}; "
                "RMS commands; chatter: sign changes of the command increments.")
    else:
        note = ("Peak errors from the set point (initial position and yaw, level): world-frame xy, depth, "
                "roll, pitch, yaw; RMS commands of the held axes; chatter: sign changes of the command "
                "increments.")
    out.print(note, markup=False, highlight=False)
    out.print(_replaced_note(scenario, args), markup=False, highlight=False)
    return out


def run(args: argparse.Namespace) -> int:
    """Run the comparison, print the table, optionally save JSON; 0 on success, 3 if a run diverged."""
    import json
    from pathlib import Path

    from rich.console import Console

    from uvms.control.compare import DEFAULT_CASES, LQR_CASE, compare_controllers, is_paper, scenario_axes
    from uvms.sim.result import atomic_write_text
    from uvms.sim.run import Actuation

    scenario = _load(args)
    _check(args, scenario)
    axes = scenario_axes(scenario)
    model = _model(args, scenario)
    paper = is_paper(scenario)
    actuation = Actuation() if args.actuators == "ideal" else None
    console = Console(stderr=True)
    with console.status("running") as status:
        cases = DEFAULT_CASES + (LQR_CASE,) if paper and args.lqr else None
        table = compare_controllers(model, cases, scenario=scenario, duration=args.duration, step=args.step,
                                    period=args.period, hydro_scale=args.hydro_scale, actuation=actuation,
                                    progress=lambda label: status.update(f"running {label}"))

    out = print_table(table, args, scenario=scenario, model=model)
    if args.json:
        settings = {"scenario": scenario.name, "axes": list(axes), "model": model.name, "duration_s": args.duration,
                    "step_s": args.step, "period_s": args.period, "hydro_scale": args.hydro_scale,
                    "actuation": "ideal" if args.actuators == "ideal" else scenario.spec.actuators,
                    "joint_torques": "paper" if paper else "scenario"}
        replaced = replaced_controller(scenario)
        if replaced is not None:
            settings["scenario_controller_replaced"] = replaced
        text = json.dumps({"settings": settings, "rows": table.to_dict("records")}, indent=2)
        atomic_write_text(Path(args.json), text + "\n")
        out.print(f"saved {args.json}", markup=False, highlight=False)
    return 0 if bool(table["complete"].all()) else 3
