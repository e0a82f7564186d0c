"""Real logs: how fast a logged trial replays and how long an identification takes (issue "Real logs in":
``uvms replay`` >= 50x real time; ``uvms identify`` on 10 trials of ~20 s within 10 minutes on the 2-core
machine).

``python benchmarks/bench_replay.py [--trials 10] [--json FILE]``

- replay: every bundled held-out Hinsdale trial (``hinsdale_2023/traj_alt_*``) replayed with
  ``hinsdale_bluerov2_alpha5`` (RK4, 2 ms), warm kernels; the real-time factor is simulated seconds over the wall
  seconds of ``uvms.replay`` (log reading, spline, run, scores), median and slowest;
- identify: ``uvms.identify`` of the published model on the first ``--trials`` clean ``traj*`` trials, the 11
  parameters of the bundled fit (``docs/logs.md``), at most 40 evaluations, on the machine's cores; its wall time.

The kernels are compiled first (one short replay) so that neither figure includes the compile. The load average
is printed with the figures: the VM's speed moves by +-20 % from minute to minute.
"""

from __future__ import annotations

import argparse
import json
import os
import time
import warnings

FIT = ("damping.linear.roll,damping.linear.pitch,damping.quadratic.roll,damping.quadratic.pitch,cob.x,cob.y,cob.z,"
       "added_mass.roll,added_mass.pitch,damping.linear.surge=0:50,damping.linear.sway=0:50")


def main() -> None:
    import numpy as np

    import uvms
    from uvms.identify import identify
    from uvms.logs import Log
    from uvms.logs.bundled import resolve_logs
    from uvms.model.limits import JointLimitWarning
    from uvms.replays import plan
    from uvms.replays.hinsdale import LOST_TRACKING

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=10)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    warnings.simplefilter("ignore", JointLimitWarning)
    model = uvms.load_model("hinsdale_bluerov2_alpha5")
    held = resolve_logs("hinsdale_2023/traj_alt_*")
    uvms.replay(model, held[0])                                  # compile once
    factors = []
    for path in held:
        tic = time.perf_counter()
        rp = uvms.replay(model, path)
        factors.append(rp.log.duration / (time.perf_counter() - tic))
    fit_logs = [p for p in resolve_logs("hinsdale_2023/traj0*") if p.stem not in LOST_TRACKING][:args.trials]
    experiments = [plan(model, Log.load(p)) for p in fit_logs]
    seconds = sum(e.duration for e in experiments)
    tic = time.perf_counter()
    result = identify(model, experiments, FIT.split(","), max_evaluations=40)
    wall = time.perf_counter() - tic
    out = {"replay_real_time_factor_median": float(np.median(factors)),
           "replay_real_time_factor_slowest": float(np.min(factors)),
           "identify_trials": len(experiments), "identify_logged_seconds": round(seconds, 1),
           "identify_wall_s": round(wall, 1), "identify_evaluations": result.evaluations,
           "identify_converged": result.converged, "cores": os.cpu_count(),
           "load_average": os.getloadavg()}
    print(f"replay: {np.median(factors):.0f}x real time (median of {len(factors)} trials; slowest "
          f"{np.min(factors):.0f}x); target >= 50x")
    print(f"identify: {len(experiments)} trials ({seconds:.0f} s of log), 11 parameters, {result.evaluations} "
          f"evaluations in {wall:.0f} s on {os.cpu_count()} cores (target <= 600 s); load {os.getloadavg()[0]:.1f}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
