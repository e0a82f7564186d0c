"""``uvms thruster-curve``: steady thrust versus voltage and step-response rise times of the Healey thruster."""

from __future__ import annotations

import argparse

NAME = "thruster-curve"
HELP = "tabulate (and optionally plot) the default Healey thruster's steady thrust and step response"


MAX_POINTS = 1000
"""Most voltages tabulated on each side of zero."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--step", type=float, default=3.0, metavar="VOLTS",
                        help="voltage spacing of the table, from -Vmax to +Vmax: Vmax/1000 to Vmax (default: 3)")
    parser.add_argument("--plot", metavar="FILE.png", default=None,
                        help="save a figure (.png, .pdf, .svg or .jpg) of the thrust curve and of step responses at a few "
                             "voltages")


def run(args: argparse.Namespace) -> int:
    import math

    from rich.console import Console
    from rich.table import Table

    from uvms.errors import UvmsInputError
    from uvms.thrusters.curve import default_voltages, thrust_curve
    from uvms.thrusters.healey import RECOMMENDED_MAX_STEP, RK4_STABILITY_LIMIT, HealeyParameters

    params = HealeyParameters()
    if not (math.isfinite(args.step) and params.max_voltage / MAX_POINTS <= args.step <= params.max_voltage):
        raise UvmsInputError(f"expected a voltage step from {params.max_voltage / MAX_POINTS:g} to "
                             f"{params.max_voltage:g} V, found {args.step!r}", path="--step")
    if args.plot is not None:
        from uvms.plots import check_figure_path

        check_figure_path(args.plot, "--plot")
    curve = thrust_curve(params, default_voltages(params, args.step))

    table = Table(title="Healey thruster (defaults): steady state, 63 % rise from rest")
    for header in ("V [V]", "Omega [rad/s]", "U [m/s]", "T [N]", "t63 [ms]"):
        table.add_column(header, justify="right")
    for v, w, u, t, r in zip(curve.voltage, curve.omega, curve.inflow, curve.thrust, curve.rise_time):
        table.add_row(f"{v:+.1f}", f"{w:+.1f}", f"{u:+.3f}", f"{t:+.2f}", "-" if math.isnan(r) else f"{r * 1e3:.1f}")
    console = Console()
    console.print(table)
    console.print(f"RK4 stability limit {RK4_STABILITY_LIMIT * 1e3:.1f} ms, recommended step <= "
                  f"{RECOMMENDED_MAX_STEP * 1e3:.0f} ms")
    if args.plot is not None:
        _plot(params, curve, args.plot)
        console.print(f"figure saved to {args.plot}")
    return 0


def _plot(params, curve, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from uvms.plots import save_figure
    from uvms.thrusters.curve import step_responses
    from uvms.thrusters.healey import steady_state

    fine = np.linspace(-params.max_voltage, params.max_voltage, 201)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
    left.plot(fine, [steady_state(params, v)[2] for v in fine], label="steady thrust")
    left.plot(curve.voltage, curve.thrust, "o", label="table points")
    left.set_xlabel("voltage V [V]")
    left.set_ylabel("thrust T [N]")
    left.set_title("Steady thrust")
    left.grid(True)
    left.legend()
    for response in step_responses(params, [params.max_voltage * f for f in (0.125, 0.25, 0.5, 1.0)]):
        right.plot(response.time * 1e3, response.thrust, label=f"{response.voltage:g} V")
    right.set_xlabel("time t [ms]")
    right.set_ylabel("thrust T [N]")
    right.set_title("Step response from rest")
    right.grid(True)
    right.legend()
    fig.suptitle("Healey thruster (default parameters)")
    save_figure(fig, path, dpi=120)
    plt.close(fig)
