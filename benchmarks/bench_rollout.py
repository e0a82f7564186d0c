"""Batched closed-loop rollouts against MuJoCo's ``rollout``, side by side in one run, and the step API's cost.

``python benchmarks/bench_rollout.py [--runs 1000] [--duration 10] [--threads 2] [--json FILE]``

- **uvms**: ``uvms.rollout`` of ``--runs`` paper case-3 runs (``smc-ab`` every 10 ms, 1 ms RK4, the paper's
  joint torques), each with a random controller model error (``hydro_scale`` uniform in 0.3-1.7) and a random
  current (normal, 0.1 m/s per axis), recorded every 10 ms; ``--threads`` threads.
- **MuJoCo**: ``mujoco.rollout.rollout`` of the same number of RK4 steps (``--runs`` trajectories of
  ``duration / 1 ms`` steps) on the matching MJCF with its ellipsoid fluid model (``bench_dynamics.mjcf_from``),
  open loop, one ``MjData`` per thread, in chunks of 100 trajectories (its output holds every step).
- **step API**: ``uvms.Simulator.step(0.01)`` (10 RK4 steps) with ``smc-ab``, 2000 calls, against one call
  of the same 20 s from the same reset: the Python cost of a call.

Prints per-RK4-step times and the ratio uvms / MuJoCo (the issue's target: <= 0.7).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def uvms_rollout(runs: int, duration: float, threads: int) -> tuple[float, object]:
    import uvms
    from uvms.control.registry import make_controller
    from uvms.sim.inputs import paper_torques

    model = uvms.load_model("paper")
    rng = np.random.default_rng(2026)
    trials = [uvms.Trial(current=rng.normal(scale=0.1, size=3),
                         controller=make_controller("smc-ab", model, period=0.01,
                                                    parameters={"hydro_scale": float(rng.uniform(0.3, 1.7))}))
              for _ in range(runs)]
    uvms.rollout(model, trials[:2], duration=0.05, joint_torques=paper_torques(), threads=threads)  # warm
    start = time.perf_counter()
    batch = uvms.rollout(model, trials, duration=duration, step=1e-3, joint_torques=paper_torques(),
                         threads=threads, record_period=0.01)
    return time.perf_counter() - start, batch


def mujoco_rollout(runs: int, duration: float, threads: int) -> float | None:
    try:
        import mujoco
        from mujoco import rollout
    except ImportError:
        return None
    import uvms
    from bench_dynamics import mjcf_from

    model = uvms.load_model("paper")
    mm = mujoco.MjModel.from_xml_string(mjcf_from(model, fluid=True))
    datas = [mujoco.MjData(mm) for _ in range(threads)]
    nstate = mujoco.mj_stateSize(mm, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    d0 = datas[0]
    mujoco.mj_resetData(mm, d0)
    state0 = np.zeros(nstate)
    mujoco.mj_getState(mm, d0, state0, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    nstep = int(round(duration / 1e-3))
    chunk = min(100, runs)
    initial = np.tile(state0, (chunk, 1))
    out = np.zeros((chunk, nstep, nstate))
    rollout.rollout(mm, datas, initial[:2], nstep=10)                     # warm
    start = time.perf_counter()
    done = 0
    while done < runs:
        k = min(chunk, runs - done)
        rollout.rollout(mm, datas, initial[:k], nstep=nstep, state=out[:k])
        done += k
    return time.perf_counter() - start


def step_api(calls: int = 2000, repeats: int = 5) -> dict[str, float]:
    """``calls`` calls of ``Simulator.step(0.01)`` against one ``step(calls * 0.01)`` of the same simulator from
    the same reset (the same arithmetic): the difference is the Python cost of a call. Best of ``repeats``."""
    import uvms
    from uvms.control.registry import make_controller
    from uvms.sim.inputs import paper_torques

    model = uvms.load_model("paper")
    controller = make_controller("smc-ab", model, period=0.01)
    sim = uvms.Simulator(model, step=1e-3, controller=controller,
                         inputs=uvms.Inputs(joint_torques=paper_torques()))
    sim.step(0.05)
    many = one = float("inf")
    for _ in range(repeats):
        sim.reset()
        start = time.perf_counter()
        for _ in range(calls):
            sim.step(0.01)
        many = min(many, (time.perf_counter() - start) / calls)
        sim.reset()
        start = time.perf_counter()
        sim.step(calls * 0.01)
        one = min(one, (time.perf_counter() - start) / calls)
    return {"step_api_call_us": many * 1e6, "same_steps_in_one_call_us": one * 1e6,
            "python_overhead_us": (many - one) * 1e6}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=1000)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--json", metavar="FILE", default=None)
    args = parser.parse_args(argv)
    steps = args.runs * int(round(args.duration / 1e-3))
    uvms_s, batch = uvms_rollout(args.runs, args.duration, args.threads)
    mujoco_s = mujoco_rollout(args.runs, args.duration, args.threads)
    figures = {"runs": args.runs, "duration_s": args.duration, "threads": args.threads, "rk4_steps": steps,
               "uvms_rollout_s": uvms_s, "uvms_us_per_step": uvms_s / steps * 1e6,
               "uvms_complete": int(batch.complete.sum()), **step_api(),
               "python": sys.version.split()[0], "machine": platform.machine(), "load_average": os.getloadavg()}
    print(f"uvms.rollout: {args.runs} closed-loop paper runs (smc-ab, random model error and current), "
          f"{args.duration:g} s at 1 ms, {args.threads} threads: {uvms_s:.1f} s wall, "
          f"{figures['uvms_us_per_step']:.2f} us per RK4 step (controller included), "
          f"{figures['uvms_complete']} complete")
    if mujoco_s is not None:
        figures.update(mujoco_rollout_s=mujoco_s, mujoco_us_per_step=mujoco_s / steps * 1e6,
                       ratio_uvms_to_mujoco=uvms_s / mujoco_s)
        print(f"MuJoCo rollout: the same {steps} RK4 steps with its ellipsoid fluid model (open loop), "
              f"{args.threads} threads: {mujoco_s:.1f} s wall, {figures['mujoco_us_per_step']:.2f} us per step; "
              f"uvms / MuJoCo = {figures['ratio_uvms_to_mujoco']:.2f} (target <= 0.7)")
    print(f"step API: Simulator.step(0.01) (10 RK4 steps, smc-ab) {figures['step_api_call_us']:.1f} us per call; the "
          f"same steps in one call {figures['same_steps_in_one_call_us']:.1f} us; Python per call "
          f"{figures['python_overhead_us']:.1f} us")
    print(f"load average {figures['load_average'][0]:.2f}; python {figures['python']}")
    if args.json:
        Path(args.json).write_text(json.dumps(figures, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
