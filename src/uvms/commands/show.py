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
                        help="vehicle position x y z in the world (north, east, down) [m] (default: 0 0 0)")
    parser.add_argument("--euler", metavar="RAD", type=float, nargs=3, default=None,
                        help="vehicle roll pitch yaw (ZYX Euler angles) [rad] (default: 0 0 0)")
    parser.add_argument("-o", "--output", metavar="FILE", default=None,
                        help="FILE.html (interactive, works offline), or FILE.png/.pdf/.svg/.jpg (static); "
                             "default: <model name>.html")


def output_kind(path: Path, option: str = "--output") -> str:
    """``"html"`` or ``"figure"`` from the extension, after checking that the file can be written."""
    from uvms.errors import UvmsInputError
    from uvms.output import check_destination
    from uvms.plots import FIGURE_SUFFIXES, check_figure_path

    suffix = path.suffix.lower()
    if suffix in HTML_SUFFIXES:
        check_destination(path, option, kind="file")
        return "html"
    if suffix in FIGURE_SUFFIXES:
        check_figure_path(path, option)
        return "figure"
    raise UvmsInputError("expected a .html, .png, .pdf, .svg or .jpg file name", str(path), option)


def run(args: argparse.Namespace) -> int:
    """Load the model, check the pose and the output, draw, write atomically."""
    import numpy as np

    from uvms.errors import UvmsInputError
    from uvms.model.load import load_model
    from uvms.state import State

    model = load_model(args.model)
    output = Path(args.output) if args.output else Path(f"{model.name}.html")
    if args.output == "":
        raise UvmsInputError("expected a file name, found an empty string", None, "--output")
    kind = output_kind(output)
    for option, values in (("--position", args.position), ("--euler", args.euler)):
        if values is not None and not np.all(np.isfinite(values)):
            raise UvmsInputError(f"expected finite numbers, found {values}", None, option)
    from uvms.view import picture, show, state_at

    q = q_option(model, args.q)
    state = state_at(model, State.from_euler(model, position=args.position, euler=args.euler), q=q)
    if kind == "html":
        from uvms.view.plotly_html import write_html

        write_html(show(model, state), output)
    else:
        from uvms.plots import save_figure

        save_figure(picture(model, state), output, dpi=130)
    print(f"{model.name} drawn to {output}")
    return 0
