"""Saying so while uvms's kernels compile at first use: one notice, then a line every few seconds.

Kernels compiled at install (:mod:`uvms.precompile`) load in milliseconds; whatever still compiles in a user's
process (sources edited, another numba or CPU than at install, a kernel specialisation the install did not
reach) takes seconds to minutes, during which nothing else happens. numba announces each compilation as a
``numba:compile`` event (``numba.core.event``); :class:`CompileWatch` listens to those of uvms's own functions and

- says :data:`NOTICE` once per process when the first one starts (what compiles and how long it may take);
- while compiling goes on, says :data:`PROGRESS` every :data:`HEARTBEAT_S` seconds (so no silence is longer),
  and when it ends after more than :data:`HEARTBEAT_S`, says :data:`DONE`.

Where it is said: through the :data:`writer` the CLI sets (:func:`uvms._cache.set_compile_notice`: stderr), else the
``logging`` logger ``uvms.compile`` at level WARNING (Python's last-resort handler prints it on stderr when the
application configured no logging; ``logging.getLogger("uvms.compile").setLevel(logging.ERROR)`` silences it).
"""

from __future__ import annotations

import logging
import threading
import time

HEARTBEAT_S = 8.0
"""Seconds between two progress lines while kernels compile (the issue's bound on silence is 10 s)."""

NOTICE = ("uvms: compiling {name} and the kernels it uses for this machine (first use only: up to {minutes}; "
          "they were not compiled at install, see docs/conventions.md, 'The first run')")
PROGRESS = "uvms: still compiling ({elapsed:.0f} s; {done} kernels done, now {name})"
DONE = "uvms: compiled {done} kernels in {elapsed:.0f} s (cached for later runs)"

FIRST_COMPILE_MINUTES = "2-3 minutes"
"""The cold-cache compile time measured on a 2-core machine: ``uvms run paper_case3_controlled`` 165 s,
``uvms run bluerov2_heavy_alpha5_hold6`` 149 s, a first ``uvms sweep --workers 2`` 168 s (warm: under 3 s)."""

logger = logging.getLogger("uvms.compile")

writer = None
"""Where the lines go: the CLI's writer (``uvms._cache.set_compile_notice``: stderr); ``None``: :data:`logger`."""
notice_said = False
"""Whether the first-compile notice was said in this process already (``uvms._cache.announce_compile``)."""


def _is_ours(dispatcher) -> bool:
    module = getattr(getattr(dispatcher, "py_func", None), "__module__", None) or ""
    return module == "uvms" or module.startswith("uvms.")


def _name(dispatcher) -> str:
    func = dispatcher.py_func
    return f"{func.__module__}.{func.__qualname__}"


class CompileWatch:
    """What is said while uvms's kernels compile (module docstring), fed by :func:`install`'s listener of
    numba's ``numba:compile`` events: :meth:`begin` and :meth:`end` of each compilation. Compilations nest (a
    kernel's callees compile inside it); a *session* runs from the first begin to the matching end."""

    def __init__(self, heartbeat_s: float = HEARTBEAT_S, clock=time.monotonic) -> None:
        self.heartbeat_s = heartbeat_s
        self.clock = clock
        self.depth = 0
        self.done = 0
        self.current = ""
        self.started = 0.0
        self.noticed = False
        self._lock = threading.Lock()
        self._stop: threading.Event | None = None

    def begin(self, name: str) -> None:
        with self._lock:
            self.current = name
            self.depth += 1
            if self.depth > 1:
                return
            self.started = self.clock()
            self.done = 0
            first = not self.noticed
            self.noticed = True
        if first and not notice_said:
            say(NOTICE.format(name=name, minutes=FIRST_COMPILE_MINUTES))
        if self.heartbeat_s > 0:
            self._stop = threading.Event()
            threading.Thread(target=self._beat, args=(self._stop,), name="uvms-compile-progress",
                             daemon=True).start()

    def end(self) -> None:
        with self._lock:
            self.depth = max(self.depth - 1, 0)
            self.done += 1
            if self.depth:
                return
            stop, self._stop = self._stop, None
            elapsed = self.clock() - self.started
        if stop is not None:
            stop.set()
        if elapsed > self.heartbeat_s:
            say(DONE.format(done=self.done, elapsed=elapsed))

    def _beat(self, stop: threading.Event) -> None:
        while not stop.wait(self.heartbeat_s):
            with self._lock:
                if self.depth == 0:
                    return
                line = PROGRESS.format(elapsed=self.clock() - self.started, done=self.done, name=self.current)
            say(line)


def say(text: str) -> None:
    """One line through the CLI's :data:`writer`, else the ``uvms.compile`` logger (module docstring)."""
    if writer is not None:
        writer(text)
    else:
        logger.warning(text)


_watch: CompileWatch | None = None


def install() -> CompileWatch:
    """Register one :class:`CompileWatch` with numba (once per process) and return it."""
    global _watch
    if _watch is None:
        from numba.core import event

        class Listener(event.Listener):
            def on_start(self, ev) -> None:
                dispatcher = ev.data.get("dispatcher") if isinstance(ev.data, dict) else None
                if dispatcher is not None and _is_ours(dispatcher):
                    watch.begin(_name(dispatcher))

            def on_end(self, ev) -> None:
                dispatcher = ev.data.get("dispatcher") if isinstance(ev.data, dict) else None
                if dispatcher is not None and _is_ours(dispatcher):
                    watch.end()

        watch = _watch = CompileWatch()
        event.register("numba:compile", Listener())
    return _watch
