"""Batched closed-loop rollouts against MuJoCo's ``rollout``, side by side in one run, and the step API's cost.

``python benchmarks/bench_rollout.py [--runs 1000] [--duration 10] [--threads 2] [--only measured] [--json FILE]``

- **uvms**: ``uvms.rollout`` of ``--runs`` paper case-3 runs (``smc-ab`` every 10 ms, 1 ms RK4, the paper's
  joint torques), each with a random controller model error (``hydro_scale`` uniform in 0.3-1.7) and a random
  current (normal, 0.1 m/s per axis), recorded every 10 ms; ``--threads`` threads.
- **MuJoCo**: ``mujoco.rollout.rollout`` of the same number of RK4 steps (``--runs`` trajectories of
  ``duration / 1 ms`` steps) on the matching MJCF with its ellipsoid fluid model (``bench_dynamics.mjcf_from``),
  open loop, one ``MjData`` per thread, in chunks of 100 trajectories (its output holds every step).
- **step API**: ``uvms.Simulator.step(0.01)`` (10 RK4 steps) with ``smc-ab``, 2000 calls, against one call
  of the same 20 s from the same reset: the Python cost of a call.
- **measured feedback**: one 20 s paper case-3 run of ``smc-ab`` (compiled) on the true state, and the same run
  with ``feedback: measured`` from noisy sensors (an IMU at 200 Hz with datasheet noise, a pressure sensor at
  20 Hz, a DVL at 5 Hz with dropouts, encoders at 100 Hz; ``uvms.control.estimator``), both with the same sensors
  declared and recorded (every 5 ms, the IMU's period): the compiled loop alone and the whole ``simulate``,
  alternating, best of 15 each (issue 28's target: <= 1.3 x). ``--only measured`` runs this one alone.

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


def measured_sensors():
    """The noisy sensors of :func:`measured_feedback` (datasheet-like: a tactical-grade MEMS IMU, a 0.01 bar
    pressure sensor, a 1 cm/s DVL)."""
    from uvms.sensors import Dvl, Encoders, Imu, NoiseDensity, PressureSensor

    return [Imu(rate=200.0, gyro=NoiseDensity(white=3e-5, bias_instability=2e-5, random_walk=1e-6),
                accel=NoiseDensity(white=6e-4, bias_instability=4e-4), seed=1),
            PressureSensor(rate=20.0, noise=100.0, resolution=10.0, seed=2),
            Dvl(rate=5.0, noise=0.01, water_depth=30.0, max_altitude=50.0, dropout=0.05, seed=3),
            Encoders(rate=100.0, joints=("j1", "j2", "j3"), indices=(0, 1, 2), resolutions=(2 * np.pi / 4096,) * 3)]


def measured_feedback(duration: float = 20.0, repeats: int = 15) -> dict[str, float]:
    """The same compiled closed-loop run on the true state and fed noisy measurements (module docstring): the
    whole ``uvms.simulate`` (the sensors' tables sampled after the run in both), and the compiled loop alone
    (:func:`uvms.sim.compiled_loop.advance_loop` over the run, from a fresh plan each time). The two feedbacks
    alternate, best of ``repeats`` each, so that a change of the machine's load falls on both."""
    import uvms
    from uvms.control.registry import make_controller
    from uvms.sim.compiled_loop import advance_loop, compiled_run
    from uvms.sim.inputs import paper_torques
    from uvms.sim.run import prepare

    model = uvms.load_model("paper")
    sensors = measured_sensors()
    start = uvms.State.from_euler(model, position=[0.0, 0.0, 5.0])
    options = dict(step=1e-3, sensors=sensors, joint_torques=paper_torques(), record_period=0.005)
    feedbacks = ("true_state", "measured")

    def controller(feedback):
        return make_controller("smc-ab", model, period=0.01, parameters={"feedback": feedback})

    for feedback in feedbacks:
        uvms.simulate(model, start, duration=0.05, controller=controller(feedback), **options)     # compile
    whole = {f: float("inf") for f in feedbacks}
    loop = dict(whole)
    for _ in range(repeats):
        for feedback in feedbacks:
            t0 = time.perf_counter()
            result = uvms.simulate(model, start, duration=duration, controller=controller(feedback), **options)
            whole[feedback] = min(whole[feedback], time.perf_counter() - t0)
            assert result.complete
            plan = prepare(model, start, duration=duration, controller=controller(feedback), **options)
            run = compiled_run(plan)
            t0 = time.perf_counter()
            done, code = advance_loop(run.loop, 0, plan.timing.n_total)
            loop[feedback] = min(loop[feedback], time.perf_counter() - t0)
            assert code == 0 and done == plan.timing.n_total
    steps = int(round(duration / 1e-3))
    return {"true_state_s": whole["true_state"], "measured_s": whole["measured"],
            "ratio_measured_to_true": whole["measured"] / whole["true_state"],
            "loop_true_state_us_per_step": loop["true_state"] / steps * 1e6,
            "loop_measured_us_per_step": loop["measured"] / steps * 1e6,
            "loop_ratio_measured_to_true": loop["measured"] / loop["true_state"]}


def print_measured(figures: dict) -> None:
    print(f"measured feedback: smc-ab, 20 s paper run, 1 ms RK4, noisy IMU 200 Hz, pressure 20 Hz, DVL 5 Hz, "
          f"encoders 100 Hz: the compiled loop {figures['loop_true_state_us_per_step']:.2f} us per step on the true "
          f"state, {figures['loop_measured_us_per_step']:.2f} us fed measurements: ratio "
          f"{figures['loop_ratio_measured_to_true']:.3f} (target <= 1.3); the whole simulate (sensor tables "
          f"recorded in both) {figures['true_state_s']:.3f} s and {figures['measured_s']:.3f} s: ratio "
          f"{figures['ratio_measured_to_true']:.3f}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=1000)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--json", metavar="FILE", default=None)
    parser.add_argument("--only", choices=("measured",), default=None,
                        help="measured: only the measured-feedback comparison")
    args = parser.parse_args(argv)
    if args.only == "measured":
        figures = {**measured_feedback(), "python": sys.version.split()[0], "machine": platform.machine(),
                   "load_average": os.getloadavg()}
        print_measured(figures)
        print(f"load average {figures['load_average'][0]:.2f}; python {figures['python']}")
        if args.json:
            Path(args.json).write_text(json.dumps(figures, indent=2))
        return 0
    steps = args.runs * int(round(args.duration / 1e-3))
    uvms_s, batch = uvms_rollout(args.runs, args.duration, args.threads)
    mujoco_s = mujoco_rollout(args.runs, args.duration, args.threads)
    figures = {"runs": args.runs, "duration_s": args.duration, "threads": args.threads, "rk4_steps": steps,
               "uvms_rollout_s": uvms_s, "uvms_us_per_step": uvms_s / steps * 1e6,
               "uvms_complete": int(batch.complete.sum()), **step_api(), **measured_feedback(),
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
    print_measured(figures)
    print(f"load average {figures['load_average'][0]:.2f}; python {figures['python']}")
    if args.json:
        Path(args.json).write_text(json.dumps(figures, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
