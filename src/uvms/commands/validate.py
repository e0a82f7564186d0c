"""``uvms validate FILE_OR_NAME``: check a model file (YAML, or a URDF/xacro robot description) and print a
short summary."""

from __future__ import annotations

import argparse

NAME = "validate"
HELP = "check a model file, URDF or xacro (or a bundled model name) and summarise it"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms validate``."""
    parser.add_argument("model", metavar="FILE_OR_NAME",
                        help="model YAML file, URDF (.urdf) or xacro (.xacro) file, or a bundled model name (paper)")


def run(args: argparse.Namespace) -> int:
    """Load the model (errors surface as one-line :class:`~uvms.errors.UvmsInputError`) and summarise it."""
    import numpy as np

    from uvms.model import load_model

    model = load_model(args.model)
    g = float(np.linalg.norm(model.gravity))
    mass, displaced = float(model.mass.sum()), float(model.buoyancy_mass.sum())
    print(f"{model.name}: valid ({model.source})")
    print(f"  joints:               {model.n_joints}")
    if model.n_joints:
        print(f"  joint order (q):      {', '.join(model.joint_names)}")
    print(f"  frames:               {len(model.frames)} (end effector on {model.body_names[model.ee_body]!r})")
    print(f"  thrusters:            {len(model.thrusters)}")
    print(f"  total mass:           {mass:.6g} kg")
    print(f"  displaced fluid mass: {displaced:.6g} kg")
    print(f"  net buoyancy:         {(displaced - mass) * g:.6g} N (positive: rises)")
    return 0
