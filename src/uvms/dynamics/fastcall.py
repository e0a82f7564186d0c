"""Calling a compiled kernel repeatedly from Python without numba's per-call type dispatch.

A numba dispatcher works out the types of its arguments on every call. For the model and workspace
(named tuples of ~20 arrays) that costs about 5 us, as much as a whole dynamics evaluation; the simulation
loop and the controllers call the same kernel with the same argument types thousands of times per run.
:func:`specialised` resolves the compiled specialisation once (compiling it if needed) and returns its entry
point; if numba's internals ever differ, it falls back to the dispatcher itself.
"""

from __future__ import annotations

from typing import Any, Callable


def specialised(dispatcher, *example_args: Any) -> Callable:
    """The compiled entry point of ``dispatcher`` for the types of ``example_args``.

    The returned callable must be given arguments of exactly those types (the same arrays' dtypes, layouts
    and read-only flags; Python ``int``, ``float`` and ``bool`` where the examples had them).
    """
    try:
        from numba import typeof

        signature = tuple(typeof(a) for a in example_args)
        result = dispatcher.overloads.get(signature)
        if result is None:
            dispatcher.compile(signature)
            result = dispatcher.overloads[signature]
        return result.entry_point
    except Exception:  # pragma: no cover - a numba without these internals: plain dispatch still works
        return dispatcher
