"""``uvms trim MODEL [--q NAME=VALUE ...] [--ballast mass|foam] [--json]``: the attitude the system rests at with
the arm in a given pose, its net vertical force, and the least ballast (a point mass, or buoyancy foam) that
levels it (every number from :func:`uvms.analysis.trim.trim`). No ballast that levels it: one line, exit 2."""

from __future__ import annotations

import argparse

from uvms.commands._options import add_q_argument, q_option

NAME = "trim"
HELP = "the attitude a model rests at with its arm in a pose, and the ballast that levels it"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms trim``."""
    parser.add_argument("model", metavar="MODEL", help="model YAML file, URDF or xacro file, or a bundled model name")
    add_q_argument(parser)
    parser.add_argument("--ballast", choices=("mass", "foam"), default="mass",
                        help="levelling ballast: a point mass [kg] (default) or buoyancy foam [m^3]")
    parser.add_argument("--foam-density", metavar="KG_M3", type=float, default=0.0,
                        help="density of the foam [kg/m^3] (default 0: ideal massless buoyancy)")
    parser.add_argument("--region", metavar="M", type=float, nargs=6, default=None,
                        help="box of allowed ballast positions, two corners X0 Y0 Z0 X1 Y1 Z1 in the vehicle frame [m] "
                             "(default: the vehicle's outline box)")
    parser.add_argument("--max", metavar="AMOUNT", type=float, default=None,
                        help="the most ballast allowed [kg or m^3] (default: no limit)")
    parser.add_argument("--min-arm", metavar="M", type=float, default=None,
                        help="least height of the centre of buoyancy above the centre of mass after levelling [m] "
                             "(default 0.001)")
    parser.add_argument("--json", action="store_true", help="print the trim as JSON (units in the key names)")


def run(args: argparse.Namespace) -> int:
    """Load the model, compute and print the trim."""
    from uvms.analysis.trim import MIN_ARM, trim
    from uvms.errors import UvmsInputError
    from uvms.model import load_model

    model = load_model(args.model)
    q = q_option(model, args.q)
    region = None if args.region is None else [args.region[:3], args.region[3:]]
    try:
        result = trim(model, q, ballast=args.ballast, region=region, max_amount=args.max,
                      foam_density=args.foam_density, min_arm=MIN_ARM if args.min_arm is None else args.min_arm)
    except UvmsInputError as exc:
        options = {"q": "--q", "region": "--region", "max_amount": "--max", "foam_density": "--foam-density",
                   "min_arm": "--min-arm"}
        if exc.path in options:
            raise UvmsInputError(exc.message, None, options[exc.path]) from None
        raise
    if args.json:
        import json

        print(json.dumps(result.to_dict(), indent=2, allow_nan=False))
    else:
        print(result.table())
    return 0
