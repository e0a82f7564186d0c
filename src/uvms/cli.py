"""Command-line interface: ``uvms <command> ...`` (subcommands in :mod:`uvms.commands`).

The only place that prints errors and chooses exit codes: 0 success, 1 a sweep stopped by its cluster (lost
workers or scheduler; it resumes), 2 invalid input (one line, no traceback),
3 simulation diverged.
"""

from __future__ import annotations

import argparse
import importlib
import sys
import warnings
from importlib.metadata import PackageNotFoundError, version

from uvms.commands import COMMANDS
from uvms.errors import SimulationDiverged, UvmsInputError


def _version() -> str:
    try:
        return version("uvms")
    except PackageNotFoundError:  # running from a source tree without installation
        return "unknown"


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line (``uvms: error: ...``), like every other input error."""

    def error(self, message: str):
        raise UvmsInputError(f"{message} (see '{self.prog} --help')")


def build_parser() -> argparse.ArgumentParser:
    """The ``uvms`` parser with one subparser per module in :data:`uvms.commands.COMMANDS`."""
    parser = _Parser(prog="uvms", description="Underwater vehicle-manipulator system simulator.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module_name in COMMANDS:
        module = importlib.import_module(f"uvms.commands.{module_name}")
        sub = subparsers.add_parser(module.NAME, help=module.HELP, description=module.HELP)
        module.add_arguments(sub)
        sub.set_defaults(_run=module.run)
    return parser


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A Python warning as one line on stderr, ``uvms: warning: <message>`` (no file, line or source)."""
    print(f"uvms: warning: {' '.join(str(message).split())}", file=sys.stderr, flush=True)


def main(argv: list[str] | None = None) -> int:
    """Run the CLI and return the exit code (``--help``, ``--version`` and usage errors included). Python
    warnings print as one line each (``uvms: warning: ...``), every distinct one once (Python's default filter)."""
    with warnings.catch_warnings():       # the filters stay the caller's: Python's default shows a warning once
        warnings.showwarning = _show_warning
        return _main(argv)


def _main(argv: list[str] | None) -> int:
    try:
        args = build_parser().parse_args(argv)
        from uvms._cache import set_compile_notice

        set_compile_notice(lambda text: print(text, file=sys.stderr, flush=True))
        return int(args._run(args))
    except SystemExit as exc:  # argparse: --help, --version
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    except KeyboardInterrupt:  # Ctrl-C: results are written atomically, so nothing half-written remains
        print("uvms: interrupted", file=sys.stderr)
        return 130
    except UvmsInputError as exc:
        print(f"uvms: error: {exc}", file=sys.stderr)
        return 2
    except SimulationDiverged as exc:
        print(f"uvms: error: {exc}", file=sys.stderr)
        return 3
    except OSError as exc:  # an output path that cannot be written, a file that vanished: the user's to fix
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"uvms: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    finally:
        from uvms._cache import set_compile_notice

        set_compile_notice(None)              # the notice belongs to this command only
