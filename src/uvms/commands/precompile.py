"""``uvms precompile``: compile every kernel into the cache now (what ``pip install`` does; :mod:`uvms.precompile`)."""

from __future__ import annotations

import argparse

NAME = "precompile"
HELP = "compile the numerical kernels for this machine now (pip install does it; for a changed numba or CPU)"

MAX_JOBS = 64


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--jobs", type=int, default=2, help="processes compiling side by side (default: 2)")


def run(args: argparse.Namespace) -> int:
    from uvms.errors import UvmsInputError
    from uvms.precompile import main

    if not 1 <= args.jobs <= MAX_JOBS:
        raise UvmsInputError(f"expected 1 to {MAX_JOBS} processes, found {args.jobs}", path="--jobs")
    return main(["--jobs", str(args.jobs)])
