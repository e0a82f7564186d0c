"""Batched stepping: N step-API simulators (:class:`uvms.sim.stepper.Simulator`) advanced together, for users
who close N loops at once (vectorised reinforcement learning, sampling-based model-predictive control).

One :meth:`BatchSimulator.step` call writes every member's held inputs, advances every member's compiled loop
(:class:`uvms.sim.compiled_loop.Loop`) by the same duration and gathers the N state vectors, all inside one
compiled function (:func:`advance_members`, ``nogil``). The members are split into contiguous blocks, one
per thread, each block advanced by one call of that function from a thread pool (the threads run in parallel
because the compiled code releases the GIL). Each member continues its own step grid (step ``k`` of an episode
starts at ``t = k h``), so a member's trajectory is, to the last bit, the one its own :class:`Simulator` gives
for the same calls (tested). ``benchmarks/bench_gym.py`` compares one thread (one compiled call over all
members) with two.

The state vectors are laid out as :mod:`uvms.state` lays them out
(``[p(3) | quaternion(4, wxyz) | nu(6) | q(n) | qd(n) | actuator states]``, :class:`~uvms.state.StateLayout`).
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from typing import Sequence

import numpy as np
from numba import njit
from numba.typed import List

from uvms import checks
from uvms.sim.compiled_loop import advance_loop
from uvms.sim.options import Inputs
from uvms.sim.stepper import STEP_CHUNK, steps_of
from uvms.state import State

MAX_MEMBERS = 4096
"""Most members of one :class:`BatchSimulator` (each holds its own compiled plant and loop); more are refused
before any is built."""

NONE, COMMAND, BODY_WRENCH = 0, 1, 2
"""What :func:`advance_members` writes from its ``inputs`` matrix into each member's held inputs."""


@njit(cache=True, nogil=True)
def advance_members(loops, lo, hi, done, steps, inputs, kind, out, codes, active):
    """Members ``lo <= k < hi`` of ``loops`` with ``active[k]``: write ``inputs[k]`` into the held actuator
    commands (``kind`` :data:`COMMAND`) or the held external body wrench (:data:`BODY_WRENCH`), advance from global step
    ``done[k]`` by ``steps`` steps (:func:`~uvms.sim.compiled_loop.advance_loop`), and copy the state into
    ``out[k]``. ``done[k]`` and ``codes[k]`` (0, or the divergence code) are updated; a member whose code is
    already non-zero is left alone."""
    for k in range(lo, hi):
        if codes[k] != 0 or not active[k]:
            continue
        loop = loops[k]
        if kind == COMMAND:
            command = loop.held.command
            for j in range(inputs.shape[1]):
                command[j] = inputs[k, j]
        elif kind == BODY_WRENCH:
            wrench = loop.held.body_wrench
            for j in range(6):
                wrench[j] = inputs[k, j]
        new_done, code = advance_loop(loop, done[k], done[k] + steps)
        done[k] = new_done
        codes[k] = code
        x = loop.x
        for j in range(x.shape[0]):
            out[k, j] = x[j]


class BatchSimulator:
    """``n`` plants of one model (each optionally with a bundled controller and arm input) stepped together.

    Args:
        model: a :class:`~uvms.model.Model`.
        n: number of members.
        step: integration step [s] (RK4), shared.
        controller, actuation: as :class:`~uvms.sim.stepper.Simulator`'s (shared; a controller is copied per
            member by its ``compiled`` data, so members keep separate memories).
        inputs: one :class:`~uvms.sim.options.Inputs` for all members or a sequence of ``n`` (each member's own
            joint-torque input, current, ...).
        states: the members' initial states (a sequence of ``n``; default at rest at the origin).
        threads: threads that advance the members (default: the machine's cores, at most ``n``).

    Attributes read by callers: :attr:`x` (n, size) the members' state vectors after the last call,
    :attr:`codes` (n,) 0 or the divergence code of each member (a diverged member stops until it is reset).
    """

    def __init__(self, model, n: int, *, step: float = 1e-3, controller=None, actuation=None,
                 inputs: Inputs | Sequence[Inputs] | None = None, states: Sequence[State] | None = None,
                 threads: int | None = None) -> None:
        from uvms.sim.stepper import Simulator

        checks.model(model)
        self.model = model
        self.n = checks.count(n, "n", minimum=1)
        if self.n > MAX_MEMBERS:
            raise checks.fail("n", f"expected at most {MAX_MEMBERS} members, got {self.n}")
        if threads is not None:
            from uvms.sim.batch import MAX_THREADS

            if checks.count(threads, "threads", minimum=1) > MAX_THREADS:
                raise checks.fail("threads", f"expected at most {MAX_THREADS} threads, got {threads}")
        self.h = checks.number(step, "step", positive=True, unit="s")
        self._shared = (controller, actuation)
        per_member = self._per_member(inputs, "inputs", Inputs)
        initial = self._per_member(states, "states", State)
        self.members = [Simulator(model, initial[k], step=self.h, controller=controller, actuation=actuation,
                                  inputs=per_member[k]) for k in range(self.n)]
        first = self.members[0]
        self.size = first.x.size
        self.n_command = first.command_size
        self.has_controller = controller is not None
        self._loops = List([m.loop for m in self.members])
        self.done = np.zeros(self.n, dtype=np.int64)
        self.codes = np.zeros(self.n, dtype=np.int64)
        self.x = np.stack([m.x for m in self.members])
        self._all = np.ones(self.n, dtype=np.bool_)
        threads = (os.cpu_count() or 1) if threads is None else checks.count(threads, "threads", minimum=1)
        self.threads = min(threads, self.n)
        bounds = np.linspace(0, self.n, self.threads + 1).round().astype(int)
        self._blocks = [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:]) if b > a]
        self._pool = ThreadPoolExecutor(max_workers=self.threads) if self.threads > 1 else None

    def _per_member(self, value, name: str, kind) -> list:
        if value is None or isinstance(value, kind):
            return [value] * self.n
        if not isinstance(value, Sequence) or len(value) != self.n:
            raise checks.fail(name, f"expected one {kind.__name__} or a sequence of {self.n}, got {checks.show(value)}")
        return list(value)

    @property
    def time(self) -> np.ndarray:
        """(n,) each member's simulated time since its last reset [s]."""
        return self.done * self.h

    def reset(self, index: int, state: State | None = None, *, inputs: Inputs | None = None) -> np.ndarray:
        """Member ``index`` back to ``t = 0`` at ``state`` (default: its initial state), its controller's memory
        cleared; with ``inputs`` it is rebuilt with these inputs (e.g. a new current or arm trajectory).
        Returns its state vector."""
        from uvms.sim.stepper import Simulator

        k = checks.count(index, "index", minimum=0)
        if k >= self.n:
            raise checks.fail("index", f"expected a member index below {self.n}, got {index!r}")
        if inputs is not None:
            controller, actuation = self._shared
            self.members[k] = Simulator(self.model, state, step=self.h, controller=controller, actuation=actuation,
                                        inputs=inputs)
        else:
            self.members[k].reset(state)
        member = self.members[k]
        self._loops[k] = member.loop
        self.done[k] = 0
        self.codes[k] = 0
        self.x[k] = member.x
        return self.x[k]

    def step(self, duration: float, *, commands=None, body_wrenches=None) -> np.ndarray:
        """Advance every member (that has not diverged) ``duration`` seconds (a whole number of steps) with the
        given inputs held: ``commands`` (n, c) the actuator commands (the body wrench [K M N X Y Z] without
        thrusters; thruster commands with them; only without a controller), or ``body_wrenches`` (n, 6) an
        external body wrench [N m, N] (body axes). Returns :attr:`x` (n, size), the state vectors."""
        steps = steps_of(duration, self.h, int(self.done.max(initial=0)))
        kind, values = NONE, np.zeros((self.n, 0))
        if commands is not None and body_wrenches is not None:
            raise checks.fail("commands", "give commands or body_wrenches, not both")
        if commands is not None:
            if self.has_controller:
                raise checks.fail("commands", "the members have a controller: it sets the commands")
            kind, values = COMMAND, checks.matrix(commands, self.n, None, "commands", "")
            if values.shape[1] > self.n_command:
                raise checks.fail("commands", f"expected at most {self.n_command} commands per member, got "
                                              f"{values.shape[1]}")
        elif body_wrenches is not None:
            kind, values = BODY_WRENCH, checks.matrix(body_wrenches, self.n, 6, "body_wrenches", " [moment; force]")
        values = np.ascontiguousarray(values, dtype=np.float64)
        while steps > STEP_CHUNK:                 # bounded calls (the same step grid): Ctrl-C is seen between them
            self.advance(STEP_CHUNK, values, kind)
            steps -= STEP_CHUNK
        return self.advance(steps, values, kind)

    def advance(self, steps: int, values: np.ndarray, kind: int, active: np.ndarray | None = None) -> np.ndarray:
        """:meth:`step` without the checks: ``steps`` steps, ``values`` a C-contiguous float64 (n, c) matrix of
        inputs of ``kind`` (:data:`NONE`, :data:`COMMAND`, :data:`BODY_WRENCH`), only the members where the
        bool array ``active`` (n,) holds (default: all). For callers that checked their inputs once (the
        Gymnasium vector environment)."""
        args = (self._loops, self.done, steps, values, kind, self.x, self.codes,
                self._all if active is None else active)
        if self._pool is None:
            advance_members(self._loops, 0, self.n, *args[1:])
        else:
            futures = [self._pool.submit(advance_members, self._loops, lo, hi, *args[1:])
                       for lo, hi in self._blocks]
            for f in futures:
                f.result()
        if self.codes.any():                      # a member stopped: one that left a field with no outside says so
            from uvms.errors import UvmsInputError

            for k in np.flatnonzero(self.codes):
                try:
                    self.members[k].check_water()
                except UvmsInputError as error:
                    raise UvmsInputError(error.message, error.source, f"member {k}: {error.path}") from None
        return self.x

    def state(self, index: int) -> State:
        """Member ``index``'s state as a :class:`~uvms.state.State`."""
        from uvms.sim.integrate import unpack

        return unpack(self.x[index], self.model.n_joints)

    def close(self) -> None:
        """Stop the thread pool."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None
