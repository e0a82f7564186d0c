"""``uvms reproduce paper [-o DIR] [--actuators ideal|healey|paper-layout] [--format png|svg|pdf]
[--no-comparison] [--no-animation]``: the paper's Section 6 (``docs/reproduce.md``)."""

from __future__ import annotations

import argparse

NAME = "reproduce"
HELP = "reproduce the paper's simulations: figures 4-8, time series, metrics.json, report.md/.html, animation"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("target", choices=["paper"], help="what to reproduce (the seed paper's Section 6)")
    parser.add_argument("-o", "--output", default="reproduce-paper", metavar="DIR",
                        help="output folder (default: reproduce-paper)")
    parser.add_argument("--actuators", default="ideal", choices=["ideal", "healey", "paper-layout"],
                        help="ideal body wrench, Healey thrusters with a sway thruster, or the paper's 3 thrusters")
    parser.add_argument("--format", default="png", choices=["png", "svg", "pdf"], dest="figure_format",
                        help="file format of the figures (default: png)")
    parser.add_argument("--no-comparison", action="store_true",
                        help="skip the controller comparison table (24 extra runs)")
    parser.add_argument("--no-animation", action="store_true",
                        help="skip the 3-D replay of case 2 beside case 3 (animation_case2_vs_case3.html)")


def run(args: argparse.Namespace) -> int:
    import math
    import sys
    import time

    from rich.console import Console
    from rich.table import Table

    from uvms import reproduce

    console = Console(stderr=True)
    t0 = time.perf_counter()

    def progress(message: str) -> None:
        console.print(f"[dim]{time.perf_counter() - t0:6.1f} s[/dim]  {message}")

    import shlex

    command = ["uvms", "reproduce", "paper", "-o", args.output, "--actuators", args.actuators,
               "--format", args.figure_format] + (["--no-comparison"] if args.no_comparison else []) + (
        ["--no-animation"] if args.no_animation else [])
    metrics = reproduce.paper(args.output, actuators=args.actuators, compare=not args.no_comparison,
                              figure_format=args.figure_format, animation=not args.no_animation,
                              command_line=shlex.join(command), progress=progress)
    out = Console()
    table = Table(title=f"Paper Section 6 ({args.actuators} actuators), epsilon = "
                        f"{metrics['epsilon_m'] * 1e3:.2f} mm")
    for col in ("case", "peak |x| m", "peak |y| m", "peak |yaw| deg", "xy error mm", "ee deviation mm",
                "max |s|/Phi"):
        table.add_column(col, justify="right" if col != "case" else "left", no_wrap=col == "case")
    for name, c in metrics["cases"].items():
        s_ratio = max(c["max_abs_s"].values()) / reproduce.PAPER_PHI
        table.add_row(name, f"{c['peak_abs_x_m']:.4f}", f"{c['peak_abs_y_m']:.4f}",
                      f"{math.degrees(c['peak_abs_yaw_rad']):.2f}", f"{c['peak_body_error_xy_m'] * 1e3:.2f}",
                      f"{c['peak_ee_deviation_m'] * 1e3:.1f}", f"{s_ratio:.2f}")
    out.print(table)
    for claim in metrics["claims"]:
        mark = "[green]holds[/green]" if claim["verdict"] == "holds" else "[red]does not hold[/red]"
        out.print(f"- {claim['claim']}: {mark} ({claim['measured']})")
    central = metrics["central_claim"]
    mark = "[green]holds[/green]" if central["verdict"] == "holds" else "[red]does not hold[/red]"
    out.print(f"- central claim (smc-ab against smc-ne with an IMU): {mark}: {central['finding']}")
    if metrics.get("paper_layout"):
        failed = [c["claim"].split(":")[0] for c in metrics["paper_layout"]["claims"] if c["verdict"] != "holds"]
        out.print(f"- with the paper's 3-thruster layout, {len(failed)} claims fail: {'; '.join(failed) or '-'}")
    out.print(f"Wrote {args.output}/ (figures, cases/, metrics.json, report.md, report.html) in "
              f"{metrics['wall_time_s']:.1f} s")
    sys.stdout.flush()
    return 0
