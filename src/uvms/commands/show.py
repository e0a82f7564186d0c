"""``uvms show MODEL [--q Q1 ... | --q NAME=VALUE ...] [-o FILE.html|FILE.png]``: the vehicle and arm in 3-D at a pose."""

from __future__ import annotations

import argparse
from pathlib import Path

from uvms.commands._options import add_q_argument, q_option

NAME = "show"
HELP = ("draw a model in 3-D at a pose: an interactive offline .html page (default MODEL.html) or a .png/.pdf/"
        ".svg picture")

HTML_SUFFIXES = (".html", ".htm")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms show``."""
    parser.add_argument("model", metavar="MODEL", help="model YAML file, or a bundled model name (e.g. paper)")
    add_q_argument(parser)
    parser.add_argument("--position", metavar="M", type=float, nargs=3, default=None,
                        help="vehicle position x y z in the world, in the model's frame (ned: north, east, down; enu: z up) [m] (default: 0 0 0)")
    parser.add_argument("--euler", metavar="RAD", type=float, nargs=3, default=None,
                        help="vehicle roll pitch yaw (ZYX Euler angles) [rad] (default: 0 0 0)")
    parser.add_argument("--scenario", metavar="SCENARIO", default=None,
                        help="also draw the free surface and current arrows of this scenario's environment at t = 0 "
                             "(waves, a depth profile or a gridded field; docs/environment.md)")
    parser.add_argument("-o", "--output", metavar="FILE", default=None,
                        help="FILE.html (interactive, works offline), or FILE.png/.pdf/.svg/.jpg (static); "
                             "default: <model name>.html in the working folder, which never replaces a file "
                             "uvms did not write")
    parser.add_argument("--force", action="store_true",
                        help="let the default output replace an existing file that uvms did not write")


def output_kind(path: Path, option: str = "--output") -> str:
    """``"html"`` or ``"figure"`` from the extension (else a one-line error naming ``option``)."""
    from uvms.errors import UvmsInputError
    from uvms.plots import FIGURE_SUFFIXES

    suffix = path.suffix.lower()
    if suffix not in HTML_SUFFIXES + FIGURE_SUFFIXES:
        raise UvmsInputError("expected a .html, .png, .pdf, .svg or .jpg file name", str(path), option)
    return "html" if suffix in HTML_SUFFIXES else "figure"


def default_output(model, given: str) -> Path:
    """``<model name>.html`` in the working folder: the model's name if it is a plain file name, else the model
    file's stem made one (other characters become ``_``), else ``model.html``
    (:func:`uvms.output.default_file_name`; a name never makes a path)."""
    from uvms.output import default_file_name
    from uvms.schema_base import sanitised_name

    source = str(model.source or given)
    stem = sanitised_name(Path(source).stem, "model") if "\0" not in source else "model"
    return Path(default_file_name([model.name, stem], ".html", fallback="model"))


def run(args: argparse.Namespace) -> int:
    """Load the model, check the pose and the output, draw, write atomically."""
    import numpy as np

    from uvms.errors import UvmsInputError
    from uvms.model.load import load_model
    from uvms.output import check_file_output, record_written
    from uvms.state import State

    model = load_model(args.model)
    if args.output == "":
        raise UvmsInputError("expected a file name, found an empty string", None, "--output")
    output = Path(args.output) if args.output else default_output(model, args.model)
    kind = output_kind(output)
    record = check_file_output(output, "--output", named=args.output is not None, force=args.force)
    for option, values in (("--position", args.position), ("--euler", args.euler)):
        if values is not None and not np.all(np.isfinite(values)):
            raise UvmsInputError(f"expected finite numbers, found {values}", None, option)
    from uvms.view import picture, show, state_at

    flow = None
    if getattr(args, "scenario", None) is not None:
        from uvms.sim.scenario import load_scenario
        from uvms.view.water import flow_of_scenario

        flow = flow_of_scenario(load_scenario(args.scenario))
    q = q_option(model, args.q)
    state = state_at(model, State.from_euler(model, position=args.position, euler=args.euler), q=q)
    if kind == "html":
        from uvms.view.plotly_html import write_html

        write_html(show(model, state, flow=flow), output)
    else:
        from uvms.plots import save_figure

        save_figure(picture(model, state, flow=flow), output, dpi=130)
    if record:
        record_written(output)
    print(f"{model.name} drawn to {output}")
    return 0
