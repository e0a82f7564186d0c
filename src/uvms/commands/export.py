"""``uvms export RUN -o FILE.mcap [--model MODEL]``: a saved run as ROS 2 messages in an MCAP file (``docs/ros.md``).

The file opens in Foxglove and ``ros2 bag info``; its topics and frames are those of :mod:`uvms.ros.export`
(world z up, bodies forward-left-up: a z-down run is converted), the run's simulated sensors included. Needs the
optional extra ``uvms[ros]``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

NAME = "export"
HELP = ("write a saved run as ROS 2 messages (odometry, joint states, wrenches, tf, simulated sensors) in an MCAP "
        "file (uvms[ros])")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms export``."""
    parser.add_argument("directory", metavar="RUN", help="a run folder written by 'uvms run' or 'uvms replay'")
    parser.add_argument("-o", "--output", metavar="FILE.mcap", default=None,
                        help="the MCAP file (default: RUN/run.mcap, which never replaces a file uvms did not write)")
    parser.add_argument("--model", metavar="MODEL", default=None,
                        help="the run's model (default: the one its scenario.yaml names; a replay folder has none)")
    parser.add_argument("--force", action="store_true",
                        help="let the default output replace an existing file that uvms did not write")


def run(args: argparse.Namespace) -> int:
    """Read the run and its model, check the output, write the bag atomically."""
    from uvms.errors import UvmsInputError
    from uvms.output import check_file_output, record_written
    from uvms.sim.result import check_result_files

    directory = Path(args.directory)
    if args.output == "":
        raise UvmsInputError("expected a file name, found an empty string", None, "--output")
    output = Path(args.output) if args.output else directory / "run.mcap"
    if output.suffix.lower() != ".mcap":
        raise UvmsInputError("expected a .mcap file name", str(output), "--output")
    check_result_files(directory)
    from uvms.ros.export import _need_ros

    _need_ros()                                   # the extra before any work
    from uvms.model.load import load_model
    from uvms.ros import write_mcap
    from uvms.sim.result import Result

    result = Result.load(directory)
    if args.model is not None:
        model, thrusters = load_model(args.model), None
    else:
        from uvms.view.animate import model_of_run

        model, thrusters = model_of_run(directory)
    frame = (result.metadata or {}).get("frame", model.convention)
    if frame != model.convention:                 # a replay runs in its log's convention
        model = model.in_frame(frame)
        thrusters = None
    record = check_file_output(output, "--output", named=args.output is not None, force=args.force)
    write_mcap(result, output, model=model, thrusters=thrusters)
    if record:
        record_written(output)
    sensors = f" and {len(result.sensors)} sensors ({', '.join(result.sensors)})" if result.sensors else ""
    print(f"{len(result.time)} rows ({result.time[0]:.3g}..{result.time[-1]:.3g} s) of {model.name}{sensors} written "
          f"to {output} as ROS 2 messages (world z up, bodies forward-left-up)")
    return 0
