"""``uvms plot DIR [-o FILE.png]``: time-series figure of a saved run (``DIR/result.csv``)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

NAME = "plot"
HELP = "draw the time series of a saved run (DIR/result.csv) into DIR/timeseries.png"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms plot``."""
    parser.add_argument("directory", metavar="DIR", help="a run directory written by 'uvms run'")
    parser.add_argument("-o", "--output", metavar="FILE.png", default=None,
                        help="figure file (default: DIR/timeseries.png; the format follows the extension)")


def run(args: argparse.Namespace) -> int:
    """Read the run's table, draw it, save the figure."""
    from uvms.plots import check_figure_path, save_figure, timeseries_figure

    directory = Path(args.directory)
    table = _read_table(directory)
    output = check_figure_path(args.output if args.output else directory / "timeseries.png", "--output")
    fig = timeseries_figure(table, title=_title(directory))
    save_figure(fig, output)
    print(f"figure saved to {output}")
    return 0


def _read_table(directory: Path):
    """``result.csv`` of a run as a DataFrame; a missing or unreadable table is an input error."""
    import pandas as pd

    from uvms.errors import UvmsInputError

    path = directory / "result.csv"
    if not directory.is_dir():
        raise UvmsInputError("no such run directory", str(directory))
    if not path.is_file():
        raise UvmsInputError("no result.csv here (write one with 'uvms run SCENARIO -o DIR')", str(directory))
    try:
        table = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError, OSError) as exc:
        raise UvmsInputError(f"cannot read the table: {' '.join(str(exc).split())}", str(path)) from None
    required = ("t_s", "x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad", "ee_x_m", "ee_y_m")
    missing = [c for c in required if c not in table.columns]
    if missing or table.empty:
        what = f"missing columns {', '.join(missing)}" if missing else "no rows"
        raise UvmsInputError(f"not a uvms result table: {what}", str(path))
    return table


def _title(directory: Path) -> str:
    """Scenario name and completeness from ``result.json`` (the directory name if there is none)."""
    try:
        summary = json.loads((directory / "result.json").read_text())
    except (OSError, ValueError):
        return directory.name
    meta = summary.get("metadata", {})
    name = meta.get("scenario") or directory.name
    parts = [name, f"{meta.get('vehicle', '')} vehicle".strip() if meta.get("vehicle") else "",
             f"controller {meta['controller']}" if meta.get("controller") else "control off"]
    title = ", ".join(p for p in parts if p)
    if not summary.get("complete", True):
        title += f"\nINCOMPLETE: {summary.get('message', '')}"
    return title
