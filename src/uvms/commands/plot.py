"""``uvms plot DIR [-o FILE.png]``: time-series figure of a saved run (``DIR/result.csv``)."""

from __future__ import annotations

import argparse
from pathlib import Path

NAME = "plot"
HELP = "draw the time series of a saved run (DIR/result.csv) into DIR/timeseries.png"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms plot``."""
    parser.add_argument("directory", metavar="DIR", help="a run directory written by 'uvms run'")
    parser.add_argument("-o", "--output", metavar="FILE.png", default=None,
                        help="figure file (default: DIR/timeseries.png, which never replaces a file uvms did not "
                             "write; the format follows the extension)")
    parser.add_argument("--force", action="store_true",
                        help="let the default output replace an existing file that uvms did not write")


def run(args: argparse.Namespace) -> int:
    """Read the run's table, draw it, save the figure."""
    from uvms.errors import UvmsInputError
    from uvms.output import check_file_output, record_written
    from uvms.plots import check_drawable, check_figure_path, save_figure, timeseries_figure
    from uvms.sim.result import check_result_files, load_result_summary, load_result_table

    if args.output == "":
        raise UvmsInputError("expected a file name, found an empty string", None, "--output")
    directory = Path(args.directory)
    check_result_files(directory)          # sizes and nesting first: refused before pandas is imported
    table = load_result_table(directory)
    summary = load_result_summary(directory)
    table.attrs["frame"] = (summary.get("metadata") or {}).get("frame", "ned")
    check_drawable(table, str(directory / "result.csv"))
    output = check_figure_path(args.output if args.output else directory / "timeseries.png", "--output")
    record = check_file_output(output, "--output", named=args.output is not None, force=args.force)
    fig = timeseries_figure(table, title=_title(summary, directory))
    save_figure(fig, output)
    if record:                      # a new file, or one uvms wrote: listed in the run folder's marker
        record_written(output)
    print(f"figure saved to {output}")
    return 0


def _title(summary: dict, directory: Path) -> str:
    """Scenario name and completeness from the run's summary (the folder name if there is none)."""
    meta = summary.get("metadata") or {}
    name = meta.get("scenario") or directory.name
    parts = [name, f"{meta['vehicle']} vehicle" if meta.get("vehicle") else "",
             f"controller {meta['controller']}" if meta.get("controller") else "control off"]
    title = ", ".join(p for p in parts if p)
    if summary.get("complete") is False:
        title += f"\nINCOMPLETE: {summary.get('message') or ''}"
    return title
