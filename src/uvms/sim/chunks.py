"""What both event loops share (:mod:`uvms.sim.compiled_loop`, :mod:`uvms.sim.loop`): the names of the logged
command, how a loop ended, and the driver that cuts a run into calls so that Ctrl-C and ``progress`` respond."""

from __future__ import annotations

import time as _time
from dataclasses import dataclass

COMMAND_NAMES = tuple(f"command_{a}" for a in ("K", "M", "N", "X", "Y", "Z"))
"""Logged commanded body wrench ``[K, M, N, X, Y, Z]`` (moments about and forces along the body axes)."""


@dataclass
class Outcome:
    """How a loop ended: steps done, the divergence code (0: none; else :func:`~uvms.sim.integrate.check_state`'s)
    and a reason when an adaptive solver gave up."""

    done: int = 0
    code: int = 0
    reason: str = ""


def run_in_chunks(plan, chunking, advance) -> Outcome:
    """Advance ``plan`` to its end (or divergence) by calls ``advance(start, stop) -> (done, code)`` that
    process the events in ``[start, stop)`` and integrate to ``stop`` (a later call resumes there): calls of
    ``chunking.first`` steps at first, then of ``chunking.next(steps, seconds, current)`` (sized from the last
    call's cost: :data:`uvms.sim.run.CHUNK_SECONDS`), with ``progress`` after each. The cut does not change the
    arithmetic: every call continues the same step grid (``t = k h``). ``advance.reason`` (if any) says why an
    adaptive solver gave up."""
    done, code, chunk = 0, 0, chunking.first
    n_total = plan.timing.n_total
    while done < n_total and code == 0:
        tic = _time.perf_counter()
        stop = min(n_total, done + chunk)
        new_done, code = advance(done, stop)
        chunk = chunking.next(stop - done, _time.perf_counter() - tic, chunk)
        done = new_done
        if code == 0:
            plan.report_progress(done)
    return Outcome(done, code, getattr(advance, "reason", "") if code else "")
