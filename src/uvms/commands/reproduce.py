"""``uvms reproduce paper [-o DIR] [--actuators ideal|healey|paper-layout]``: the paper's Section 6."""

from __future__ import annotations

import argparse

NAME = "reproduce"
HELP = "reproduce the paper's simulations: figures 4-8, metrics.json, report.md/.html"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("target", choices=["paper"], help="what to reproduce (the seed paper's Section 6)")
    parser.add_argument("-o", "--output", default="reproduce-paper", metavar="DIR",
                        help="output folder (default: reproduce-paper)")
    parser.add_argument("--actuators", default="ideal", choices=["ideal", "healey", "paper-layout"],
                        help="ideal body wrench, Healey thrusters with a sway thruster, or the paper's 3 thrusters")
    parser.add_argument("--no-comparison", action="store_true",
                        help="skip the controller comparison table (24 extra runs)")


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

    metrics = reproduce.paper(args.output, actuators=args.actuators, compare=not args.no_comparison,
                              progress=progress)
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
    out.print(f"Wrote {args.output}/ (figures, metrics.json, report.md, report.html) in "
              f"{metrics['wall_time_s']:.1f} s")
    sys.stdout.flush()
    return 0
