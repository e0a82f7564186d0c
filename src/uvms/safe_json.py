"""Reading JSON files uvms wrote (``result.json``, ``.uvms-output.json``) safely: bounded before it is parsed.

A JSON file given to uvms may come from anyone (a copied run folder). Python's parser recurses once per level
of nesting, so ``[[[[...]]]]`` 100,000 deep is a ``RecursionError``, and a huge file is read whole into memory.
:func:`read_json` refuses, with one line naming the file, before parsing:

- a file larger than its ``max_bytes`` (the size is checked with ``stat`` and the read is capped);
- nesting deeper than :data:`MAX_DEPTH` levels (one flat pass over the brackets outside strings, no recursion).

The limits are documented in ``docs/conventions.md`` (the same idea as :mod:`uvms.safe_yaml` for YAML).
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any

from uvms.errors import UvmsInputError

MAX_DEPTH = 64
"""Deepest nesting of objects and arrays accepted (uvms writes at most 4 levels)."""

_STRING = re.compile(r'"(?:[^"\\]|\\.)*"', re.DOTALL)
_BRACKET = re.compile(r"[\[\]{}]")


def nesting_depth(text: str) -> int:
    """The deepest nesting of ``[`` and ``{`` in JSON ``text``, brackets inside strings not counted (a flat
    pass: any depth is measured without recursion)."""
    depth = deepest = 0
    for match in _BRACKET.finditer(_STRING.sub('""', text)):
        if match.group() in "[{":
            depth += 1
            deepest = max(deepest, depth)
        else:
            depth -= 1
    return deepest


def parse_json(text: str, source: str, *, max_depth: int = MAX_DEPTH) -> Any:
    """Parse JSON ``text`` nested at most ``max_depth`` deep; any problem is a one-line :class:`UvmsInputError`
    naming ``source``."""
    if nesting_depth(text) > max_depth:
        raise UvmsInputError(f"refused: nested more than {max_depth} levels deep, not a file uvms wrote", source)
    try:
        return json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise UvmsInputError(f"cannot read: {' '.join(str(exc).split())[:200]}", source) from None


def read_json(path: str | os.PathLike[str], *, max_bytes: int, max_depth: int = MAX_DEPTH) -> Any:
    """Read and parse a JSON file of at most ``max_bytes`` bytes and ``max_depth`` levels (see the module
    docstring); a missing, unreadable, oversized, deep or malformed file is a one-line :class:`UvmsInputError`."""
    path = Path(path)
    try:
        size = path.stat().st_size
        if not path.is_file():
            raise UvmsInputError("expected a JSON file, found something that is not a regular file", str(path))
        if size > max_bytes:
            raise UvmsInputError(f"refused: larger than {size_text(max_bytes)} ({size_text(size)}), not a file "
                                 "uvms wrote", str(path))
        with path.open("rb") as fh:
            raw = fh.read(max_bytes + 1)
    except OSError as exc:
        raise UvmsInputError(f"cannot read: {exc.strerror or exc}", str(path)) from None
    if len(raw) > max_bytes:   # grew since stat, or a special file
        raise UvmsInputError(f"refused: larger than {size_text(max_bytes)}, not a file uvms wrote", str(path))
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise UvmsInputError(f"cannot read: not UTF-8 text (byte {exc.start})", str(path)) from None
    return parse_json(text, str(path), max_depth=max_depth)


def size_text(n: int) -> str:
    """A byte count in words (``"16 MiB"``, ``"1.5 GiB"``)."""
    for unit, scale in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n} bytes"
