"""Batched rollouts: N closed-loop trajectories at once, in threads without the GIL (MuJoCo's ``rollout`` is
the anchor).

Each :class:`Trial` may differ from the others in its initial state, the plant's hydrodynamic scale factors
(model error), the current, the joint-torque input and the controller (its parameters); everything else is
shared. Every trial is prepared as :func:`uvms.simulate` prepares a run (:class:`~uvms.sim.plan.RunPlan`), then
the compiled loops (:func:`uvms.sim.compiled_loop.advance_loop`, ``nogil``) run in a pool of threads, and each
trajectory is labelled as ``simulate`` labels its run: a trial's result is the same as its ``simulate`` run, to
the last bit.
"""

from __future__ import annotations

import time as _time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Any, Callable, Sequence

import numpy as np

from uvms import checks
from uvms.sim.options import Inputs, grouped
from uvms.sim.plan import MAX_RECORDED_VALUES, RunPlan, Timing
from uvms.sim.result import Result
from uvms.state import State

MAX_THREADS = 1024
"""Most threads of one :func:`rollout` or :class:`~uvms.sim.batch_stepper.BatchSimulator` (each an operating
system thread with its own stack)."""

MAX_TRIALS = 10_000
"""Most trials of one :func:`rollout` (each holds its own compiled plant, controller and record); more are
refused before anything is built. Their records together are bounded too
(:data:`~uvms.sim.plan.MAX_RECORDED_VALUES`)."""


@dataclass(frozen=True)
class Trial:
    """One trajectory of a batch; ``None`` fields take the batch's shared value.

    Attributes:
        initial_state: the state at ``t = 0`` (default: at rest at the origin).
        hydro_scale: ``(added_mass, drag)`` factors of the *plant's* hydrodynamics (one number: both), e.g. a
            model error of the real vehicle against its description.
        current: the world current (as :class:`~uvms.sim.options.Inputs.current`).
        joint_torques: the joint-torque input (as :class:`~uvms.sim.options.Inputs.joint_torques`).
        controller: this trajectory's own controller (e.g. other parameters).
        joint_motion: this trajectory's prescribed joint motion (as :class:`~uvms.sim.options.Inputs.joint_motion`),
            e.g. one logged trial of an identification.
    """

    initial_state: State | None = None
    hydro_scale: float | tuple[float, float] | None = None
    current: Any = None
    joint_torques: Any = None
    controller: Any = None
    joint_motion: Any = None


@dataclass(frozen=True, eq=False)
class Batch:
    """The labelled result of :func:`rollout`: one :class:`~uvms.sim.result.Result` per trial, in order."""

    results: tuple[Result, ...]
    metadata: dict

    def __len__(self) -> int:
        return len(self.results)

    def __getitem__(self, k: int) -> Result:
        return self.results[k]

    def __repr__(self) -> str:
        done = sum(r.complete for r in self.results)
        return (f"Batch({len(self.results)} trajectories, {done} complete, "
                f"{self.metadata.get('wall_time_s', 0.0):.3g} s on {self.metadata.get('threads')} threads)")

    @property
    def complete(self) -> np.ndarray:
        """(N,) whether each trajectory ran to the end."""
        return np.array([r.complete for r in self.results])

    @property
    def time(self) -> np.ndarray:
        """(K,) the common sample times of complete trajectories [s]."""
        return self.results[0].time

    @property
    def states(self) -> np.ndarray:
        """(N, K, size) every trajectory's states (all must be complete, on one grid)."""
        if not self.complete.all():
            raise checks.fail("states", "expected complete trajectories only (see Batch.complete)")
        return np.stack([r.states for r in self.results])

    def summary(self):
        """One row per trajectory: :meth:`uvms.sim.result.Result.summary` as a pandas DataFrame."""
        import pandas as pd

        return pd.DataFrame([r.summary() for r in self.results])


def _trial_plan(model, trial: Trial, shared: tuple, timing: Timing) -> RunPlan:
    controller, actuation, inputs, integrator, recording = shared
    if not isinstance(trial, Trial):
        raise checks.fail("trials", f"expected uvms States or Trials, got {checks.show(trial)}")
    plant_model = model
    if trial.hydro_scale is not None:
        a, d = np.broadcast_to(np.asarray(trial.hydro_scale, dtype=float), (2,))
        plant_model = model.with_hydrodynamics_scaled(added_mass=float(a), drag=float(d))
    changes = {k: v for k, v in (("current", trial.current), ("joint_torques", trial.joint_torques),
                                 ("joint_motion", trial.joint_motion)) if v is not None}
    plan = RunPlan.build(plant_model, trial.initial_state, timing,
                         (trial.controller if trial.controller is not None else controller, actuation),
                         (replace(inputs, **changes), integrator, recording))
    return plan


def run_plans(plans: Sequence[RunPlan], *, threads: int, progress: Callable[[int, int], None] | None = None
              ) -> tuple[Result, ...]:
    """Run prepared plans (each wholly compilable: :func:`uvms.sim.compiled_loop.compilable`) in a pool of
    ``threads`` threads; the compiled loops release the GIL, so the threads run in parallel. Each result is
    what :func:`uvms.simulate` gives for the same plan."""
    from uvms.sim.chunks import Outcome
    from uvms.sim.record import result_of

    runs = [_runner(plan) for plan in plans]
    finished = [0]

    def one(k: int):
        tic = _time.perf_counter()
        done, code = runs[k][0](0, plans[k].timing.n_total)
        return Outcome(done, code), _time.perf_counter() - tic

    outcomes = []
    with ThreadPoolExecutor(max_workers=threads) as pool:
        for outcome in pool.map(one, range(len(plans))):
            outcomes.append(outcome)
            finished[0] += 1
            if progress is not None:
                progress(finished[0], len(plans))
    for k, plan in enumerate(plans):                 # a body left a field that has no outside: one line
        _check_water(plan, k)
    return tuple(result_of(plan, outcome, run[1](), _time.perf_counter() - seconds)
                 for plan, run, (outcome, seconds) in zip(plans, runs, outcomes))


def _check_water(plan: RunPlan, k: int) -> None:
    """:func:`uvms.hydro.flow.check_status` of trial ``k``'s water, its error naming the trial."""
    from uvms.errors import UvmsInputError
    from uvms.hydro.flow import check_status

    if plan.water is None:
        return
    try:
        check_status(plan.water)
    except UvmsInputError as error:
        raise UvmsInputError(error.message, error.source, f"trial {k}: {error.path}") from None


def _runner(plan):
    """``(advance(start, stop) -> (done, code), log())`` of a plan's compiled loop (``log()`` read after the
    run): the prescribed-motion loop (:mod:`uvms.sim.prescribed`) or the closed loop
    (:func:`uvms.sim.compiled_loop.advance_loop`)."""
    from uvms.sim.compiled_loop import CompiledLog, advance_loop, compiled_run

    if plan.motion is not None:
        from uvms.sim.prescribed import MotionLog, prescribed_advance

        return prescribed_advance(plan), lambda: MotionLog(plan.layout.n_joints)
    run = compiled_run(plan)
    return (lambda start, stop: advance_loop(run.loop, start, stop)), lambda: CompiledLog(run.log, run.signal_names)


def rollout(model, trials: Sequence[Trial | State], *, duration: float, step: float = 1e-3, controller=None,
            actuation=None, inputs: Inputs | None = None, **options) -> "Batch":
    """Run every trial (a :class:`Trial`, or just an initial :class:`~uvms.state.State`) for ``duration``
    seconds and return a labelled :class:`Batch`.

    Args:
        controller, actuation, inputs: shared by the trials (as :func:`uvms.simulate`'s).
        options: ``threads=`` (default: the machine's cores), ``progress=`` a callable ``progress(done, total)``
            called as trajectories finish, and :func:`uvms.simulate`'s recording keywords (``record_period=``
            ...). The controllers must be bundled ones (compiled); a Python controller runs with ``simulate``.
    """
    import os

    from uvms.sim.compiled_loop import compilable

    wall0 = _time.perf_counter()
    checks.model(model)
    timing = Timing.of(duration, step)
    threads = checks.count(options.pop("threads", os.cpu_count() or 1), "threads", minimum=1)
    if threads > MAX_THREADS:
        raise checks.fail("threads", f"expected at most {MAX_THREADS} threads, got {threads}")
    progress: Callable[[int, int], None] | None = options.pop("progress", None)
    checks.callable_or_none(progress, "progress", "progress(done, total)")
    if isinstance(trials, (State, Trial)) or not isinstance(trials, Sequence) or not len(trials):
        raise checks.fail("trials", f"expected a non-empty list of States or Trials, got {checks.show(trials)}")
    if len(trials) > MAX_TRIALS:
        raise checks.fail("trials", f"expected at most {MAX_TRIALS} trials in one rollout, got {len(trials)}; run "
                                    f"them in batches")
    trials = list(trials)
    shared = (controller, actuation, *grouped(inputs, "rk4", None, options))
    plans = [_trial_plan(model, Trial(initial_state=t) if isinstance(t, State) else t, shared, timing)
             for t in trials[:1]]
    rows, size = plans[0].samples.states.shape
    if len(trials) * rows * size > MAX_RECORDED_VALUES:
        raise checks.fail("trials", f"expected at most {MAX_RECORDED_VALUES:.0e} recorded values in all, found "
                                    f"{len(trials)} trials x {rows} rows x {size} state entries: fewer trials, or "
                                    f"record less often (a larger record_period)")
    plans += [_trial_plan(model, Trial(initial_state=t) if isinstance(t, State) else t, shared, timing)
              for t in trials[1:]]
    for k, plan in enumerate(plans):
        if not compilable(plan):
            raise checks.fail(f"trials[{k}]", "expected bundled controllers and arm inputs (compiled); run a Python "
                                              "controller or arm with uvms.simulate")
    results = run_plans(plans, threads=threads, progress=progress)
    return Batch(results, {"threads": threads, "trajectories": len(plans),
                           "wall_time_s": _time.perf_counter() - wall0})
