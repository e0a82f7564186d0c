"""Throughput of the Gymnasium station-keeping environment (issue 16: >= 10,000 environment steps per second on
the 2-core machine with the vectorised version, environment steps of 10 ms).

Run ``python benchmarks/bench_gym.py [--envs 64] [--steps 200] [--repeats 3] [--model bluerov2_heavy_alpha5]
[--action thrusters] [--json FILE]`` on a quiet machine (``uptime``: load < 1.5); the script prints the load.

Figures (medians over ``repeats`` batches of ``steps`` vector steps, after a warm-up batch; random actions
drawn uniformly in the action space; episodes reset automatically as in training):

* ``vector, T threads``: ``gymnasium.make_vec("uvms/StationKeeping-v0", num_envs=N, threads=T)`` steps,
  environment steps per second (N per vector step), for T = 1 (one compiled call over all N loops) and
  T = 2 (two threads, one compiled call over half the loops each).
* ``batch only, ...``: :meth:`uvms.sim.batch_stepper.BatchSimulator.advance` alone (the physics: ``dt / step``
  RK4 steps per environment step), one compiled call per thread block, and the alternative of a pool of
  threads calling :func:`uvms.sim.compiled_loop.advance_loop` once per loop (as :func:`uvms.rollout` does).
* ``single env``: ``gymnasium.make("uvms/StationKeeping-v0")`` (the step API, one environment).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import gymnasium
import numpy as np

import uvms.gym  # noqa: F401  (registers the environments)


def _median_rate(run, count: int, repeats: int) -> float:
    run()                                                    # warm-up (compilation, first episodes)
    rates = []
    for _ in range(repeats):
        tic = time.perf_counter()
        run()
        rates.append(count / (time.perf_counter() - tic))
    return statistics.median(rates)


def vector_rate(options: dict, envs: int, steps: int, repeats: int, threads: int) -> float:
    env = gymnasium.make_vec("uvms/StationKeeping-v0", num_envs=envs, threads=threads, **options)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    low, high = env.single_action_space.low, env.single_action_space.high
    actions = [rng.uniform(low, high, (envs, low.size)) for _ in range(steps)]

    def run():
        for a in actions:
            env.step(a)

    rate = _median_rate(run, envs * steps, repeats)
    env.close()
    return rate


def batch_rates(options: dict, envs: int, steps: int, repeats: int) -> dict[str, float]:
    from uvms.sim.batch_stepper import COMMAND
    from uvms.sim.compiled_loop import advance_loop

    env = gymnasium.make_vec("uvms/StationKeeping-v0", num_envs=envs, threads=2, **options)
    env.reset(seed=0)
    batch, task = env.unwrapped.batch, env.unwrapped.task
    commands, _ = task.commands(np.zeros((envs, env.single_action_space.shape[0])))
    out = {}
    for threads in (1, 2):
        batch_threads = batch.threads, batch._blocks, batch._pool
        if threads == 1:
            batch._pool, batch._blocks = None, [(0, envs)]

        def run():
            for _ in range(steps):
                batch.advance(task.substeps, commands, COMMAND)

        out[f"batch only, one compiled call per thread, {threads} thread(s) [env steps/s]"] = \
            _median_rate(run, envs * steps, repeats)
        batch.threads, batch._blocks, batch._pool = batch_threads
    pool = ThreadPoolExecutor(max_workers=2)

    def one(k):
        done = batch.done[k]
        batch.done[k] = advance_loop(batch._loops[k], done, done + task.substeps)[0]

    def run_pool():
        for _ in range(steps):
            list(pool.map(one, range(envs)))

    out["batch only, pool of 2 threads, one call per loop [env steps/s]"] = _median_rate(run_pool, envs * steps,
                                                                                          repeats)
    pool.shutdown()
    env.close()
    return out


def single_rate(options: dict, steps: int, repeats: int) -> float:
    env = gymnasium.make("uvms/StationKeeping-v0", **options)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    actions = [env.action_space.sample() for _ in range(steps)]
    del rng

    def run():
        for a in actions:
            _, _, terminated, truncated, _ = env.step(a)
            if terminated or truncated:
                env.reset()

    return _median_rate(run, steps, repeats)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--envs", type=int, default=64)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--model", default="bluerov2_heavy_alpha5")
    parser.add_argument("--action", default=None, choices=(None, "thrusters", "wrench"))
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    options = {"model": args.model}
    if args.action:
        options["action"] = args.action
    load_before = os.getloadavg()[0]
    figures: dict[str, float] = {}
    for threads in (1, 2):
        figures[f"vector, {args.envs} envs, {threads} thread(s) [env steps/s]"] = vector_rate(
            options, args.envs, args.steps, args.repeats, threads)
    figures.update(batch_rates(options, args.envs, args.steps, args.repeats))
    figures["single env (step API) [env steps/s]"] = single_rate(options, args.steps, args.repeats)
    load_after = os.getloadavg()[0]
    env = gymnasium.make("uvms/StationKeeping-v0", **options).unwrapped
    setup = (f"model {args.model}, action {env.task.action}, dt {env.task.dt:g} s, step {env.task.h:g} s "
             f"({env.task.substeps} RK4 steps per env step), arm '{env.task.config.arm}'")
    print(f"command: python benchmarks/bench_gym.py {' '.join(argv if argv is not None else sys.argv[1:])}")
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, load average "
          f"{load_before:.2f} before, {load_after:.2f} after")
    print(setup)
    width = max(len(k) for k in figures)
    for name, value in figures.items():
        print(f"{name:<{width}}  {value:10.0f}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"figures": figures, "setup": setup, "load": [load_before, load_after]}, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
