"""``uvms animate RUN [-o FILE.html|FILE.mp4|FILE.gif]``: a saved run replayed in 3-D."""

from __future__ import annotations

import argparse
from pathlib import Path

VIDEO_SUFFIXES = (".mp4", ".gif")
"""Video outputs (:data:`uvms.view.animate.VIDEO_SUFFIXES`, repeated here so that checking the output's name
imports nothing heavy)."""

NAME = "animate"
HELP = ("replay a saved run (a folder written by 'uvms run') in 3-D: an offline .html page with play/pause and a "
        "time slider (default RUN/animation.html), or an .mp4/.gif video")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the arguments of ``uvms animate``."""
    from uvms.view import DEFAULT_FPS, DEFAULT_MAX_FRAMES

    parser.add_argument("directory", metavar="RUN", help="a run folder written by 'uvms run' (result.csv, "
                        "result.json, scenario.yaml)")
    parser.add_argument("-o", "--output", metavar="FILE", default=None,
                        help="FILE.html (interactive, offline), FILE.mp4 (needs ffmpeg) or FILE.gif; "
                             "default: RUN/animation.html, which never replaces a file uvms did not write")
    parser.add_argument("--force", action="store_true",
                        help="let the default output replace an existing file that uvms did not write")
    parser.add_argument("--fps", type=float, default=DEFAULT_FPS,
                        help=f"frames per second of playback (default {DEFAULT_FPS:g})")
    parser.add_argument("--speed", type=float, default=1.0,
                        help="playback speed: simulated seconds per second of playback (default 1)")
    parser.add_argument("--max-frames", type=int, default=DEFAULT_MAX_FRAMES,
                        help=f"at most this many frames; a longer replay keeps its length at a lower frame rate "
                             f"(default {DEFAULT_MAX_FRAMES})")
    parser.add_argument("--start", type=float, default=None, metavar="SECONDS",
                        help="HTML only: the time the page opens at (default: the start of the run)")


def run(args: argparse.Namespace) -> int:
    """Read the run and its model, check the output, draw the frames, write atomically."""
    import numpy as np

    from uvms.errors import UvmsInputError
    from uvms.output import check_file_output, record_written
    from uvms.sim.result import check_result_files

    directory = Path(args.directory)
    if args.output == "":
        raise UvmsInputError("expected a file name, found an empty string", None, "--output")
    output = Path(args.output) if args.output else directory / "animation.html"
    suffix = output.suffix.lower()
    if suffix not in (".html", ".htm") + VIDEO_SUFFIXES:
        raise UvmsInputError("expected a .html, .mp4 or .gif file name", str(output), "--output")
    check_result_files(directory)          # sizes and nesting first: refused before the heavy imports
    from uvms.sim.result import Result
    from uvms.sim.run import Actuation
    from uvms.view.animate import replay, scenario_of_run, write_replay_html, write_video
    from uvms.view.water import flow_of_scenario

    result = Result.load(directory)
    scenario = scenario_of_run(directory)
    model, thrusters = scenario.model, Actuation.named(scenario.spec.actuators, scenario.model).thrusters
    record = check_file_output(output, "--output", named=args.output is not None, force=args.force)
    rp = replay(result, model, fps=args.fps, speed=args.speed, max_frames=args.max_frames, thrusters=thrusters,
                flow=flow_of_scenario(scenario))
    if suffix in VIDEO_SUFFIXES:
        if args.start is not None:
            raise UvmsInputError("applies to .html pages only", None, "--start")
        write_video(rp, output)
    else:
        start = 0
        if args.start is not None:
            if not np.isfinite(args.start):
                raise UvmsInputError(f"expected a time in seconds, found {args.start}", None, "--start")
            start = int(np.argmin(np.abs(rp.times - args.start)))
        write_replay_html(rp, output, start=start)
    if record:                      # a new file, or one uvms wrote: listed in the run folder's marker
        record_written(output)
    print(f"{len(rp.snaps)} frames at {rp.fps:.3g} fps ({rp.times[0]:.3g}..{rp.times[-1]:.3g} s) written to {output}")
    return 0
