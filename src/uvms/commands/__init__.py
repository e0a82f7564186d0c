"""CLI subcommands, one module each.

A module exposes ``NAME`` (the subcommand), ``HELP`` (one line), ``add_arguments(parser)`` and
``run(args) -> int`` (exit code), and imports heavy modules inside ``run`` so that ``uvms --help`` stays fast.
Add a subcommand by adding its module name to :data:`COMMANDS`.
"""

COMMANDS: tuple[str, ...] = (
    "validate",
    "trim",
    "thruster_curve",
    "reproduce",
    "run", "plot",
    "compare",
    "sweep",
    "show", "animate",
    "replay", "identify",
    "export",
    "precompile",
)
