"""``uvms validate FILE_OR_NAME [--q Q1 ... | --q NAME=VALUE ...] [--json]``: check a model file (YAML, or a
URDF/xacro robot description), print a short summary and what a modeller needs next: mass and buoyancy, static moment and trim,
thrust available per axis, thruster layout rank, and whether the sliding-mode controller's ``b`` bounds
contain the model's effective inertia (every number from :func:`uvms.analysis.report.model_report`)."""

from __future__ import annotations

import argparse

from uvms.commands._options import add_q_argument, q_option

NAME = "validate"
HELP = "check a model file, URDF or xacro (or a bundled model name), summarise it and report its statics"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms validate``."""
    parser.add_argument("model", metavar="FILE_OR_NAME",
                        help="model YAML file, URDF (.urdf) or xacro (.xacro) file, or a bundled model name (paper)")
    add_q_argument(parser)
    parser.add_argument("--frame", choices=("ned", "enu"), default=None,
                        help="convention the file is written in (default: its 'frame:' key, else ned; a bare ROS "
                             "URDF is enu: world z up, base_link forward-left-up)")
    parser.add_argument("--json", action="store_true",
                        help="print the report as JSON (units in the key names) instead of text")


def run(args: argparse.Namespace) -> int:
    """Load the model (errors surface as one-line :class:`~uvms.errors.UvmsInputError`), summarise and report.

    The model is loaded before the report's modules are imported (they bring the compiled kernels): a bad or
    hostile file is refused after the loader's imports only (tests/model/test_gazebo_security.py)."""
    from uvms.model import load_model

    model = load_model(args.model, frame=getattr(args, "frame", None))

    from uvms.analysis.report import end_effector_name, model_report
    from uvms.frames import VEHICLE_AXES

    report = model_report(model, q=q_option(model, args.q))
    if args.json:
        import json

        data = {"valid": True, "source": model.source, "joints": list(model.joint_names),
                "frames": len(model.frames), "end_effector": end_effector_name(model),
                "end_effector_body": model.body_names[model.ee_body],
                **report.to_dict()}
        print(json.dumps(data, indent=2, allow_nan=False))
        return 0
    print(f"{model.name}: valid ({model.source})")
    world = "z down" if model.convention == "ned" else "z up"
    print(f"  frame:                {model.convention} (world {world}; vehicle {VEHICLE_AXES[model.convention]})")
    print(f"  joints:               {model.n_joints}")
    if model.n_joints:
        print(f"  joint order (q):      {', '.join(model.joint_names)}")
    print(f"  frames:               {len(model.frames)} (end effector {end_effector_name(model)!r}, fixed in body "
          f"{model.body_names[model.ee_body]!r})")
    print(f"  thrusters:            {len(model.thrusters)}")
    print(report.table())
    return 0
